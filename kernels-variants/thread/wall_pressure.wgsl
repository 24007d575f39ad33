// wall_pressure.wgsl (thread mapping): R-wall pressure (Adami 2012), one thread per wall
// particle (`wall_pressure_at` of common/wall_pressure.wgsl, which the colour-gradient pass
// runs itself when fused). Twin of `cpu::stages::wall_pressure`.

#import common/wall_pressure

@compute @workgroup_size(GROUP_THREADS)
fn wall_pressure(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = params.n_fluid + linear_id(gid, nwg);
    if i < params.n {
        wall_pressure_at(i);
    }
}
