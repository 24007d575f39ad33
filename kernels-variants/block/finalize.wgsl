// finalize.wgsl (block mappings): one thread per particle turns the accumulated sums of
// common/accum.wgsl into the fields, applying the per-particle prefactors of
// common/pair_terms.wgsl (χ = same/σ; σ_i × gradient; 1/m_i, gravity, Lennard-Jones); once
// per list chunk, as the accumulator is split alike (common/accum.wgsl).

#import common/pair_terms
#import common/accum

@compute @workgroup_size(GROUP_THREADS)
fn finalize_density(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i < params.n {
        density_out(i, real2(acc_get(i, 0u, F_DENSITY), acc_get(i, 1u, F_DENSITY)));
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn finalize_gradient(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i < params.n {
        let g0 = real2(acc_get(i, 0u, F_GRAD), acc_get(i, 1u, F_GRAD));
        let g1 = real2(acc_get(i, 2u, F_GRAD), acc_get(i, 3u, F_GRAD));
        grad_out(i, Grad2(g0, g1));
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn finalize_acceleration(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i < params.n {
        acc_out(i, real2(acc_get(i, 0u, F_ACC), acc_get(i, 1u, F_ACC)));
    }
}
