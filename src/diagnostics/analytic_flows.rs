//! Analytic reference solutions used to validate the solver: transient plane Poiseuille flow
//! (Morris, Fox & Zhu 1997), the mode-2 oscillation period of a 2D drop (docs/PHYSICS.md §9(a)) and
//! the equilibrium circular cap of a 2D sessile drop (docs/PHYSICS.md §9(c), §10.3).

use std::f64::consts::PI;

/// Transient body-force-driven plane Poiseuille flow between no-slip plates at `y = 0` and
/// `y = height`, from rest (Morris et al. 1997, series solution):
/// ```text
/// u(y,t) = g/(2ν) y (L − y)
///        − Σ_{n≥0} 4 g L² / (ν π³ (2n+1)³) · sin(π y (2n+1)/L) · exp(−(2n+1)² π² ν t / L²)
/// ```
/// The series is summed until the term bound `4gL²/(νπ³(2n+1)³)·exp(…)` drops below
/// `1e-14 · u_max` (at most 10⁶ terms; at t = 0 the truncation error is ~1e-10·u_max).
/// Returns 0 for non-physical inputs (`height ≤ 0`, `nu ≤ 0`).
pub fn poiseuille_velocity(y: f64, t: f64, height: f64, nu: f64, g: f64) -> f64 {
    if !(height > 0.0 && nu > 0.0) {
        return 0.0;
    }
    let l = height;
    let steady = g / (2.0 * nu) * y * (l - y);
    let u_max = (g * l * l / (8.0 * nu)).abs();
    let c = 4.0 * g * l * l / (nu * PI.powi(3));
    let decay = PI * PI * nu * t.max(0.0) / (l * l);
    let mut sum = 0.0;
    for n in 0..1_000_000u64 {
        let k = (2 * n + 1) as f64;
        let bound = c / (k * k * k) * (-k * k * decay).exp();
        sum += bound * (PI * y * k / l).sin();
        if bound.abs() < 1e-14 * u_max {
            break;
        }
    }
    steady - sum
}

/// Steady plane Poiseuille centre-line velocity `g L²/(8ν)`.
pub fn poiseuille_max(height: f64, nu: f64, g: f64) -> f64 {
    g * height * height / (8.0 * nu)
}

/// Inviscid mode-2 oscillation period `T = 2π/ω` of a 2D drop (liquid column) of radius `r` in
/// an outer fluid (§9(a)): `ω² = n(n² − 1) σ / ((ρ_in + ρ_out) R³)`, n = 2.
/// σ = 1, ρ = 1 both, R = 0.1875 gives T = 0.2945.
pub fn drop_mode2_period(sigma: f64, rho_in: f64, rho_out: f64, r: f64) -> f64 {
    let n = 2.0f64;
    let omega2 = n * (n * n - 1.0) * sigma / ((rho_in + rho_out) * r.powi(3));
    2.0 * PI / omega2.sqrt()
}

/// A 2D circular cap on the wall line y = 0 (all lengths; `centre_y` and `apex` relative to the
/// wall).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cap {
    /// Cap radius R_c.
    pub radius: f64,
    /// Contact half-width `x_tp = R_c sin θ`.
    pub x_tp: f64,
    /// Apex height `R_c (1 − cos θ)`.
    pub apex: f64,
    /// Circle centre height `−R_c cos θ` (below the wall for θ < 90°).
    pub centre_y: f64,
}

/// Equilibrium circular cap (§9(c)) of contact angle `theta_rad` whose area equals
/// `area_full_drop`, the area of the whole drop on both sides of the symmetry plane (e.g.
/// `πR²/2` for the half-circle drop of radius R of §9(b)): `R_c² (θ − sinθ cosθ) = A`.
/// R = 0.25, θ = 60° gives R_c = 0.3998, x_tp = 0.3462 (D/D0 = x_tp/0.25 = 1.385).
pub fn equilibrium_cap(area_full_drop: f64, theta_rad: f64) -> Cap {
    let (s, c) = theta_rad.sin_cos();
    let radius = (area_full_drop / (theta_rad - s * c)).sqrt();
    Cap { radius, x_tp: radius * s, apex: radius * (1.0 - c), centre_y: -radius * c }
}
