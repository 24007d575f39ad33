// wall_typing.wgsl (thread mapping): Algorithm 2, one thread per wall particle
// (`wall_typing_at` of common/epilogues.wgsl, which the number-density pass runs itself when
// fused). Twin of `cpu::stages::wall_typing`.

#import common/epilogues

@compute @workgroup_size(GROUP_THREADS)
fn wall_typing(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = params.n_fluid + linear_id(gid, nwg);
    if i < params.n {
        wall_typing_at(i);
    }
}
