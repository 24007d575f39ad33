//! Pair terms of the Hu–Adams momentum equation (docs/PHYSICS.md §4, §5.2, §5.5, §7.1).
//! CPU twin of `shaders/pair.wgsl`. Every function returns the contribution of one neighbour j
//! to a sum over j for particle i; the caller multiplies the sum by the prefactor named in the
//! doc (1/m_i or σ_i). Conventions: `x_ij = x_i − x_j`, `∇_iW_ij = F'(r_ij) x_ij / r_ij` points
//! from i towards j (F' ≤ 0).

use crate::real::{Real, Sym2, V2};

/// `∇_i W_ij = F'(r) · x_ij / r` (zero for r = 0).
#[inline(always)]
pub fn grad_w_ij<T: Real>(dwdr: T, x_ij: V2<T>, r: T) -> V2<T> {
    if r > T::zero() {
        x_ij * (dwdr / r)
    } else {
        V2::zero()
    }
}

/// `1/σ²` of a particle's number density, the factor every pair term of (T68), (T70), (T71),
/// (T76) takes from each side (once per particle: the GPU stores it next to σ).
#[inline(always)]
pub fn inv_sigma2<T: Real>(sigma: T) -> T {
    T::one() / (sigma * sigma)
}

/// Pressure term of (T68): `−(p_i/σ_i² + p_j/σ_j²) ∇_iW_ij`. Sum over j, then × 1/m_i.
#[inline(always)]
pub fn pressure_acc_ij<T: Real>(p_i: T, inv_s2_i: T, p_j: T, inv_s2_j: T, grad_w: V2<T>) -> V2<T> {
    -(grad_w * (p_i * inv_s2_i + p_j * inv_s2_j))
}

/// Harmonic mean of the dynamic viscosities, `η̄ = 2η_iη_j/(η_i + η_j)` (T69).
#[inline(always)]
pub fn harmonic_viscosity<T: Real>(eta_i: T, eta_j: T) -> T {
    let s = eta_i + eta_j;
    if s > T::zero() {
        T::c(2.0) * eta_i * eta_j / s
    } else {
        T::zero()
    }
}

/// Regularised `F'(r)/r → r F'(r) / (r² + 0.01 h²)` used by the viscous term (§4).
#[inline(always)]
pub fn viscous_fac_ij<T: Real>(dwdr: T, r: T, h: T) -> T {
    r * dwdr / (r * r + T::c(0.01) * h * h)
}

/// Viscous term of (T70): `η̄ (1/σ_i² + 1/σ_j²) (F'/r) v_ij`. Sum over j, then × 1/m_i.
/// With F' < 0 it decelerates i relative to j.
#[inline(always)]
pub fn viscous_acc_ij<T: Real>(eta_ij: T, inv_s2_i: T, inv_s2_j: T, fac: T, v_ij: V2<T>) -> V2<T> {
    v_ij * (eta_ij * (inv_s2_i + inv_s2_j) * fac)
}

/// Projected viscous term (docs/PHYSICS.md §4.1): [`viscous_acc_ij`] with `v_ij` replaced by
/// `(d + 2)(v_ij·x_ij) x_ij / r²` (d = 2). Same bulk Laplacian for a divergence-free field; its
/// pair power is `2η e:e`, T70's `η|∇v|²`. Sum over j, then × 1/m_i. Zero for r² = 0.
#[inline(always)]
pub fn viscous_projected_acc_ij<T: Real>(
    eta_ij: T,
    inv_s2_i: T,
    inv_s2_j: T,
    fac: T,
    v_ij: V2<T>,
    x_ij: V2<T>,
    r2: T,
) -> V2<T> {
    if r2 > T::zero() {
        x_ij * (eta_ij * (inv_s2_i + inv_s2_j) * fac * T::c(4.0) * v_ij.dot(x_ij) / r2)
    } else {
        V2::zero()
    }
}

/// Colour-gradient term of (T71): `∇_iW_ij / σ_j²` for j of the other phase. Sum, then × σ_i.
#[inline(always)]
pub fn colour_gradient_ij<T: Real>(inv_s2_j: T, grad_w: V2<T>) -> V2<T> {
    grad_w * inv_s2_j
}

/// Single-field colour-gradient term (Adami, Hu & Adams 2010 eq. 14 as PySPH's
/// `ColorGradientAdami` sums it, for one colour field C = 1 in the liquid, 0 elsewhere):
/// `(C_i/σ_i² + C_j/σ_j²) ∇_iW_ij` over every neighbour j. Sum, then × σ_i. Used instead of
/// [`colour_gradient_ij`] when a scene sets `surface_tension.colour_gradient = "single-field"`.
#[inline(always)]
pub fn colour_gradient_single_ij<T: Real>(c_i: T, inv_s2_i: T, c_j: T, inv_s2_j: T, grad_w: V2<T>) -> V2<T> {
    grad_w * (c_i * inv_s2_i + c_j * inv_s2_j)
}

/// Surface term of (T76): `+(Π_i/σ_i² + Π_j/σ_j²) · ∇_iW_ij`. Sum over j, then × 1/m_i.
#[inline(always)]
pub fn surface_acc_ij<T: Real>(pi_i: Sym2<T>, inv_s2_i: T, pi_j: Sym2<T>, inv_s2_j: T, grad_w: V2<T>) -> V2<T> {
    (pi_i * inv_s2_i + pi_j * inv_s2_j).mul_vec(grad_w)
}

/// The surface term (T76) of an isotropic stress `sI` (the tangential form's part,
/// docs/PHYSICS.md §5.3): `+(s_i/σ_i² + s_j/σ_j²) ∇_iW_ij`, the pressure term (T68) of −s. Sum
/// over j, then × 1/m_i. CPU only: the WGSL stages carry the traceless tensor alone.
#[inline(always)]
pub fn surface_isotropic_acc_ij<T: Real>(s_i: T, inv_s2_i: T, s_j: T, inv_s2_j: T, grad_w: V2<T>) -> V2<T> {
    -pressure_acc_ij(s_i, inv_s2_i, s_j, inv_s2_j, grad_w)
}

/// Artificial-stress term of the transport-velocity formulation (Adami, Hu & Adams 2013,
/// eq. 12; docs/PHYSICS.md §7.5): `(1/σ_i² + 1/σ_j²) ½(A_i + A_j)·∇_iW_ij`, given
/// `A_k·∇_iW_ij = ρ_k v_k ((ṽ_k − v_k)·∇_iW_ij)` for both particles. Sum over fluid j, then
/// × 1/m_i. CPU only: the transport-velocity formulation has no WGSL path.
#[inline(always)]
pub fn artificial_stress_acc_ij<T: Real>(a_i_gw: V2<T>, inv_s2_i: T, a_j_gw: V2<T>, inv_s2_j: T) -> V2<T> {
    (a_i_gw + a_j_gw) * (T::c(0.5) * (inv_s2_i + inv_s2_j))
}

/// XSPH term of (T51) restricted to same-phase fluid neighbours:
/// `2 m_j/(ρ_i + ρ_j) (v_j − v_i) W_ij`. Sum over j, then × ε.
#[inline(always)]
pub fn xsph_ij<T: Real>(m_j: T, rho_i: T, rho_j: T, v_ji: V2<T>, w: T) -> V2<T> {
    v_ji * (T::c(2.0) * m_j / (rho_i + rho_j) * w)
}
