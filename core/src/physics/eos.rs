//! Equation of state (docs/PHYSICS.md §3, thesis T34–T36). CPU twin of `shaders/eos.wgsl`.

use crate::real::Real;

/// Tait / Batchelor pressure `p = B[(ρ/ρ0)^γ − 1] + p_b` with stiffness `B = ρ0 c0²/γ` (T36).
#[inline(always)]
pub fn eos_pressure<T: Real>(rho: T, rho0: T, stiffness: T, gamma: T, p_b: T) -> T {
    stiffness * ((rho / rho0).powf(gamma) - T::one()) + p_b
}

/// Stiffness `B = ρ0 c0² / γ` (T35–T36), computed in f64.
pub fn eos_stiffness(rho0: f64, c0: f64, gamma: f64) -> f64 {
    rho0 * c0 * c0 / gamma
}
