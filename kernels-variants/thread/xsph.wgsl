// xsph.wgsl (thread mapping): T51, ṽ_i = v_i + ε Σ_{j same fluid phase} 2m_j/(ρ_i+ρ_j)
// (v_j − v_i) W_ij, one thread per fluid particle. Twin of `cpu::stages::xsph`. Without XSPH the
// host copies v into ṽ instead.

#import common/neighbours
#import pair

@compute @workgroup_size(GROUP_THREADS)
fn xsph(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n_fluid {
        return;
    }
    let kp = params_kernel(params);
    let xi = pos[i];
    let vi = vel[i];
    var s = real2(real(0.0), real(0.0));
    var sp = nb_spans(i, xi);
    while nb_span(&sp) {
        for (var t = sp.s0; t < sp.s1; t++) {
            let nb = nb_at(sp, t);
            let j = nb.j;
            if !nb.hit || j >= params.n_fluid || phase[j] != phase[i] {
                continue;
            }
            let d = xi - nb.xj;
            let w = kernel_w(kp, sqrt(d.x * d.x + d.y * d.y));
            let v_ji = vel[j] * image_map_of(nb.code).sign - vi;
            s += xsph_ij(mass[j], rho[i], rho[j], v_ji, w);
        }
    }
    vt[i] = vi + s * params.xsph;
}
