//! Flow measurements on particle data (docs/PHYSICS.md §9(a) centroid and oscillation, §9(b)
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
    argmax_density_error(rho, rho0_of_phase, phase).map_or(0.0, |(_, e)| e)
}

/// The particle of [`max_density_error`]: `(index, error)` of the first particle with the largest
/// error (NaN errors skipped); None when no particle has a reference density.
pub fn argmax_density_error(rho: &[f64], rho0_of_phase: &[f64], phase: &[u32]) -> Option<(usize, f64)> {
    let errors = rho.iter().zip(phase).enumerate().filter_map(|(i, (r, &p))| {
        rho0_of_phase.get(p as usize).filter(|_| p != WALL).map(|r0| (i, (r / r0 - 1.0).abs()))
    });
    argmax(errors)
}

/// The fluid particle with the largest speed: `(index, |v|)`, the first of equals; None when
/// there is no fluid particle.
pub fn argmax_speed(vel: &[[f64; 2]], phase: &[u32]) -> Option<(usize, f64)> {
    argmax(vel.iter().zip(phase).enumerate().filter(|(_, (_, &p))| p != WALL).map(|(i, (v, _))| (i, v[0].hypot(v[1]))))
}

/// The first `(index, value)` with the largest value, NaN values skipped.
fn argmax(items: impl Iterator<Item = (usize, f64)>) -> Option<(usize, f64)> {
    items.filter(|(_, v)| !v.is_nan()).fold(None, |best, (i, v)| match best {
        Some((_, b)) if v <= b => best,
        _ => Some((i, v)),
    })
}

/// Wall shear-rate profile, §9(b) quick check for a no-slip wall: for the first-row fluid
/// particles (`0 < y − y_w ≤ 1.2Δx`, any fluid phase) `γ̇_i ≈ u_i/(y_i − y_w)`, binned in x over
/// `[0, x_max]` into `bins` equal bins. Returns per bin (bin-centre x / x_max, mean |γ̇| or, with
/// `signed`, mean γ̇ (positive = flow towards +x), count); empty bins report mean 0 with count 0.
/// Particles outside `[0, x_max]` are ignored. The signed mean, averaged over many snapshots, is
/// the mean flow's shear (noise cancels); the mean of |γ̇| counts the noise too.
#[allow(clippy::too_many_arguments, reason = "the particles' arrays, the band and the bins are named at every call")]
pub fn wall_shear_profile(
    pos: &[[f64; 2]],
    vel: &[[f64; 2]],
    phase: &[u32],
    dx: f64,
    y_w: f64,
    x_max: f64,
    bins: usize,
    signed: bool,
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
        sum[b] += if signed { v[0] / s } else { (v[0] / s).abs() };
        cnt[b] += 1;
    }
    (0..bins)
        .map(|b| {
            let mean = if cnt[b] > 0 { sum[b] / cnt[b] as f64 } else { 0.0 };
            ((b as f64 + 0.5) / bins as f64, mean, cnt[b])
        })
        .collect()
}

/// Particles count in [`max_normal_deviation`] when `|∇C| ≥ NORMAL_GRAD_FRACTION · max|∇C|`.
/// Fig. 4.9 measures "near the interface": at the edge of the kernel support |∇C| is ~1 % of
/// its interface value and its direction is lattice noise (24° on the initial lattice when every
/// particle with ∇C ≠ 0 counted; 6–12° above this threshold).
pub const NORMAL_GRAD_FRACTION: f64 = 0.3;

/// Maximum normal deviation (degrees), §9(b) last bullet / Fig. 4.9: over fluid particles with
/// `|grad_c| ≥` [`NORMAL_GRAD_FRACTION`] × the largest `|grad_c|` of those fluid particles and
/// `y − y_w > 3Δx`, the largest angle between the outward liquid normal (`grad_c` for liquid
/// particles, `−grad_c` for gas particles: §5.2, ∇C points from the particle's phase towards the
/// other one) and the radial direction from `centre`.
pub fn max_normal_deviation(
    pos: &[[f64; 2]],
    phase: &[u32],
    grad_c: &[[f64; 2]],
    dx: f64,
    y_w: f64,
    centre: [f64; 2],
) -> Option<f64> {
    normal_deviations(pos, phase, grad_c, dx, y_w, centre).into_iter().reduce(f64::max)
}

/// The angles (degrees) of [`max_normal_deviation`], one per counted particle, in input order.
pub fn normal_deviations(
    pos: &[[f64; 2]],
    phase: &[u32],
    grad_c: &[[f64; 2]],
    dx: f64,
    y_w: f64,
    centre: [f64; 2],
) -> Vec<f64> {
    let norm = |g: &[f64; 2]| (g[0] * g[0] + g[1] * g[1]).sqrt();
    let gmax = pos
        .iter()
        .zip(phase)
        .zip(grad_c)
        .filter(|((p, &ph), _)| ph != WALL && p[1] - y_w > 3.0 * dx)
        .map(|(_, g)| norm(g))
        .fold(0.0, f64::max);
    let mut out = Vec::new();
    for ((p, &ph), g) in pos.iter().zip(phase).zip(grad_c) {
        let gn = norm(g);
        let r = [p[0] - centre[0], p[1] - centre[1]];
        let rn = (r[0] * r[0] + r[1] * r[1]).sqrt();
        if ph == WALL || !(gn > 0.0) || gn < NORMAL_GRAD_FRACTION * gmax || !(rn > 0.0) || !(p[1] - y_w > 3.0 * dx) {
            continue;
        }
        let sign = if ph == 0 { 1.0 } else { -1.0 };
        let cos = (sign * (g[0] * r[0] + g[1] * r[1]) / (gn * rn)).clamp(-1.0, 1.0);
        out.push(cos.acos().to_degrees());
    }
    out
}

/// Laplace pressure jump of a drop of radius `radius` about `centre`: the mean pressure of the
/// phase-0 particles deeper than `margin` inside the circle minus the mean of the phase-1
/// particles farther than `margin` outside it for which `keep(x)` holds (e.g. away from walls).
/// 2D theory: σ/R. `None` when either side has no particle.
pub fn laplace_jump(
    pos: &[[f64; 2]],
    p: &[f64],
    phase: &[u32],
    centre: [f64; 2],
    radius: f64,
    margin: f64,
    keep: impl Fn([f64; 2]) -> bool,
) -> Option<f64> {
    let (mut si, mut ni, mut so, mut no) = (0.0, 0usize, 0.0, 0usize);
    for ((x, &pi), &ph) in pos.iter().zip(p).zip(phase) {
        let r = (x[0] - centre[0]).hypot(x[1] - centre[1]);
        if ph == 0 && r < radius - margin {
            si += pi;
            ni += 1;
        } else if ph == 1 && r > radius + margin && keep(*x) {
            so += pi;
            no += 1;
        }
    }
    (ni > 0 && no > 0).then(|| si / ni as f64 - so / no as f64)
}

/// Result of [`oscillation`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oscillation {
    /// Time between successive maxima (§9(a)): weighted least-squares slope over all maxima.
    pub period: f64,
    /// Mean over the cycles between successive maxima of ½(max − min); smaller than
    /// [`Self::amplitude_first_cycle`] for a damped signal.
    pub amplitude: f64,
    /// ½(max − min) over the first full cycle `[t_0, t_0 + period]` (§9(a) definition).
    pub amplitude_first_cycle: f64,
    /// Mean of x from the first to the last maximum (whole cycles).
    pub mean: f64,
    /// Number of periods between the first and the last maximum found.
    pub n_cycles: usize,
}

/// Period and amplitude of an oscillating record (§9(a): centroid x_c(t)); `t` sorted.
///
/// Method. (1) Segment the record at the upward crossings of `x − mean`, with a Schmitt
/// trigger (the signal must first go below `−h`, the crossing counts once it exceeds `+h`;
/// `h` = 3× the noise level estimated from second differences). (2) In each segment
/// (including the partial ones at both ends) take the maximum of a centred moving average
/// (~1/20 period); keep it if it exceeds `mean + h`, is not a segment end and lies ≥ period/8
/// from both record ends; refine its time by a least-squares parabola through the raw
/// samples within ±period/8. (3) Period = slope of the weighted least-squares line through
/// (cycle index, time of maximum), weights = (peak height above the mean)² (a peak's timing
/// error scales as noise/height, so decayed cycles count little); an interval of k ≈
/// interval/median periods (a cycle lost in the noise) advances the index by k. A rough
/// period for the windows comes from a first pass (crossing spacing, or raw maxima).
///
/// Maxima rather than zero crossings: for a damped signal the mean over whole cycles is
/// biased (early cycles are larger), which shifts the crossings of `x − mean` more and more
/// as the amplitude decays (measured: +2.9 % period error on the test signal, 0.1 % with
/// maxima); the maxima of `A e^{−βt} cos ωt` are exactly one period apart whatever the mean.
/// Works on records of ~1.5 periods (two maxima), e.g. the thesis' t ∈ [0, 0.6] with T ≈ 0.37.
/// Extrema for the amplitudes are taken on the moving average so noise does not inflate them.
/// Returns `None` without two maxima.
pub fn oscillation(t: &[f64], x: &[f64]) -> Option<Oscillation> {
    let n = t.len().min(x.len());
    if n < 5 || t[..n].iter().chain(&x[..n]).any(|v| !v.is_finite()) || !(t[n - 1] > t[0]) {
        return None;
    }
    let (t, x) = (&t[..n], &x[..n]);
    let d2: f64 = (1..n - 1).map(|i| (x[i + 1] - 2.0 * x[i] + x[i - 1]).powi(2)).sum::<f64>() / (n - 2) as f64;
    let h = 3.0 * (d2 / 6.0).sqrt(); // white noise: var(Δ²x) = 6σ²
    let per_sample = (t[n - 1] - t[0]) / (n - 1) as f64;
    let mut mean = x.iter().sum::<f64>() / n as f64;
    let mut period = (t[n - 1] - t[0]) / 4.0; // first-pass guess, refined below
    let mut found = None;
    for _ in 0..3 {
        let cross = upward_crossings(t, x, mean, h);
        if cross.len() >= 2 {
            period = period.min((cross[cross.len() - 1].0 - cross[0].0) / (cross.len() - 1) as f64);
        }
        let half = (period / per_sample / 40.0) as usize;
        let smooth: Vec<f64> = (0..n)
            .map(|i| {
                let (a, b) = (i.saturating_sub(half), (i + half).min(n - 1));
                x[a..=b].iter().sum::<f64>() / (b - a + 1) as f64
            })
            .collect();
        let mut bounds = vec![0];
        bounds.extend(cross.iter().map(|c| c.1));
        bounds.push(n - 1);
        let w = period / 8.0;
        let mut peaks = Vec::new(); // (refined time, sample index)
        for s in bounds.windows(2).filter(|s| s[1] > s[0] + 1) {
            let k = (s[0]..=s[1]).fold(s[0], |m, i| if smooth[i] > smooth[m] { i } else { m });
            if k > s[0] && k < s[1] && smooth[k] > mean + h && t[k] - w >= t[0] && t[k] + w <= t[n - 1] {
                peaks.push((refine_peak(t, x, k, w), k));
            }
        }
        if peaks.len() < 2 {
            return first_cycle(t, x);
        }
        let iv: Vec<f64> = peaks.windows(2).map(|w| w[1].0 - w[0].0).collect();
        let mut sorted = iv.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        // Cycle index of each maximum, then a weighted least-squares line t_k = t_0 + k·T with
        // weights (peak height)², since the timing error of a peak scales as noise/height.
        let mut idx = vec![0.0];
        for d in &iv {
            idx.push(idx[idx.len() - 1] + (d / median).round().max(1.0));
        }
        let n_cycles = idx[idx.len() - 1] as usize;
        let (mut sw, mut sk, mut st, mut skk, mut skt) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (p, k) in peaks.iter().zip(&idx) {
            let wt = (smooth[p.1] - mean).powi(2);
            let tt = p.0 - peaks[0].0;
            sw += wt;
            sk += wt * k;
            st += wt * tt;
            skk += wt * k * k;
            skt += wt * k * tt;
        }
        period = (sw * skt - sk * st) / (sw * skk - sk * sk);
        if !(period > 0.0) {
            return None;
        }
        let (i0, i1) = (peaks[0].1, peaks[peaks.len() - 1].1);
        mean = x[i0..=i1].iter().sum::<f64>() / (i1 - i0 + 1) as f64;
        found = Some((peaks, smooth, n_cycles));
    }
    let (peaks, smooth, n_cycles) = found?;
    let half_range = |a: usize, b: usize| {
        let s = &smooth[a..=b];
        0.5 * (s.iter().cloned().fold(f64::MIN, f64::max) - s.iter().cloned().fold(f64::MAX, f64::min))
    };
    let amplitude = peaks.windows(2).map(|w| half_range(w[0].1, w[1].1)).sum::<f64>() / (peaks.len() - 1) as f64;
    let end = t.iter().position(|&ti| ti > t[0] + period).unwrap_or(n - 1);
    Some(Oscillation { period, amplitude, amplitude_first_cycle: half_range(0, end), mean, n_cycles })
}

/// Time of the maximum near sample `k`: vertex of the least-squares parabola through the
/// samples within `±w` of `t[k]`; `t[k]` itself if the fit is not a maximum inside the window.
#[allow(clippy::needless_range_loop, reason = "small dense elimination reads best with indices")]
fn refine_peak(t: &[f64], x: &[f64], k: usize, w: f64) -> f64 {
    let (mut s, mut b) = ([[0.0; 3]; 3], [0.0; 3]);
    for i in (0..t.len()).filter(|&i| (t[i] - t[k]).abs() <= w) {
        let tau = (t[i] - t[k]) / w;
        let row = [1.0, tau, tau * tau];
        for r in 0..3 {
            for c in 0..3 {
                s[r][c] += row[r] * row[c];
            }
            b[r] += row[r] * (x[i] - x[k]);
        }
    }
    // Gaussian elimination without pivoting (the normal matrix is positive definite).
    for p in 0..3 {
        if !(s[p][p].abs() > 1e-300) {
            return t[k];
        }
        for r in p + 1..3 {
            let f = s[r][p] / s[p][p];
            for c in p..3 {
                s[r][c] -= f * s[p][c];
            }
            b[r] -= f * b[p];
        }
    }
    let c2 = b[2] / s[2][2];
    let c1 = (b[1] - s[1][2] * c2) / s[1][1];
    let v = -c1 / (2.0 * c2);
    if c2 < 0.0 && v.abs() <= 1.0 {
        t[k] + v * w
    } else {
        t[k]
    }
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

/// Fallback of [`oscillation`] for a strongly damped record whose later maxima stay below the
/// record mean (a drop that settles within two cycles): on a lightly smoothed signal, the first
/// local maximum (max over ±5 % of the record), the minimum after it and the next local maximum.
/// Period = time between the two maxima; amplitude = ½(first max − min).
pub fn first_cycle(t: &[f64], x: &[f64]) -> Option<Oscillation> {
    let n = t.len().min(x.len());
    if n < 20 {
        return None;
    }
    let smooth: Vec<f64> = (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(2), (i + 2).min(n - 1));
            x[a..=b].iter().sum::<f64>() / (b - a + 1) as f64
        })
        .collect();
    let w = (n / 20).max(2);
    let is_peak = |k: usize| {
        let (a, b) = (k.saturating_sub(w), (k + w).min(n - 1));
        k > 0 && k < n - 1 && (a..=b).all(|j| smooth[j] <= smooth[k]) && smooth[k] > smooth[a].min(smooth[b])
    };
    let k1 = (1..n - 1).find(|&k| is_peak(k))?;
    let k2 = (k1 + w..n - 1).find(|&k| is_peak(k))?;
    let kmin = (k1..=k2).min_by(|&a, &b| smooth[a].total_cmp(&smooth[b]))?;
    let amp = 0.5 * (smooth[k1] - smooth[kmin]);
    Some(Oscillation {
        period: t[k2] - t[k1],
        amplitude: amp,
        amplitude_first_cycle: amp,
        mean: smooth[k1..=k2].iter().sum::<f64>() / (k2 - k1 + 1) as f64,
        n_cycles: 1,
    })
}
