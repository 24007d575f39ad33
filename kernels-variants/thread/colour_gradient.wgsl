// colour_gradient.wgsl (thread mapping): T71, for each coloured particle
// σ_i Σ_{j of colour l} ∇_iW_ij/σ_j² towards every other colour l with σ^{kl} > 0, by slot
// (grad[2i + slot]). Twin of `cpu::stages::colour_gradient`.

#import common/neighbours
#import pair

@compute @workgroup_size(64)
fn colour_gradient(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n {
        return;
    }
    let kp = params_kernel(params);
    let k = colour[i];
    var g0 = real2(real(0.0), real(0.0));
    var g1 = g0;
    if k >= 0 {
        let xi = pos[i];
        var it = nb_begin(i, xi);
        while nb_next(&it) {
            let j = it.j;
            let l = colour[j];
            if l < 0 || l == k || params_sigma(params, k, l) == real(0.0) {
                continue;
            }
            let x_ij = xi - it.xj;
            let r = sqrt(x_ij.x * x_ij.x + x_ij.y * x_ij.y);
            let gw = grad_w_ij(kernel_dwdr(kp, r), x_ij, r);
            let t = colour_gradient_ij(real(1.0) / (sigma[j] * sigma[j]), gw);
            if l < k {
                if l == 0 { g0 += t; } else { g1 += t; }
            } else {
                if l == 1 { g0 += t; } else { g1 += t; }
            }
        }
    }
    grad[2u * i] = g0 * sigma[i];
    grad[2u * i + 1u] = g1 * sigma[i];
}
