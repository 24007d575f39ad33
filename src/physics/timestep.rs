//! Time-step limits (PHYSICS.md §7.3, thesis T52–T54 and the Brackbill capillary limit).

use serde::Serialize;

/// The individual limits of one evaluation; `dt = min` of the finite ones.
#[derive(Clone, Copy, Debug, Serialize, Default)]
pub struct DtLimits {
    /// CFL: `cfl · h / (c_max + |v|_max)` (T52).
    pub cfl: f64,
    /// Viscous: `0.125 h² / ν_max` (T53).
    pub viscous: f64,
    /// Force: `0.125 sqrt(h/|a|_max)` (T54).
    pub force: f64,
    /// Capillary: `0.25 sqrt(ρ̄ h³ / (2π σ_max))`, ρ̄ the mean of the phase rest densities.
    pub capillary: f64,
}

impl DtLimits {
    /// Computes every limit. Infinite where the physics is absent (σ = 0, ν = 0, a = 0).
    #[allow(clippy::too_many_arguments)]
    pub fn compute(
        h: f64,
        cfl: f64,
        c_max: f64,
        v_max: f64,
        nu_max: f64,
        a_max: f64,
        rho_mean: f64,
        sigma_max: f64,
    ) -> Self {
        let inf = f64::INFINITY;
        Self {
            cfl: cfl * h / (c_max + v_max),
            viscous: if nu_max > 0.0 {
                0.125 * h * h / nu_max
            } else {
                inf
            },
            force: if a_max > 0.0 {
                0.125 * (h / a_max).sqrt()
            } else {
                inf
            },
            capillary: if sigma_max > 0.0 {
                0.25 * (rho_mean * h * h * h / (2.0 * std::f64::consts::PI * sigma_max)).sqrt()
            } else {
                inf
            },
        }
    }
    /// The smallest limit.
    pub fn min(&self) -> f64 {
        self.cfl
            .min(self.viscous)
            .min(self.force)
            .min(self.capillary)
    }
}
