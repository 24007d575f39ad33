//! Prosperetti's initial-value solution for a small-amplitude standing capillary wave between
//! two viscous fluids of equal kinematic viscosity (Phys. Fluids 24, 1981, 1217–1223; the form
//! written out in docs/PHYSICS.md §14). The interface starts at rest as `a0 cos(kx)`; with
//! `β = ρ1ρ2/(ρ1 + ρ2)²`, `ω0² = σk³/(ρ1 + ρ2)` and `z_i` the roots of
//!
//! ```text
//! z⁴ − 4β(k²ν)^{1/2} z³ + 2(1 − 6β)k²ν z² + 4(1 − 3β)(k²ν)^{3/2} z + (1 − 4β)ν²k⁴ + ω0² = 0,
//! ```
//!
//! ```text
//! a(t)/a0 = 4(1 − 4β)ν²k⁴/(8(1 − 4β)ν²k⁴ + ω0²) · erfc((νk²t)^{1/2})
//!         + Σ_i z_i/Z_i · ω0²/(z_i² − νk²) · exp((z_i² − νk²)t) erfc(z_i t^{1/2}),
//! Z_i = Π_{j≠i} (z_j − z_i).
//! ```
//!
//! `exp(z²t) erfc(z√t)` is evaluated as one function ([`complex::exp_sq_erfc`]).

use super::complex::{self, C};
use std::f64::consts::PI;

/// Bad input to the capillary-wave solution.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum WaveError {
    #[error("density `{0}` must be finite and >= 0, with the two summing to > 0, got {1}")]
    Density(&'static str, f64),
    #[error("kinematic viscosity `nu` must be finite and >= 0, got {0}")]
    Viscosity(f64),
    #[error("surface tension `sigma` must be finite and > 0, got {0}")]
    Sigma(f64),
    #[error("`wavelength` must be finite and > 0, got {0}")]
    Wavelength(f64),
    #[error(
        "the characteristic quartic has a repeated root (critically damped wave): the solution's form does not apply"
    )]
    RepeatedRoot,
}

/// The physical set-up: lower and upper densities, the common kinematic viscosity, σ and λ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveParams {
    /// ρ1, the lower fluid.
    pub rho_lower: f64,
    /// ρ2, the upper fluid (0: a free surface).
    pub rho_upper: f64,
    /// ν, the same in both fluids.
    pub nu: f64,
    /// σ.
    pub sigma: f64,
    /// λ = 2π/k.
    pub wavelength: f64,
}

impl WaveParams {
    /// Wavenumber k = 2π/λ.
    pub fn k(&self) -> f64 {
        2.0 * PI / self.wavelength
    }
    /// β = ρ1ρ2/(ρ1 + ρ2)² (1/4 for equal densities, 0 for a free surface).
    pub fn beta(&self) -> f64 {
        self.rho_lower * self.rho_upper / (self.rho_lower + self.rho_upper).powi(2)
    }
    /// The inviscid angular frequency ω0 = (σk³/(ρ1 + ρ2))^{1/2}.
    pub fn omega0(&self) -> f64 {
        (self.sigma * self.k().powi(3) / (self.rho_lower + self.rho_upper)).sqrt()
    }
    /// The inviscid period 2π/ω0.
    pub fn period0(&self) -> f64 {
        2.0 * PI / self.omega0()
    }
    /// The Laplace number σ(ρ1 + ρ2)λ/(2 μ̄²) with μ̄ = ν(ρ1 + ρ2)/2 (σρλ/μ² for equal fluids).
    pub fn laplace(&self) -> f64 {
        let rho = 0.5 * (self.rho_lower + self.rho_upper);
        self.sigma * rho * self.wavelength / (self.nu * rho).powi(2)
    }

    fn check(&self) -> Result<(), WaveError> {
        let ok = |v: f64| v.is_finite() && v >= 0.0;
        if !ok(self.rho_lower) {
            return Err(WaveError::Density("rho_lower", self.rho_lower));
        }
        if !ok(self.rho_upper) || self.rho_lower + self.rho_upper <= 0.0 {
            return Err(WaveError::Density("rho_upper", self.rho_upper));
        }
        if !ok(self.nu) {
            return Err(WaveError::Viscosity(self.nu));
        }
        if !(self.sigma.is_finite() && self.sigma > 0.0) {
            return Err(WaveError::Sigma(self.sigma));
        }
        if !(self.wavelength.is_finite() && self.wavelength > 0.0) {
            return Err(WaveError::Wavelength(self.wavelength));
        }
        Ok(())
    }
}

/// The solution with its roots and coefficients computed once: [`Prosperetti::amplitude`]
/// is a(t)/a0.
#[derive(Debug, Clone, PartialEq)]
pub struct Prosperetti {
    /// The set-up.
    pub params: WaveParams,
    /// The four roots z_i of the quartic.
    pub roots: [C; 4],
    /// z_i/Z_i · ω0²/(z_i² − νk²).
    coef: [C; 4],
    /// 4(1 − 4β)ν²k⁴/(8(1 − 4β)ν²k⁴ + ω0²).
    erfc_coef: f64,
    /// νk².
    nuk2: f64,
}

impl Prosperetti {
    /// Solves the quartic and sets up the sum.
    pub fn new(params: WaveParams) -> Result<Self, WaveError> {
        params.check()?;
        let (k, beta, w2) = (params.k(), params.beta(), params.omega0().powi(2));
        let nuk2 = params.nu * k * k;
        let s = nuk2.sqrt();
        let quartic = [
            1.0,
            -4.0 * beta * s,
            2.0 * (1.0 - 6.0 * beta) * nuk2,
            4.0 * (1.0 - 3.0 * beta) * nuk2 * s,
            (1.0 - 4.0 * beta) * nuk2 * nuk2 + w2,
        ]
        .map(C::real);
        let r = complex::poly_roots(&quartic);
        let roots: [C; 4] = [r[0], r[1], r[2], r[3]];
        let mut coef = [C::default(); 4];
        for i in 0..4 {
            let mut zi = C::real(1.0);
            for j in (0..4).filter(|&j| j != i) {
                zi = zi * (roots[j] - roots[i]);
            }
            if zi.abs() <= 1e-9 * roots[i].abs().max(w2.sqrt().sqrt()).powi(3) {
                return Err(WaveError::RepeatedRoot);
            }
            coef[i] = roots[i] / zi * C::real(w2) / (roots[i].sq() - C::real(nuk2));
        }
        let g = (1.0 - 4.0 * beta) * nuk2 * nuk2;
        Ok(Prosperetti { params, roots, coef, erfc_coef: 4.0 * g / (8.0 * g + w2), nuk2 })
    }

    /// a(t)/a0 (t ≥ 0; 1 at t = 0).
    pub fn amplitude(&self, t: f64) -> f64 {
        let t = t.max(0.0);
        let st = t.sqrt();
        let decay = (-self.nuk2 * t).exp();
        let mut sum = C::real(self.erfc_coef * complex::erfc_real((self.nuk2 * t).sqrt()));
        for (z, k) in self.roots.iter().zip(&self.coef) {
            sum = sum + *k * complex::exp_sq_erfc(*z * st) * decay;
        }
        sum.re
    }

    /// The slowest-decaying oscillatory mode: (angular frequency, decay rate) of
    /// `exp((z² − νk²)t)` over the roots with Re z < 0 (the terms that do not die out
    /// algebraically); None when no root is complex (an overdamped wave).
    pub fn dominant_mode(&self) -> Option<(f64, f64)> {
        self.roots
            .iter()
            .filter(|z| z.re < 0.0)
            .map(|z| z.sq() - C::real(self.nuk2))
            .filter(|s| s.im.abs() > 0.0)
            .map(|s| (s.im.abs(), -s.re))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// The small-viscosity decay rate of the amplitude to second order in `ε = (νk²)^{1/2}`: the
/// quartic's roots move from the inviscid `z0⁴ = −ω0²` to
/// `z = z0 + βε − (2 − 12β − 6β²)ε²/(4z0) + O(ε³)`, so the oscillatory modes (Re z0 < 0)
/// decay at `−Re(z² − ε²) = 2βε(ω0/2)^{1/2} + (2 − 6β − 4β²)νk²`. The first term is the
/// vortical layer at the interface (∝ ν^{1/2}); for a free surface (β = 0) only Lamb's 2νk²
/// is left.
pub fn small_viscosity_decay(p: &WaveParams) -> f64 {
    let (beta, w0) = (p.beta(), p.omega0());
    let nuk2 = p.nu * p.k().powi(2);
    2.0 * beta * nuk2.sqrt() * (w0 / 2.0).sqrt() + (2.0 - 6.0 * beta - 4.0 * beta * beta) * nuk2
}
