// acceleration.wgsl (thread mapping): T65, pressure (T68) + viscous (T70 with the Morris or
// Holmes wall ghost velocity, §6.2–6.4) + surface (T76) + gravity + optional Lennard-Jones, one
// thread per particle (walls get zero). Twin of `cpu::stages::{acceleration, lennard_jones}`.

#import common/neighbours
#import pair
#import wall
#import common/pair_terms

@compute @workgroup_size(64)
fn acceleration(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n {
        return;
    }
    if i >= params.n_fluid {
        acc[i] = real2(real(0.0), real(0.0));
        return;
    }
    let kp = params_kernel(params);
    let visc = params_has(params, STAGE_VISCOSITY);
    let surf = params_has(params, STAGE_SURFACE);
    let xi = pos[i];
    let vi = vel[i];
    let inv_s2_i = real(1.0) / (sigma[i] * sigma[i]);
    let eta_i = params.eta[phase[i]];
    let pi_i = Sym2(pi[i].x, pi[i].y);
    let w = nearest_wall(xi);
    var d_i = real(0.0);
    if w != 0xFFFFFFFFu {
        d_i = wall_distance(w, xi);
    }
    var sum = real2(real(0.0), real(0.0));
    var it = nb_begin(i, xi);
    while nb_next(&it) {
        let j = it.j;
        let x_ij = xi - it.xj;
        let r2 = x_ij.x * x_ij.x + x_ij.y * x_ij.y;
        if r2 == real(0.0) {
            continue;
        }
        let r = sqrt(r2);
        let dwdr = kernel_dwdr(kp, r);
        let gw = grad_w_ij(dwdr, x_ij, r);
        let inv_s2_j = real(1.0) / (sigma[j] * sigma[j]);
        sum += pressure_acc_ij(pres[i], inv_s2_i, pres[j], inv_s2_j, gw);
        if visc {
            let fac = viscous_fac_ij(dwdr, r, kp.h);
            var eta_ij = eta_i;
            var v_ij = vi;
            if j < params.n_fluid {
                eta_ij = harmonic_viscosity(eta_i, params.eta[phase[j]]);
                v_ij = vi - image_vec(it.code, vel[j]);
            } else if w != 0xFFFFFFFFu {
                var beta = real(1.0);
                if params.wall_velocity == WALL_VELOCITY_HOLMES {
                    beta = holmes_beta(chi[i], chi[j], params.chi_floor, params.beta_max);
                } else {
                    beta = noslip_beta(d_i, -wall_distance(w, it.xj), params.beta_max, params.dx);
                }
                v_ij = wall_relative_velocity(vi, beta, params.wall_free_slip[w] != 0u, wall_normal(w));
            }
            sum += viscous_acc_ij(eta_ij, inv_s2_i, inv_s2_j, fac, v_ij);
        }
        if surf {
            let pi_j = image_sym(it.code, Sym2(pi[j].x, pi[j].y));
            sum += surface_acc_ij(pi_i, inv_s2_i, pi_j, inv_s2_j, gw);
        }
    }
    var a = sum / mass[i] + real2(params.gravity_x, params.gravity_y);
    if params_has(params, STAGE_LJ) {
        a += lennard_jones(xi);
    }
    acc[i] = a;
}
