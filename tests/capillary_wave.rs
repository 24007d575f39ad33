//! Prosperetti's capillary-wave solution (docs/PHYSICS.md §14) against what it must satisfy:
//! the start at rest (a = a0, a' = 0, a'' = −ω0²a0), the inviscid limit a0 cos(ω0t), the
//! small-viscosity decay rates (Lamb's 2νk² for a free surface, the interface layer's
//! 2βε(ω0/2)^{1/2} between two fluids, derived independently of the solution's sum), and its
//! own dominant root.

use sphlab::analytic::capillary_wave::{small_viscosity_decay, Prosperetti, WaveError, WaveParams};
use std::f64::consts::PI;

fn params(rho_upper: f64, nu: f64) -> WaveParams {
    WaveParams { rho_lower: 1.0, rho_upper, nu, sigma: 1.0, wavelength: 1.0 }
}

/// The successive |extrema| of a(t) on a fine grid over [t0, t1]: (time, |a|).
fn extrema(p: &Prosperetti, t0: f64, t1: f64, n: usize) -> Vec<(f64, f64)> {
    let dt = (t1 - t0) / n as f64;
    let a: Vec<f64> = (0..=n).map(|i| p.amplitude(t0 + i as f64 * dt)).collect();
    (1..n)
        .filter(|&i| (a[i] - a[i - 1]) * (a[i + 1] - a[i]) < 0.0)
        .map(|i| {
            // Parabola through the three samples.
            let (l, m, r) = (a[i - 1], a[i], a[i + 1]);
            let off = 0.5 * (l - r) / (l - 2.0 * m + r);
            (t0 + (i as f64 + off) * dt, (m - 0.25 * (l - r) * off).abs())
        })
        .collect()
}

/// Least-squares slope of ln|a| over the extrema: −decay rate; and the mean half-period.
fn decay_and_period(ext: &[(f64, f64)]) -> (f64, f64) {
    let n = ext.len() as f64;
    let (mt, ml) = (ext.iter().map(|e| e.0).sum::<f64>() / n, ext.iter().map(|e| e.1.ln()).sum::<f64>() / n);
    let cov: f64 = ext.iter().map(|e| (e.0 - mt) * (e.1.ln() - ml)).sum();
    let var: f64 = ext.iter().map(|e| (e.0 - mt).powi(2)).sum();
    let half = (ext[ext.len() - 1].0 - ext[0].0) / (n - 1.0);
    (-cov / var, 2.0 * half)
}

#[test]
fn the_wave_starts_at_rest_from_a0() {
    for (rho_upper, nu) in [(1.0, 0.018_257), (0.001, 0.018_257), (1.0, 1e-4), (0.0, 0.01), (0.3, 0.05)] {
        let p = Prosperetti::new(params(rho_upper, nu)).unwrap();
        let w0 = p.params.omega0();
        assert!((p.amplitude(0.0) - 1.0).abs() < 1e-12, "ρ2 {rho_upper} ν {nu}: a(0) = {}", p.amplitude(0.0));
        // a'(0) = 0 and a''(0) = −ω0² whatever ν: the fluid is at rest, only the capillary
        // pressure acts. The √t terms of each erfc cancel in the sum only if the roots are right.
        let t = 1e-6;
        let curv = (p.amplitude(t) - 1.0) / (t * t);
        assert!((curv / (-0.5 * w0 * w0) - 1.0).abs() < 0.01, "ρ2 {rho_upper} ν {nu}: (a − 1)/t² = {curv}");
    }
}

#[test]
fn the_inviscid_limit_is_a_cosine() {
    for rho_upper in [1.0, 0.001, 0.0] {
        let p = Prosperetti::new(params(rho_upper, 1e-12)).unwrap();
        let w0 = p.params.omega0();
        for i in 0..=300 {
            let t = i as f64 * 3.0 * p.params.period0() / 300.0;
            let (a, want) = (p.amplitude(t), (w0 * t).cos());
            assert!((a - want).abs() < 1e-4, "ρ2 {rho_upper}, t {t}: {a} vs cos(ω0t) {want}");
        }
    }
    // ω0² = σk³/(ρ1 + ρ2): at λ = 1, σ = 1, equal densities ω0² = (2π)³/2.
    assert!((params(1.0, 0.0).omega0().powi(2) - 4.0 * PI.powi(3)).abs() < 1e-10);
}

#[test]
fn small_viscosity_decay_rates() {
    // Free surface (β = 0): Lamb's 2νk²; two equal fluids (β = ¼) and density ratio 1000: the
    // interface layer's 2βε(ω0/2)^{1/2}, ε = (νk²)^{1/2}, plus (2 − 6β − 4β²)νk², to O(ε³).
    for (rho_upper, nu, tol) in [(0.0, 1e-6, 0.002), (1.0, 1e-5, 0.002), (0.001, 1e-6, 0.002), (1.0, 1e-3, 0.05)] {
        let p = Prosperetti::new(params(rho_upper, nu)).unwrap();
        let want = small_viscosity_decay(&p.params);
        let t0 = 20.0 * p.params.period0();
        let (decay, period) = decay_and_period(&extrema(&p, t0, t0 + 20.0 * p.params.period0(), 40_000));
        println!("ρ2 {rho_upper} ν {nu}: decay {decay} vs {want} ({:+.2e})", decay / want - 1.0);
        assert!((decay / want - 1.0).abs() < tol, "ρ2 {rho_upper} ν {nu}: decay {decay} vs {want}");
        if nu <= 1e-5 {
            assert!((period / p.params.period0() - 1.0).abs() < 5e-3, "ρ2 {rho_upper} ν {nu}: period {period}");
        }
        // The envelope of the summed solution decays as its slowest oscillatory root says.
        let (omega, rate) = p.dominant_mode().unwrap();
        assert!((decay / rate - 1.0).abs() < 1e-3, "ρ2 {rho_upper}: {decay} vs root {rate}");
        assert!((2.0 * PI / omega / period - 1.0).abs() < 1e-3, "period {period} vs root {omega}");
    }
}

#[test]
fn at_laplace_3000_the_wave_is_damped_faster_than_the_free_surface_rate() {
    // Equal fluids, La = σρλ/μ² = 3000: the interface layer dominates the damping.
    let p = Prosperetti::new(params(1.0, (1.0f64 / 3000.0).sqrt())).unwrap();
    assert!((p.params.laplace() - 3000.0).abs() < 1e-9);
    let (decay, _) = decay_and_period(&extrema(&p, 0.5 * p.params.period0(), 4.0 * p.params.period0(), 20_000));
    let nuk2 = p.params.nu * (2.0 * PI).powi(2);
    assert!(decay > 1.5 * nuk2 && decay < 3.0 * nuk2, "decay {decay}, νk² {nuk2}");
    // The amplitude stays real and bounded by a0.
    for i in 0..=400 {
        let a = p.amplitude(i as f64 * 0.01);
        assert!(a.is_finite() && a.abs() <= 1.0 + 1e-12, "t {}: {a}", i as f64 * 0.01);
    }
}

#[test]
fn bad_input_names_the_field() {
    let bad = |p: WaveParams| Prosperetti::new(p).unwrap_err();
    assert_eq!(bad(WaveParams { nu: -1.0, ..params(1.0, 0.0) }), WaveError::Viscosity(-1.0));
    assert_eq!(bad(WaveParams { sigma: 0.0, ..params(1.0, 0.0) }), WaveError::Sigma(0.0));
    assert!(matches!(bad(params(f64::NAN, 0.0)), WaveError::Density("rho_upper", _)));
    assert!(matches!(bad(WaveParams { wavelength: 0.0, ..params(1.0, 0.0) }), WaveError::Wavelength(_)));
    assert!(bad(WaveParams { wavelength: 0.0, ..params(1.0, 0.0) }).to_string().contains("`wavelength`"));
}
