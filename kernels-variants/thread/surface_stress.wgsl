// surface_stress.wgsl (thread mapping): T73–T75, Π_i = Σ_l σ^{kl} |g^{kl}| (I/2 − n̂n̂) over the
// gradient slots of the particle's colour; zero for uncoloured particles. Twin of
// `cpu::stages::surface_stress`.

#import common/bindings

@compute @workgroup_size(64)
fn surface_stress(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let k = colour[i];
    var t = Sym2(real(0.0), real(0.0));
    if k >= 0 {
        for (var slot = 0; slot < 2; slot++) {
            let l = select(slot + 1, slot, slot < k);
            if l < 3 {
                t = sym2_add(t, stress_tensor(grad_at(i, u32(slot)), params_sigma(params, k, l)));
            }
        }
    }
    pi[i] = real2(t.xx, t.xy);
}
