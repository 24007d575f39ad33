// wall_pressure.wgsl (shared): the R-wall pressure (Adami 2012) of wall particle i,
// p_w = [Σ_f p_f W + g·Σ_f ρ_f (r_w − r_f) W] / Σ_f W, p_b of the wall phase without fluid
// neighbours. Run by thread/wall_pressure.wgsl (the unfused stage) or at the end of the
// colour-gradient pass (the stage table's epilogue: it reads ρ and p of the pass before and
// writes the walls' p, which nothing in that pass reads). Twin of `cpu::stages::wall_pressure`.

#import common/neighbours

fn wall_pressure_at(i: u32) {
    let kp = params_kernel(params);
    let g = real2(params.gravity_x, params.gravity_y);
    let xi = pos[i];
    var num = real(0.0);
    var den = real(0.0);
    var sp = nb_spans(i, xi);
    while nb_span(&sp) {
        for (var t = sp.s0; t < sp.s1; t++) {
            let nb = nb_at(sp, t);
            let j = nb.j;
            if !nb.hit || j >= params.n_fluid {
                continue;
            }
            let d = xi - nb.xj;
            let w = kernel_w(kp, sqrt(d.x * d.x + d.y * d.y));
            num += (pres[j] + (g.x * d.x + g.y * d.y) * rho[j]) * w;
            den += w;
        }
    }
    if den > real(0.0) {
        pres[i] = num / den;
    } else {
        pres[i] = params.p_b[params.wall_phase];
    }
}
