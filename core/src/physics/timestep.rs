//! Time-step limits (docs/PHYSICS.md §7.3, thesis T52–T54 and the Brackbill capillary limit).

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
    #[allow(
        clippy::too_many_arguments,
        reason = "each stability limit takes its own physical input, named at the call"
    )]
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
            viscous: if nu_max > 0.0 { 0.125 * h * h / nu_max } else { inf },
            force: if a_max > 0.0 { 0.125 * (h / a_max).sqrt() } else { inf },
            capillary: if sigma_max > 0.0 {
                0.25 * (rho_mean * h * h * h / (2.0 * std::f64::consts::PI * sigma_max)).sqrt()
            } else {
                inf
            },
        }
    }
    /// The smallest limit.
    pub fn min(&self) -> f64 {
        self.cfl.min(self.viscous).min(self.force).min(self.capillary)
    }
}

/// Viscous number `dt·ν/h²` at which the viscous limit (T53) binds.
pub const VISCOUS_NUMBER_LIMIT: f64 = 0.125;

/// The largest stability numbers a run reached, step by step: the CFL number
/// `dt·(c_max + |v|_max)/h` (limit: the scene's `time.cfl`), the viscous number `dt·ν_max/h²`
/// (limit 0.125) and `dt` over the force limit. Blow-up messages and the stability map quote them.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct StabilityNumbers {
    /// Largest CFL number.
    pub cfl_number: f64,
    /// Step at whose start it was reached.
    pub cfl_step: u64,
    /// Largest viscous number.
    pub viscous_number: f64,
    /// Largest dt / force limit.
    pub force_ratio: f64,
    /// Steps recorded.
    pub steps: u64,
}

impl StabilityNumbers {
    /// Records the limits at the start of step `step` (taken with `dt`); `cfl` is the CFL factor.
    pub fn record(&mut self, step: u64, dt: f64, cfl: f64, l: &DtLimits) {
        let c = cfl * dt / l.cfl;
        if c > self.cfl_number || self.steps == 0 {
            self.cfl_number = c;
            self.cfl_step = step;
        }
        if l.viscous.is_finite() {
            self.viscous_number = self.viscous_number.max(VISCOUS_NUMBER_LIMIT * dt / l.viscous);
        }
        if l.force.is_finite() {
            self.force_ratio = self.force_ratio.max(dt / l.force);
        }
        self.steps += 1;
    }
    /// One line for messages, e.g. `largest CFL number 0.31 at step 4 (limit time.cfl = 0.25), …`.
    pub fn describe(&self, cfl: f64) -> String {
        if self.steps == 0 {
            return "no step completed".into();
        }
        format!(
            "largest CFL number {:.3} at step {} (limit time.cfl = {cfl}), viscous number {:.3} (limit {VISCOUS_NUMBER_LIMIT}), dt/force limit {:.3}",
            self.cfl_number, self.cfl_step, self.viscous_number, self.force_ratio
        )
    }
}
