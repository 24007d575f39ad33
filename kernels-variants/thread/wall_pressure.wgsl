// wall_pressure.wgsl (thread mapping): R-wall pressure (Adami 2012), one thread per wall
// particle: p_w = [Σ_f p_f W + g·Σ_f ρ_f (r_w − r_f) W] / Σ_f W, p_b of the wall phase without
// fluid neighbours. Twin of `cpu::stages::wall_pressure`.

#import common/neighbours

@compute @workgroup_size(GROUP_THREADS)
fn wall_pressure(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = params.n_fluid + linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let kp = params_kernel(params);
    let g = real2(params.gravity_x, params.gravity_y);
    let xi = pos[i];
    var num = real(0.0);
    var den = real(0.0);
    var it = nb_begin(i, xi);
    while nb_next(&it) {
        let j = it.j;
        if j >= params.n_fluid {
            continue;
        }
        let d = xi - it.xj;
        let w = kernel_w(kp, sqrt(d.x * d.x + d.y * d.y));
        num += (pres[j] + (g.x * d.x + g.y * d.y) * rho[j]) * w;
        den += w;
    }
    if den > real(0.0) {
        pres[i] = num / den;
    } else {
        pres[i] = params.p_b[params.wall_phase];
    }
}
