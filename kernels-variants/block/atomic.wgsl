// atomic.wgsl (block-atomic mapping, thesis §6.4.1.1, Fig. 6.4): every thread of the 16 × 32
// layout (common/block_layout.wgsl) computes the term of one neighbour slot and adds it to its
// particle's sums atomically (common/accum.wgsl: CAS, native f32 or fixed point). The
// finalize kernels (block/finalize.wgsl) turn the sums into the fields.

#import common/block_layout

@compute @workgroup_size(16, 32)
fn number_density(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let i = block_particle(wg, nwg, lid);
    let t = block_density(i, block_k(wg, lid));
    if i < params.n {
        acc_add(i, 0u, F_DENSITY, t.x);
        acc_add(i, 1u, F_DENSITY, t.y);
    }
}

@compute @workgroup_size(16, 32)
fn colour_gradient(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let i = block_particle(wg, nwg, lid);
    let t = block_gradient(i, block_k(wg, lid));
    if i < params.n {
        acc_add(i, 0u, F_GRAD, t.g0.x);
        acc_add(i, 1u, F_GRAD, t.g0.y);
        acc_add(i, 2u, F_GRAD, t.g1.x);
        acc_add(i, 3u, F_GRAD, t.g1.y);
    }
}

@compute @workgroup_size(16, 32)
fn acceleration(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let i = block_particle(wg, nwg, lid);
    let t = block_acceleration(i, block_k(wg, lid));
    if i < params.n {
        acc_add(i, 0u, F_ACC, t.x);
        acc_add(i, 1u, F_ACC, t.y);
    }
}
