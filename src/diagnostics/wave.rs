//! The standing capillary wave (docs/PHYSICS.md §9(f), §14): its amplitude from particle data,
//! and the period and damping of a sampled amplitude history (a damped-cosine fit).
//!
//! The amplitude is the first Fourier mode of the lower fluid's region. For an interface
//! `y = y0 + a cos(k(x − x0))` over a whole number of wavelengths W,
//! `∫∫_lower cos(k(x − x0)) dA = aW/2` whatever the shape of the bottom, and the particle sum
//! with lattice volumes Δx² is its quadrature; the upper fluid gives the same with the
//! opposite sign, and the estimator averages both:
//!
//! ```text
//! a = (Δx²/W) [ Σ_{i ∈ phase 0} cos(k(x_i − x0)) − Σ_{i ∈ phase 1} cos(k(x_i − x0)) ]
//! ```
//!
//! Phase 0 is the lower fluid. Motion that is the same in every column (the interface band's
//! vertical settling) does not enter it.

use crate::scene::build::WALL;

/// The wave amplitude a of the interface between phase 0 (below) and phase 1 (above) over the
/// width `width` starting at `x0` (a whole number of wavelengths 2π/k), with lattice spacing `dx`.
pub fn wave_amplitude(pos: &[[f64; 2]], phase: &[u32], dx: f64, x0: f64, width: f64, k: f64) -> f64 {
    let s: f64 = pos
        .iter()
        .zip(phase)
        .filter(|(_, &p)| p != WALL && p < 2)
        .map(|(r, &p)| if p == 0 { 1.0 } else { -1.0 } * (k * (r[0] - x0)).cos())
        .sum();
    dx * dx / width * s
}

/// The damped cosine `A e^{−γt} cos(ωt + φ)` closest in least squares to the samples with
/// t ≤ `t_max`: (ω, γ) by a grid over ω ∈ [0.3, 2]·`omega_guess`, γ ∈ [−0.5, 1.5]·`omega_guess`
/// (A and φ linear at each point), refined twice on a 10× finer grid around the best. Robust
/// to noise that crossings and peaks are not; NaN with fewer than 8 samples.
pub fn damped_cosine_fit(pts: &[(f64, f64)], t_max: f64, omega_guess: f64) -> (f64, f64) {
    let pts: Vec<(f64, f64)> = pts.iter().copied().filter(|p| p.0 <= t_max && p.1.is_finite()).collect();
    if pts.len() < 8 || !(omega_guess > 0.0) {
        return (f64::NAN, f64::NAN);
    }
    // Residual after the best A cos + B sin at (ω, γ).
    let resid = |w: f64, g: f64| {
        let (mut cc, mut cs, mut ss, mut yc, mut ys, mut yy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for &(t, y) in &pts {
            let e = (-g * t).exp();
            let (c, s) = (e * (w * t).cos(), e * (w * t).sin());
            cc += c * c;
            cs += c * s;
            ss += s * s;
            yc += y * c;
            ys += y * s;
            yy += y * y;
        }
        let det = cc * ss - cs * cs;
        if det.abs() < 1e-300 {
            return f64::INFINITY;
        }
        let (a, b) = ((yc * ss - ys * cs) / det, (ys * cc - yc * cs) / det);
        yy - a * yc - b * ys
    };
    let (mut w_lo, mut w_hi, mut g_lo, mut g_hi) =
        (0.3 * omega_guess, 2.0 * omega_guess, -0.5 * omega_guess, 1.5 * omega_guess);
    let mut best = (f64::NAN, f64::NAN);
    for _ in 0..3 {
        let n = 60;
        let mut r_best = f64::INFINITY;
        for i in 0..=n {
            let w = w_lo + (w_hi - w_lo) * i as f64 / n as f64;
            for j in 0..=n {
                let g = g_lo + (g_hi - g_lo) * j as f64 / n as f64;
                let r = resid(w, g);
                if r < r_best {
                    r_best = r;
                    best = (w, g);
                }
            }
        }
        let (dw, dg) = ((w_hi - w_lo) / n as f64, (g_hi - g_lo) / n as f64);
        (w_lo, w_hi, g_lo, g_hi) = (best.0 - 3.0 * dw, best.0 + 3.0 * dw, best.1 - 3.0 * dg, best.1 + 3.0 * dg);
    }
    best
}

/// Root-mean-square of `f(t) − g(t)` over the samples of `f` with t ≤ `t_max`.
pub fn rms_difference(f: &[(f64, f64)], g: impl Fn(f64) -> f64, t_max: f64) -> f64 {
    let d: Vec<f64> = f.iter().filter(|p| p.0 <= t_max).map(|p| p.1 - g(p.0)).collect();
    if d.is_empty() {
        return f64::NAN;
    }
    (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_finds_a_damped_cosine_under_noise() {
        let (w, g) = (11.0, 1.2);
        let pts: Vec<(f64, f64)> = (0..=400)
            .map(|i| i as f64 * 0.005)
            .map(|t| (t, 0.9 * (-g * t).exp() * (w * t + 0.2).cos() + 0.1 * (173.0 * t).sin()))
            .collect();
        let (fw, fg) = damped_cosine_fit(&pts, 2.0, 10.0);
        assert!((fw / w - 1.0).abs() < 0.01 && (fg / g - 1.0).abs() < 0.05, "ω {fw} γ {fg}");
        assert!(damped_cosine_fit(&pts[..5], 2.0, 10.0).0.is_nan());
    }

    #[test]
    fn the_amplitude_of_a_displaced_lattice_is_its_interface_amplitude() {
        use crate::scene::wave::InterfaceWave;
        let (n, a) = (40usize, 0.01);
        let dx = 1.0 / n as f64;
        let w = InterfaceWave { y0: 0.0, amplitude: a, wavelength: 1.0 };
        let (mut pos, mut phase) = (Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                let p = [(i as f64 + 0.5) * dx, -0.5 + (j as f64 + 0.5) * dx];
                phase.push(if p[1] < 0.0 { 0 } else { 1 });
                pos.push(w.displace(p, 0.0, -0.5, 0.5));
            }
        }
        let est = wave_amplitude(&pos, &phase, dx, 0.0, 1.0, w.k());
        // The midpoint rule of ∫ k cosh(k(H − y))/sinh(kH) dy: 1 − (kΔx)²/24 to leading order.
        assert!((est / a - 1.0).abs() < 0.003, "{est}");
        // An undisplaced lattice reads 0, a uniform vertical shift too.
        let flat: Vec<[f64; 2]> = (0..n * n).map(|q| [((q % n) as f64 + 0.5) * dx, 0.3]).collect();
        assert!(wave_amplitude(&flat, &phase, dx, 0.0, 1.0, w.k()).abs() < 1e-15);
    }
}
