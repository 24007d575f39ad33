//! The one background-pressure and sound-speed rule of every two-phase capillary built-in
//! (docs/PHYSICS.md §3.1): both follow from the tensile stress the Hu–Adams tensor puts on the
//! interface band, computed from the scene's kernel and h, so nothing is chosen per scene.

use super::{KernelCfg, Scene};
use crate::physics::kernel::{kernel_dwdr, lattice_sum, KernelParams};
use serde::{Deserialize, Serialize};

/// α: the background pressure is this multiple of the band tension `σ|∇C|_max/2`, so the
/// pressure in the band stays at or above `p_b/2 > 0` (no voids) with the rest of p_b as margin.
pub const BAND_PB_FACTOR: f64 = 2.0;

/// ε: the band tension is at most this fraction of the stiffest phase's `ρ0c0²`, so the density
/// deficit that carries it stays near 1 % at every resolution.
pub const BAND_TENSION_FRACTION: f64 = 0.01;

/// The rule's two constants as a scene section (`[capillary_rule]`), so a sensitivity run can
/// change them (`--set capillary_rule.alpha=1`); the built-ins take [`BAND_PB_FACTOR`] and
/// [`BAND_TENSION_FRACTION`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CapillaryRule {
    /// α: p_b = α·σ|∇C|_max/2.
    pub alpha: f64,
    /// ε: σ|∇C|_max/2 = ε·ρ0c0² of the densest phase.
    pub epsilon: f64,
}

impl Default for CapillaryRule {
    fn default() -> Self {
        CapillaryRule { alpha: BAND_PB_FACTOR, epsilon: BAND_TENSION_FRACTION }
    }
}

/// `|∇C|_max·Δx` on a flat interface of a square lattice (equal densities, colour jump 0 → 1):
/// the first row's `(1/V_i)Σ_j (V_i² + V_j²)·½·∇W_ij` over the other phase, with `V = 1/ΣW` the
/// lattice volume of the mass normalisation (docs/PHYSICS.md §2). Computed from the kernel
/// itself: 0.4628 for the quintic at h = Δx, 0.4119 at 1.2Δx.
pub fn flat_interface_gradient(kernel: &KernelCfg) -> f64 {
    let h = kernel.h_ratio;
    let kp = KernelParams::<f64>::new(kernel.kind, h);
    let vol = 1.0 / lattice_sum(kernel.kind, h, 1.0);
    let n = kp.support.ceil() as i64 + 1;
    // Rows k = 0, 1, ... below the interface (y_i = −k − ½), the other phase above y = 0.
    let row = |k: i64| -> f64 {
        let mut g = 0.0;
        for a in -n..=n {
            for b in 0..=n {
                let dy = (b + k + 1) as f64;
                let r = ((a * a) as f64 + dy * dy).sqrt();
                g -= vol * kernel_dwdr(&kp, r) * dy / r;
            }
        }
        g
    };
    (0..3).map(row).fold(0.0, f64::max)
}

/// The band tension `σ|∇C|_max/2` of a kernel at lattice spacing `dx`.
pub fn band_tension(sigma: f64, kernel: &KernelCfg, dx: f64) -> f64 {
    0.5 * sigma * flat_interface_gradient(kernel) / dx
}

/// Background pressure of the rule with the built-ins' α: `p_b = α·σ|∇C|_max/2`.
pub fn background_pressure(sigma: f64, kernel: &KernelCfg, dx: f64) -> f64 {
    BAND_PB_FACTOR * band_tension(sigma, kernel, dx)
}

/// The stiffness `B = ρ0c0²/γ` of the rule (the built-ins' ε) for a phase of rest density
/// `rho0` and exponent `gamma`: the band tension is `ε·ρ0c0²`.
pub fn stiffness(sigma: f64, kernel: &KernelCfg, dx: f64, rho0: f64, gamma: f64) -> f64 {
    let c0_sq = band_tension(sigma, kernel, dx) / (BAND_TENSION_FRACTION * rho0);
    rho0 * c0_sq / gamma
}

/// Applies the rule (the scene's `capillary_rule`, set to the default when absent) to a
/// two-phase scene at its resolution and kernel: every phase gets `p_b = α·T`; the densest phase
/// the c0 with `T = ε·ρ0c0²` and every other phase the sound speed of the same stiffness B
/// (`c_k = (γ_k B/ρ_k)^{1/2}`, one B in both phases as docs/PHYSICS.md §3 sets it).
pub fn apply(scene: &mut Scene) {
    let rule = scene.capillary_rule.get_or_insert_with(CapillaryRule::default).clone();
    let sigma = scene.surface_tension.as_ref().map_or(0.0, |s| s.sigma);
    let t = band_tension(sigma, &scene.kernel, scene.domain.dx());
    let Some(dense) = scene.phases.iter().max_by(|a, b| a.rho0.total_cmp(&b.rho0)).cloned() else {
        return;
    };
    let b = t / (rule.epsilon * dense.gamma);
    for p in &mut scene.phases {
        p.p_b = rule.alpha * t;
        p.c0 = (p.gamma * b / p.rho0).sqrt();
    }
}

/// A copy of the scene with the rule applied ([`apply`]).
pub fn ruled(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    apply(&mut s);
    s
}

/// `--set` overrides that move a capillary scene to `nx` under the rule (resolution, every
/// phase's p_b and c0), for the validation cases that run a built-in at another resolution.
pub fn sets_at(scene: &Scene, nx: u32) -> Vec<String> {
    let mut s = scene.clone();
    s.domain.nx = nx;
    apply(&mut s);
    let mut sets = vec![format!("domain.nx={nx}")];
    for (k, p) in s.phases.iter().enumerate() {
        sets.push(format!("phases.{k}.p_b={}", p.p_b));
        sets.push(format!("phases.{k}.c0={}", p.c0));
    }
    sets
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::kernel::KernelKind;

    #[test]
    fn the_flat_interface_gradient_matches_the_measured_first_row() {
        // tests/surface_tension.rs measures 0.4628 on a solver frame (quintic, h = Δx).
        let g = flat_interface_gradient(&KernelCfg { kind: KernelKind::Quintic, h_ratio: 1.0 });
        assert!((g - 0.4628).abs() < 2e-4, "{g}");
        // A wider kernel spreads the jump over more rows: a smaller first-row gradient.
        let wide = flat_interface_gradient(&KernelCfg { kind: KernelKind::Quintic, h_ratio: 1.2 });
        assert!(wide < g - 0.03, "{wide}");
    }

    #[test]
    fn the_rule_keeps_the_band_tension_at_one_percent_of_the_stiffness() {
        let k = KernelCfg { kind: KernelKind::CubicSpline, h_ratio: 1.2 };
        for nx in [33.0, 65.0, 105.0] {
            let dx = 0.5 / nx;
            let t = band_tension(1.0, &k, dx);
            let b = stiffness(1.0, &k, dx, 1.0, 7.0);
            assert!((t / (7.0 * b) - BAND_TENSION_FRACTION).abs() < 1e-12);
            assert!((background_pressure(1.0, &k, dx) - 2.0 * t).abs() < 1e-12);
        }
        // p_b ∝ 1/Δx, c0 ∝ Δx^{-1/2}.
        let c = |nx: f64| (7.0 * stiffness(1.0, &k, 0.5 / nx, 1.0, 7.0)).sqrt();
        assert!((c(120.0) / c(30.0) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn an_override_of_kernel_or_resolution_re_applies_the_rule_except_a_named_p_b() {
        let drop = crate::scene::builtin::builtin("oscillating-drop").unwrap();
        let set = |v: &[&str]| {
            crate::scene::overrides::apply_overrides(&drop, &v.iter().map(|s| s.to_string()).collect::<Vec<_>>())
                .unwrap()
        };
        let cubic = set(&["kernel.kind=cubic-spline", "domain.nx=45"]);
        let want = ruled(&cubic);
        assert!((cubic.phases[1].p_b - want.phases[1].p_b).abs() < 1e-12 && cubic.phases[1].p_b != drop.phases[1].p_b);
        assert!((cubic.phases[0].c0 - want.phases[0].c0).abs() < 1e-12 && cubic.phases[0].c0 > drop.phases[0].c0);
        let named = set(&["domain.nx=45", "phases.0.p_b=5"]);
        assert_eq!(named.phases[0].p_b, 5.0);
        assert!((named.phases[1].p_b - ruled(&named).phases[1].p_b).abs() < 1e-12);
        let alpha = set(&["capillary_rule.alpha=1"]);
        assert!((alpha.phases[0].p_b - 0.5 * drop.phases[0].p_b).abs() < 1e-12);
    }
}
