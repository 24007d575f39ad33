// pair.wgsl: pair terms of the Hu–Adams momentum equation (docs/PHYSICS.md §4, §5.2, §5.5, §7.1;
// thesis T67–T71, T76, T51). WGSL twin of src/physics/pair.rs, same names and argument order.
// Each function is the contribution of one neighbour j to a sum over j for particle i; the caller
// applies the prefactor (1/m_i or σ_i). Conventions: x_ij = x_i − x_j, ∇_iW_ij = F'(r) x_ij / r.
// Library module: functions only (no bindings, no entry points).

#import stress

// ∇_i W_ij = F'(r) · x_ij / r (zero for r = 0).
fn grad_w_ij(dwdr: real, x_ij: real2, r: real) -> real2 {
    if r > real(0.0) {
        return x_ij * (dwdr / r);
    }
    return real2(real(0.0), real(0.0));
}

// 1/σ² of a particle's number density, the factor every pair term of (T68), (T70), (T71), (T76)
// takes from each side (once per particle: stored next to σ).
fn inv_sigma2(sigma: real) -> real {
    return real(1.0) / (sigma * sigma);
}

// Pressure term of (T68): −(p_i/σ_i² + p_j/σ_j²) ∇_iW_ij. Sum over j, then × 1/m_i.
fn pressure_acc_ij(p_i: real, inv_s2_i: real, p_j: real, inv_s2_j: real, grad_w: real2) -> real2 {
    return -(grad_w * (p_i * inv_s2_i + p_j * inv_s2_j));
}

// Harmonic mean of the dynamic viscosities, η̄ = 2η_iη_j/(η_i + η_j) (T69).
fn harmonic_viscosity(eta_i: real, eta_j: real) -> real {
    let s = eta_i + eta_j;
    if s > real(0.0) {
        return real(2.0) * eta_i * eta_j / s;
    }
    return real(0.0);
}

// Regularised F'(r)/r → r F'(r) / (r² + 0.01 h²) used by the viscous term (§4).
fn viscous_fac_ij(dwdr: real, r: real, h: real) -> real {
    return r * dwdr / (r * r + real(0.01) * h * h);
}

// Viscous term of (T70): η̄ (1/σ_i² + 1/σ_j²) (F'/r) v_ij. Sum over j, then × 1/m_i.
fn viscous_acc_ij(eta_ij: real, inv_s2_i: real, inv_s2_j: real, fac: real, v_ij: real2) -> real2 {
    return v_ij * (eta_ij * (inv_s2_i + inv_s2_j) * fac);
}

// Projected viscous term (docs/PHYSICS.md §4.1): viscous_acc_ij with v_ij replaced by
// (d + 2)(v_ij·x_ij) x_ij / r² (d = 2). Sum over j, then × 1/m_i. Zero for r² = 0.
fn viscous_projected_acc_ij(eta_ij: real, inv_s2_i: real, inv_s2_j: real, fac: real, v_ij: real2, x_ij: real2, r2: real) -> real2 {
    if r2 > real(0.0) {
        return x_ij * (eta_ij * (inv_s2_i + inv_s2_j) * fac * real(4.0) * dot(v_ij, x_ij) / r2);
    }
    return real2(real(0.0), real(0.0));
}

// Colour-gradient term of (T71): ∇_iW_ij / σ_j² for j of the other phase. Sum, then × σ_i.
fn colour_gradient_ij(inv_s2_j: real, grad_w: real2) -> real2 {
    return grad_w * inv_s2_j;
}

// Single-field colour-gradient term (Adami 2010 eq. 14 as PySPH's ColorGradientAdami, one colour
// field C = 1 liquid / 0 elsewhere): (C_i/σ_i² + C_j/σ_j²) ∇_iW_ij over every neighbour. × σ_i.
fn colour_gradient_single_ij(c_i: real, inv_s2_i: real, c_j: real, inv_s2_j: real, grad_w: real2) -> real2 {
    return grad_w * (c_i * inv_s2_i + c_j * inv_s2_j);
}

// Surface term of (T76): +(Π_i/σ_i² + Π_j/σ_j²) · ∇_iW_ij. Sum over j, then × 1/m_i.
fn surface_acc_ij(pi_i: Sym2, inv_s2_i: real, pi_j: Sym2, inv_s2_j: real, grad_w: real2) -> real2 {
    return sym2_mul_vec(sym2_add(sym2_scale(pi_i, inv_s2_i), sym2_scale(pi_j, inv_s2_j)), grad_w);
}

// XSPH term of (T51), same-phase fluid neighbours: 2 m_j/(ρ_i + ρ_j) (v_j − v_i) W_ij. × ε.
fn xsph_ij(m_j: real, rho_i: real, rho_j: real, v_ji: real2, w: real) -> real2 {
    return v_ji * (real(2.0) * m_j / (rho_i + rho_j) * w);
}
