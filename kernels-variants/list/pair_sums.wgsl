// pair_sums.wgsl (thread mapping over the explicit lists): number_density, colour_gradient and
// acceleration with one thread per particle looping over its 64-slot list (the thesis's
// one-particle-per-thread layout, §6.4.2). Used by the `cached` kernel-value variants, which
// read W_ij and F'(r_ij) stored when the list was built (search/nbr_list.wgsl). The pair bodies
// and prefactors are those of common/pair_terms.wgsl (twins of `cpu::stages`).

#import common/pair_terms

@compute @workgroup_size(GROUP_THREADS)
fn number_density(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i >= params.n {
        return;
    }
    let kp = params_kernel(params);
    let xi = pos[i];
    var s = real2(real(0.0), real(0.0));
    for (var k = 0u; k < list_len(i); k++) {
        s += density_pair(i, kp, list_pair(i, xi, k));
    }
    density_out(i, s);
}

@compute @workgroup_size(GROUP_THREADS)
fn colour_gradient(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i >= params.n {
        return;
    }
    let kp = params_kernel(params);
    let xi = pos[i];
    let k = colour[i];
    var g = Grad2(real2(real(0.0), real(0.0)), real2(real(0.0), real(0.0)));
    if k >= 0 {
        for (var s = 0u; s < list_len(i); s++) {
            let t = grad_pair(k, kp, list_pair(i, xi, s));
            g.g0 += t.g0;
            g.g1 += t.g1;
        }
    }
    grad_out(i, g);
}

@compute @workgroup_size(GROUP_THREADS)
fn acceleration(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i >= params.n {
        return;
    }
    var sum = real2(real(0.0), real(0.0));
    if i < params.n_fluid {
        let kp = params_kernel(params);
        let c = acc_ctx(i);
        for (var k = 0u; k < list_len(i); k++) {
            sum += acc_pair(i, c, kp, list_pair(i, c.xi, k));
        }
    }
    acc_out(i, sum);
}
