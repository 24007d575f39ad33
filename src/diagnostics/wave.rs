//! The standing capillary wave (docs/PHYSICS.md §9(f), §14): its amplitude from particle data,
//! and the period and damping of a sampled amplitude history.
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

/// Period and damping of a sampled oscillation.
#[derive(Clone, Debug, PartialEq)]
pub struct WaveFit {
    /// The zero crossings found (linearly interpolated).
    pub crossings: Vec<f64>,
    /// Twice the mean spacing of successive crossings.
    pub period: f64,
    /// The half-cycle peaks (time, |a|): the largest |a| between successive crossings.
    pub peaks: Vec<(f64, f64)>,
    /// Decay rate γ: minus the least-squares slope of ln|peak| against t.
    pub damping: f64,
}

/// The zero crossings, half-cycle peaks, period and damping of `(t, a)` samples (t
/// increasing) up to `t_max`. A crossing counts once |a| has exceeded `threshold` on the
/// other side since the last one, so noise around a zero is not a crossing. Period needs two
/// crossings, damping two peaks (NaN otherwise); the first peak (before the first crossing)
/// is the start, not a peak, and is left out.
pub fn period_and_damping(pts: &[(f64, f64)], t_max: f64, threshold: f64) -> WaveFit {
    let pts: Vec<(f64, f64)> = pts.iter().copied().filter(|p| p.0 <= t_max && p.1.is_finite()).collect();
    let mut crossings = Vec::new();
    let mut state = 0.0f64;
    let mut last_change = None;
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if a.1.signum() != b.1.signum() {
            last_change = Some(if b.1 == a.1 { a.0 } else { a.0 + (b.0 - a.0) * a.1 / (a.1 - b.1) });
        }
        if b.1.abs() > threshold && b.1.signum() != state {
            if state != 0.0 {
                crossings.extend(last_change);
            }
            state = b.1.signum();
        }
    }
    let period = if crossings.len() >= 2 {
        2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
    } else {
        f64::NAN
    };
    let peaks: Vec<(f64, f64)> = crossings
        .windows(2)
        .filter_map(|c| {
            pts.iter().filter(|p| p.0 > c[0] && p.0 < c[1]).map(|p| (p.0, p.1.abs())).max_by(|x, y| x.1.total_cmp(&y.1))
        })
        .collect();
    let damping = if peaks.len() >= 2 {
        let n = peaks.len() as f64;
        let mt = peaks.iter().map(|p| p.0).sum::<f64>() / n;
        let ml = peaks.iter().map(|p| p.1.ln()).sum::<f64>() / n;
        let cov: f64 = peaks.iter().map(|p| (p.0 - mt) * (p.1.ln() - ml)).sum();
        let var: f64 = peaks.iter().map(|p| (p.0 - mt).powi(2)).sum();
        -cov / var
    } else {
        f64::NAN
    };
    WaveFit { crossings, period, peaks, damping }
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
    use std::f64::consts::PI;

    #[test]
    fn a_damped_cosine_gives_its_period_and_damping_and_noise_no_extra_crossings() {
        let (w, g) = (2.0 * PI / 0.5, 1.3);
        let mut pts: Vec<(f64, f64)> =
            (0..=2000).map(|i| i as f64 * 1e-3).map(|t| (t, (-g * t).exp() * (w * t).cos())).collect();
        let f = period_and_damping(&pts, 2.0, 0.02);
        assert!((f.period - 0.5).abs() < 1e-3, "{f:?}");
        // Peaks of e^{−γt}cos(ωt) sit slightly before the cosine's; the slope is still −γ.
        assert!((f.damping - g).abs() < 0.01, "{f:?}");
        assert_eq!(f.crossings.len(), 8);
        // ±0.01 jitter around each zero adds no crossing at threshold 0.02.
        for (i, p) in pts.iter_mut().enumerate() {
            p.1 += if i % 2 == 0 { 0.01 } else { -0.01 };
        }
        assert_eq!(period_and_damping(&pts, 2.0, 0.02).crossings.len(), 8);
        assert!(period_and_damping(&pts[..10], 2.0, 0.02).period.is_nan());
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
