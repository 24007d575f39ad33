// colour_gradient.wgsl (thread mapping): T71, for each coloured particle
// σ_i Σ_{j of colour l} ∇_iW_ij/σ_j² towards every other colour l with σ^{kl} > 0, by slot
// (grad0[i], grad1[i]). The pair term and the output are common/pair_terms.wgsl's, as in every
// mapping. Twin of `cpu::stages::colour_gradient`.

#import common/neighbours
#import common/pair_terms

@compute @workgroup_size(GROUP_THREADS)
fn colour_gradient(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let kp = params_kernel(params);
    let k = colour[i];
    var g = Grad2(real2(real(0.0), real(0.0)), real2(real(0.0), real(0.0)));
    if k >= 0 {
        let xi = pos[i];
        var w = nb_spans(i, xi);
        while nb_span(&w) {
            for (var t = w.s0; t < w.s1; t++) {
                let nb = nb_at(w, t);
                if nb.hit {
                    let q = grad_pair(k, kp, pair_of(xi, nb.j, nb.code, nb.xj));
                    g.g0 += q.g0;
                    g.g1 += q.g1;
                }
            }
        }
    }
    grad_out(i, g);
}
