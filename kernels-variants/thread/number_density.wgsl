// number_density.wgsl (thread mapping): σ_i = Σ_j W_ij over the neighbours (self and images
// included, T66) and the Holmes ratio χ_i = Σ_{same kind} W / σ_i when active. One thread per
// particle; the pair term and the output are common/pair_terms.wgsl's, as in every mapping.
// Twin of `cpu::stages::number_density`.

#import common/neighbours
#import common/pair_terms

@compute @workgroup_size(GROUP_THREADS)
fn number_density(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let kp = params_kernel(params);
    let xi = pos[i];
    var s = real2(real(0.0), real(0.0));
    var w = nb_spans(i, xi);
    while nb_span(&w) {
        for (var t = w.s0; t < w.s1; t++) {
            let nb = nb_at(w, t);
            if nb.hit {
                s += density_pair(i, kp, pair_of(xi, nb.j, nb.code, nb.xj));
            }
        }
    }
    density_out(i, s);
}
