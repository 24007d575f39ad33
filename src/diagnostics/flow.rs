//! Flow measurements on particle data (PHYSICS.md §9(a) centroid and oscillation, §9(b)
//! kinetic energy, wall shear-rate profile and maximum normal deviation).
//!
//! Pure functions over plain slices; wall particles carry the phase [`WALL`] and are skipped
//! everywhere. Slices of different lengths are read up to the shortest one.

use crate::scene::build::WALL;

/// Kinetic energy `Σ_{i∈phase} ½ m_i |v_i|²` of one fluid phase (§9(b)).
pub fn kinetic_energy(mass: &[f64], vel: &[[f64; 2]], phase: &[u32], which_phase: u32) -> f64 {
    mass.iter()
        .zip(vel)
        .zip(phase)
        .filter(|(_, &p)| p == which_phase)
        .map(|((m, v), _)| 0.5 * m * (v[0] * v[0] + v[1] * v[1]))
        .sum()
}

/// Mass-weighted centroid `Σ m_i x_i / Σ m_i` of one fluid phase (§9(a): x_c, y_c of the
/// quarter drop). `[NaN, NaN]` when the phase has no (positive) mass.
pub fn centroid(mass: &[f64], pos: &[[f64; 2]], phase: &[u32], which_phase: u32) -> [f64; 2] {
    let (mut m, mut mx, mut my) = (0.0, 0.0, 0.0);
    for ((mi, p), _) in mass.iter().zip(pos).zip(phase).filter(|(_, &ph)| ph == which_phase) {
        m += mi;
        mx += mi * p[0];
        my += mi * p[1];
    }
    if m > 0.0 {
        [mx / m, my / m]
    } else {
        [f64::NAN, f64::NAN]
    }
}

/// Total mass of each fluid phase `0..n_phases` (walls and out-of-range phases skipped).
pub fn mass_per_phase(mass: &[f64], phase: &[u32], n_phases: usize) -> Vec<f64> {
    let mut out = vec![0.0; n_phases];
    for (m, &p) in mass.iter().zip(phase) {
        if p != WALL && (p as usize) < n_phases {
            out[p as usize] += m;
        }
    }
    out
}

/// Maximum relative density error `max_i |ρ_i/ρ0_{k(i)} − 1|` over fluid particles whose phase
/// has a reference density in `rho0_of_phase` (0 when there is none).
pub fn max_density_error(rho: &[f64], rho0_of_phase: &[f64], phase: &[u32]) -> f64 {
    rho.iter()
        .zip(phase)
        .filter_map(|(r, &p)| rho0_of_phase.get(p as usize).filter(|_| p != WALL).map(|r0| (r / r0 - 1.0).abs()))
        .fold(0.0, f64::max)
}

/// Wall shear-rate profile, §9(b) quick check for a no-slip wall: for the first-row fluid
/// particles (`0 < y − y_w ≤ 1.2Δx`, any fluid phase) `γ̇_i ≈ u_i/(y_i − y_w)`, binned in x over
/// `[0, x_max]` into `bins` equal bins. Returns per bin (bin-centre x / x_max, mean |γ̇|, count);
/// empty bins report mean 0 with count 0. Particles outside `[0, x_max]` are ignored.
pub fn wall_shear_profile(
    pos: &[[f64; 2]],
    vel: &[[f64; 2]],
    phase: &[u32],
    dx: f64,
    y_w: f64,
    x_max: f64,
    bins: usize,
) -> Vec<(f64, f64, usize)> {
    if bins == 0 || !(x_max > 0.0) || !(dx > 0.0) {
        return Vec::new();
    }
    let mut sum = vec![0.0; bins];
    let mut cnt = vec![0usize; bins];
    for ((p, v), &ph) in pos.iter().zip(vel).zip(phase) {
        let s = p[1] - y_w;
        if ph == WALL || !(s > 0.0 && s <= 1.2 * dx) || !(p[0] >= 0.0 && p[0] <= x_max) {
            continue;
        }
        let b = ((p[0] / x_max * bins as f64) as usize).min(bins - 1);
        sum[b] += (v[0] / s).abs();
        cnt[b] += 1;
    }
    (0..bins)
        .map(|b| {
            let mean = if cnt[b] > 0 { sum[b] / cnt[b] as f64 } else { 0.0 };
            ((b as f64 + 0.5) / bins as f64, mean, cnt[b])
        })
        .collect()
}

/// Maximum normal deviation (degrees), §9(b) last bullet / Fig. 4.9: over fluid particles with
/// `|grad_c| > 0` and `y − y_w > 3Δx`, the largest angle between the outward liquid normal
/// (`grad_c` for liquid particles, `−grad_c` for gas particles: §5.2, ∇C points from the
/// particle's phase towards the other one) and the radial direction from `centre`.
pub fn max_normal_deviation(
    pos: &[[f64; 2]],
    phase: &[u32],
    grad_c: &[[f64; 2]],
    dx: f64,
    y_w: f64,
    centre: [f64; 2],
) -> Option<f64> {
    let mut worst: Option<f64> = None;
    for ((p, &ph), g) in pos.iter().zip(phase).zip(grad_c) {
        let gn = (g[0] * g[0] + g[1] * g[1]).sqrt();
        let r = [p[0] - centre[0], p[1] - centre[1]];
        let rn = (r[0] * r[0] + r[1] * r[1]).sqrt();
        if ph == WALL || !(gn > 0.0) || !(rn > 0.0) || !(p[1] - y_w > 3.0 * dx) {
            continue;
        }
        let sign = if ph == 0 { 1.0 } else { -1.0 };
        let cos = (sign * (g[0] * r[0] + g[1] * r[1]) / (gn * rn)).clamp(-1.0, 1.0);
        let a = cos.acos().to_degrees();
        worst = Some(worst.map_or(a, |w| w.max(a)));
    }
    worst
}

/// Result of [`oscillation`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oscillation {
    /// Mean time between successive upward crossings of `x − mean`.
    pub period: f64,
    /// Mean over all full cycles (between successive upward crossings) of ½(max − min).
    pub amplitude: f64,
    /// ½(max − min) over the first full cycle `[t_0, t_0 + period]` (§9(a) definition).
    pub amplitude_first_cycle: f64,
    /// Mean of x over the full cycles (from the first to the last upward crossing).
    pub mean: f64,
    /// Number of full cycles between the first and the last upward crossing.
    pub n_cycles: usize,
}

/// Period and amplitude of an oscillating record (§9(a): centroid x_c(t)).
///
/// Method (chosen over successive maxima, which noise shifts by a sizeable fraction of the
/// flat top): upward crossings of `x − mean` with a Schmitt trigger (the signal must first go
/// below `−h`, then the crossing counts once it exceeds `+h`; `h` = 3× the noise level
/// estimated from second differences), the crossing time interpolated linearly between the two
/// samples that bracket zero. The mean is first the plain mean, then re-taken over the full
/// cycles found, and the crossings searched again. Extrema are taken on a centred moving
/// average over ~1/20 of a period so that noise does not inflate ½(max − min).
/// Needs sorted `t` and at least two upward crossings; otherwise `None`.
pub fn oscillation(t: &[f64], x: &[f64]) -> Option<Oscillation> {
    let n = t.len().min(x.len());
    if n < 5 || t[..n].iter().chain(&x[..n]).any(|v| !v.is_finite()) {
        return None;
    }
    let (t, x) = (&t[..n], &x[..n]);
    // Noise level from second differences (white noise: var(Δ²x) = 6σ²).
    let d2: f64 = (1..n - 1).map(|i| (x[i + 1] - 2.0 * x[i] + x[i - 1]).powi(2)).sum::<f64>() / (n - 2) as f64;
    let noise = (d2 / 6.0).sqrt();
    let mut mean = x.iter().sum::<f64>() / n as f64;
    let mut cross = Vec::new();
    for _ in 0..2 {
        cross = upward_crossings(t, x, mean, 3.0 * noise);
        if cross.len() < 2 {
            return None;
        }
        let (i0, i1) = (cross[0].1, cross[cross.len() - 1].1);
        mean = x[i0..=i1].iter().sum::<f64>() / (i1 - i0 + 1) as f64;
    }
    let n_cycles = cross.len() - 1;
    let period = (cross[n_cycles].0 - cross[0].0) / n_cycles as f64;
    if !(period > 0.0) {
        return None;
    }
    let per_sample = (t[n - 1] - t[0]) / (n - 1) as f64;
    let half = (period / per_sample / 40.0) as usize;
    let smooth: Vec<f64> = (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half).min(n - 1));
            x[a..=b].iter().sum::<f64>() / (b - a + 1) as f64
        })
        .collect();
    let half_range = |a: usize, b: usize| {
        let s = &smooth[a..=b];
        0.5 * (s.iter().cloned().fold(f64::MIN, f64::max) - s.iter().cloned().fold(f64::MAX, f64::min))
    };
    let amplitude = cross.windows(2).map(|w| half_range(w[0].1, w[1].1)).sum::<f64>() / n_cycles as f64;
    let end = t.iter().position(|&ti| ti > t[0] + period).unwrap_or(n - 1);
    Some(Oscillation { period, amplitude, amplitude_first_cycle: half_range(0, end), mean, n_cycles })
}

/// Upward crossings of `x − mean` with hysteresis `h`: (interpolated time, sample index after
/// the crossing).
fn upward_crossings(t: &[f64], x: &[f64], mean: f64, h: f64) -> Vec<(f64, usize)> {
    let mut out = Vec::new();
    let mut armed = false;
    let mut last_up: Option<(f64, usize)> = None;
    for i in 0..x.len() {
        let y = x[i] - mean;
        if y < -h {
            armed = true;
            last_up = None;
        }
        if i > 0 && armed && x[i - 1] - mean < 0.0 && y >= 0.0 {
            let y0 = x[i - 1] - mean;
            let f = -y0 / (y - y0);
            last_up = Some((t[i - 1] + f * (t[i] - t[i - 1]), i));
        }
        if armed && y > h {
            if let Some(c) = last_up.take() {
                out.push(c);
            }
            armed = false;
        }
    }
    out
}
