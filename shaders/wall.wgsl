// wall.wgsl: wall boundary physics (docs/PHYSICS.md §6, thesis T44–T49): Morris no-slip ghost
// velocity with its cap, the free-slip variant, the Holmes state-ratio option and Monaghan's
// Lennard-Jones repulsion. WGSL twin of src/physics/wall.rs, same names and argument order.
// Library module: functions only (no bindings, no entry points).

// Morris factor β = min(β_max, 1 + d_j/d_i) (T45); d_j ≤ 0 gives 1; d_i floored at 1e-6 Δx.
fn noslip_beta(d_i: real, d_j: real, beta_max: real, dx: real) -> real {
    if d_j <= real(0.0) {
        return real(1.0);
    }
    let di = max(d_i, real(1e-6) * dx);
    return min(real(1.0) + d_j / di, beta_max);
}

// v_ij = v_i − v_ghost: β v_i (no-slip) or β (v_i·n̂_w) n̂_w (free-slip, §6.3).
fn wall_relative_velocity(v_i: real2, beta: real, free_slip: bool, n_w: real2) -> real2 {
    if free_slip {
        return n_w * ((v_i.x * n_w.x + v_i.y * n_w.y) * beta);
    }
    return v_i * beta;
}

// Holmes variant (T49 reconstruction): β = min(β_max, 1 + (χ_j − ½)/max(χ_i − ½, χ_floor));
// χ_j ≤ ½ gives 1.
fn holmes_beta(chi_i: real, chi_j: real, chi_floor: real, beta_max: real) -> real {
    let dj = chi_j - real(0.5);
    if dj <= real(0.0) {
        return real(1.0);
    }
    let di = max(chi_i - real(0.5), chi_floor);
    return min(real(1.0) + dj / di, beta_max);
}

// Lennard-Jones repulsion from one boundary point (T44), acceleration on i:
// D[(r0/r)^12 − (r0/r)^4] r_ib/r² for 0 < r < r0, else 0.
fn lj_wall_acc(r_ib: real2, r0: real, d: real) -> real2 {
    let r2 = r_ib.x * r_ib.x + r_ib.y * r_ib.y;
    if r2 >= r0 * r0 || r2 <= real(0.0) {
        return real2(real(0.0), real(0.0));
    }
    let q2 = r0 * r0 / r2;
    let q4 = q2 * q2;
    let q12 = q4 * q4 * q4;
    return r_ib * (d * (q12 - q4) / r2);
}
