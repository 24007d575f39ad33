// acceleration.wgsl (thread mapping): T65, pressure (T68) + viscous (T70 with the Morris or
// Holmes wall ghost velocity, §6.2–6.4) + surface (T76) + gravity + optional Lennard-Jones, one
// thread per particle (walls get zero). The pair term and the output are
// common/pair_terms.wgsl's, as in every mapping. Twin of `cpu::stages::{acceleration,
// lennard_jones}`.

#import common/neighbours
#import common/pair_terms

@compute @workgroup_size(GROUP_THREADS)
fn acceleration(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    var sum = real2(real(0.0), real(0.0));
    if i < params.n_fluid {
        let kp = params_kernel(params);
        let c = acc_ctx(i);
        var w = nb_spans(i, c.xi);
        while nb_span(&w) {
            for (var t = w.s0; t < w.s1; t++) {
                let nb = nb_at(w, t);
                if nb.hit {
                    sum += acc_pair(i, c, kp, pair_of(c.xi, nb.j, nb.code, nb.xj));
                }
            }
        }
    }
    acc_out(i, sum);
}
