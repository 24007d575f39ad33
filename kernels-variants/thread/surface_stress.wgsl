// surface_stress.wgsl (thread mapping): T73–T75, the surface stress tensor Π of every particle
// (common/epilogues.wgsl, which the colour-gradient pass runs itself when fused). Twin of
// `cpu::stages::surface_stress`.

#import common/epilogues

@compute @workgroup_size(GROUP_THREADS)
fn surface_stress(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i < params.n {
        surface_stress_at(i);
    }
}
