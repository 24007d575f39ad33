// normal_correction.wgsl (thread mapping): Algorithm 1, one thread per particle, in place on
// grad slot 0 (common/epilogues.wgsl, which the colour-gradient pass runs itself when fused);
// nothing changes without contact points. Twin of `cpu::stages::normal_correction`.

#import common/epilogues

@compute @workgroup_size(GROUP_THREADS)
fn normal_correction(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i < params.n {
        normal_correction_at(i);
    }
}
