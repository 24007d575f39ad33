//! Contact angle from particle data (docs/PHYSICS.md §10; contact half-width from §9(e)).
//!
//! Conventions (§6.1, §10): the bottom wall surface is at `y_w`; particle rows sit at
//! `y_w + (k+½)Δx`; the drop sits against the symmetry plane x = 0 with x positive away from
//! the drop axis. Phase 0 = liquid, any other fluid phase = gas, [`WALL`](crate::scene::build::WALL) = wall particle
//! (ignored). All functions are pure, cost O(n) (a coarse cell grid of the gas particles near
//! the liquid answers the nearest-gas queries) and return `None` instead of panicking on
//! degenerate data; the `try_` forms also report an allocation of the grid or the interface
//! points that failed ([`max_bytes`] bounds them).
//!
//! * [`two_point`] — §10.1, the thesis' two-point method with the [P] interface-point
//!   refinement. On a perfect lattice the result is quantised (for one snapshot the
//!   horizontal offset between the two rows is a multiple of Δx: 90°, 45°, 135°, …); average
//!   the points (see [`two_point_points`]) or the angle over a time window as §10.1 asks.
//! * [`circle_fit`] — §10.2, Kåsa fit + 3 Gauss–Newton iterations on mirrored interface points.
//! * [`area_inversion`] — §10.3, bisection on `A/x_tp² = (θ − sinθcosθ)/sin²θ`. (The spec
//!   calls the right-hand side decreasing; it actually increases from 0 to ∞ on (0, π). The
//!   bisection is written for a monotone function of either sense.)

use super::gas_grid::{is_gas, GasGrid, LIQUID};
use crate::fallible::{self, AllocError};

/// What the interface points are called in an allocation failure.
const POINTS: &str = "the contact-angle interface points";

/// Upper bound of the bytes [`try_measure_all`] allocates for `n` fluid particles: the gas grid
/// and the interface points (16 B each, at most one per liquid particle, held with amortised
/// growth and then mirrored: 64 B per particle).
pub fn max_bytes(n: f64) -> f64 {
    GasGrid::max_bytes(n) + 64.0 * n
}

/// Result of [`circle_fit`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircleFit {
    /// Contact angle θ = acos((y_w − y_c)/R), degrees.
    pub theta_deg: f64,
    /// Fitted centre x (≈ 0 because mirrored points are used).
    pub xc: f64,
    /// Fitted centre y.
    pub yc: f64,
    /// Fitted radius R_c.
    pub radius: f64,
    /// Fitted contact half-width `x_c + sqrt(R_c² − (y_w − y_c)²)` (0 if the circle misses
    /// the wall line), §10.2 step 5.
    pub half_width: f64,
    /// Number of points in the fit, mirrored points included.
    pub n_points: usize,
}

/// The three estimates of §10, degrees (`None` where a method could not be applied).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactAngles {
    /// §10.1 two-point method.
    pub two_point: Option<f64>,
    /// §10.2 circle fit.
    pub circle_fit: Option<f64>,
    /// §10.3 area–spread inversion.
    pub area: Option<f64>,
}

fn midpoint(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
}

/// Interface point of the band `lo < y − y_w ≤ hi` (§10.1 [P]): the outermost liquid particle,
/// moved to the midpoint towards its nearest gas neighbour of the same band if one lies within
/// 1.5Δx.
fn band_point(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64, lo: f64, hi: f64) -> Option<[f64; 2]> {
    let n = pos.len().min(phase.len());
    let in_band = |i: usize| {
        let s = pos[i][1] - y_w;
        s > lo && s <= hi
    };
    let mut outer: Option<usize> = None;
    for i in (0..n).filter(|&i| phase[i] == LIQUID && in_band(i)) {
        if outer.is_none_or(|o| pos[i][0] > pos[o][0]) {
            outer = Some(i);
        }
    }
    let o = pos[outer?];
    let r2 = (1.5 * dx).powi(2);
    let mut best = (r2, None);
    for j in (0..n).filter(|&j| is_gas(phase[j]) && in_band(j)) {
        let d2 = (pos[j][0] - o[0]).powi(2) + (pos[j][1] - o[1]).powi(2);
        if d2 <= best.0 {
            best = (d2, Some(j));
        }
    }
    Some(best.1.map_or(o, |j| midpoint(o, pos[j])))
}

/// The two interface points (P1, P2) of §10.1: first row `(0, 1.2Δx]` and band
/// `(1.5Δx, 2.5Δx]` above the wall. Useful for averaging over a time window.
pub fn two_point_points(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64) -> Option<([f64; 2], [f64; 2])> {
    if !(dx > 0.0) {
        return None;
    }
    let p1 = band_point(pos, phase, dx, y_w, 0.0, 1.2 * dx)?;
    let p2 = band_point(pos, phase, dx, y_w, 1.5 * dx, 2.5 * dx)?;
    Some((p1, p2))
}

/// θ = atan2(y2 − y1, x1 − x2) in degrees, from the two points of [`two_point_points`].
pub fn two_point_angle(p1: [f64; 2], p2: [f64; 2]) -> f64 {
    (p2[1] - p1[1]).atan2(p1[0] - p2[0]).to_degrees()
}

/// §10.1 two-point contact angle (degrees) of one snapshot.
pub fn two_point(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64) -> Option<f64> {
    two_point_points(pos, phase, dx, y_w).map(|(p1, p2)| two_point_angle(p1, p2))
}

/// Interface points of §10.2 step 1: for each liquid particle with a gas particle within
/// 1.5Δx, the midpoint towards the nearest one (empty where they cannot be allocated;
/// [`try_interface_points`] says so).
pub fn interface_points(pos: &[[f64; 2]], phase: &[u32], dx: f64) -> Vec<[f64; 2]> {
    try_interface_points(pos, phase, dx).unwrap_or_default()
}

/// [`interface_points`], or the allocation that failed.
pub fn try_interface_points(pos: &[[f64; 2]], phase: &[u32], dx: f64) -> Result<Vec<[f64; 2]>, AllocError> {
    let r = 1.5 * dx;
    let Some(grid) = GasGrid::new(pos, phase, r)? else {
        return Ok(Vec::new());
    };
    let mut pts = Vec::new();
    for i in (0..pos.len().min(phase.len())).filter(|&i| phase[i] == LIQUID) {
        if let Some(j) = grid.nearest(pos, pos[i], r) {
            fallible::push(&mut pts, midpoint(pos[i], pos[j]), POINTS)?;
        }
    }
    Ok(pts)
}

/// Solves the 3×3 system `a x = b` by Cramer's rule; `None` if singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let scale = a.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    if !(d.abs() > 1e-300 && d.abs() > 1e-14 * scale.powi(3)) {
        return None;
    }
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][k] = b[r];
        }
        *xk = det(m) / d;
    }
    Some(x)
}

/// Circle through `pts`: Kåsa algebraic least squares, then 3 Gauss–Newton iterations on the
/// geometric distance. Returns (xc, yc, R).
pub fn fit_circle(pts: &[[f64; 2]]) -> Option<(f64, f64, f64)> {
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = pts.iter().fold((0.0, 0.0), |s, p| (s.0 + p[0] / n, s.1 + p[1] / n));
    // Kåsa on centred coordinates: u² + v² + D u + E v + F = 0.
    let (mut a, mut b) = ([[0.0; 3]; 3], [0.0; 3]);
    for p in pts {
        let (u, v) = (p[0] - mx, p[1] - my);
        let row = [u, v, 1.0];
        let z = u * u + v * v;
        for r in 0..3 {
            for c in 0..3 {
                a[r][c] += row[r] * row[c];
            }
            b[r] -= row[r] * z;
        }
    }
    let [d, e, f] = solve3(a, b)?;
    let (mut xc, mut yc) = (-0.5 * d, -0.5 * e);
    let mut rad = (xc * xc + yc * yc - f).max(0.0).sqrt();
    for _ in 0..3 {
        let (mut jtj, mut jtr) = ([[0.0; 3]; 3], [0.0; 3]);
        for p in pts {
            let (du, dv) = (p[0] - mx - xc, p[1] - my - yc);
            let dist = (du * du + dv * dv).sqrt();
            if dist == 0.0 {
                continue;
            }
            let jac = [-du / dist, -dv / dist, -1.0];
            let res = dist - rad;
            for r in 0..3 {
                for c in 0..3 {
                    jtj[r][c] += jac[r] * jac[c];
                }
                jtr[r] -= jac[r] * res;
            }
        }
        let Some(step) = solve3(jtj, jtr) else { break };
        xc += step[0];
        yc += step[1];
        rad += step[2];
    }
    (rad > 0.0 && rad.is_finite() && xc.is_finite() && yc.is_finite()).then_some((xc + mx, yc + my, rad))
}

/// §10.2 circle fit of the interface points above `y_w + 3Δx`, mirrored to (−x, y) (`None`
/// also where the points cannot be allocated; [`try_circle_fit`] says so).
pub fn circle_fit(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64) -> Option<CircleFit> {
    try_circle_fit(pos, phase, dx, y_w).ok().flatten()
}

/// [`circle_fit`], or the allocation that failed.
pub fn try_circle_fit(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64) -> Result<Option<CircleFit>, AllocError> {
    if !(dx > 0.0) {
        return Ok(None);
    }
    let mut pts = try_interface_points(pos, phase, dx)?;
    pts.retain(|p| p[1] - y_w >= 3.0 * dx);
    if pts.len() < 3 {
        return Ok(None);
    }
    let m = pts.len();
    if pts.capacity() < 2 * m {
        let mut all = fallible::with_capacity(2 * m, POINTS)?;
        all.extend_from_slice(&pts);
        pts = all;
    }
    for k in 0..m {
        let p = pts[k];
        pts.push([-p[0], p[1]]);
    }
    let Some((xc, yc, radius)) = fit_circle(&pts) else { return Ok(None) };
    let c = ((y_w - yc) / radius).clamp(-1.0, 1.0);
    let half_width = xc + (radius * radius - (y_w - yc).powi(2)).max(0.0).sqrt();
    Ok(Some(CircleFit { theta_deg: c.acos().to_degrees(), xc, yc, radius, half_width, n_points: pts.len() }))
}

/// `(θ − sinθcosθ)/sin²θ`: full-drop cap area divided by the squared contact half-width.
pub fn cap_area_ratio(theta: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    (theta - s * c) / (s * s)
}

/// §10.3: θ (degrees) of the circular cap of area `liquid_area_full_drop` (both sides of the
/// symmetry plane) and contact half-width `x_tp`, by bisection on (0, π).
pub fn area_inversion(liquid_area_full_drop: f64, x_tp: f64) -> Option<f64> {
    let target = liquid_area_full_drop / (x_tp * x_tp);
    if !(liquid_area_full_drop > 0.0 && x_tp > 0.0 && target.is_finite()) {
        return None;
    }
    let (mut lo, mut hi) = (1e-9, std::f64::consts::PI - 1e-9);
    let rising = cap_area_ratio(hi) > cap_area_ratio(lo);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (cap_area_ratio(mid) < target) == rising {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some((0.5 * (lo + hi)).to_degrees())
}

/// Contact half-width (§9(e)): x of the outermost first-row liquid particle
/// (`0 < y − y_w ≤ 1.2Δx`) plus Δx/2.
pub fn contact_half_width(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64) -> Option<f64> {
    (0..pos.len().min(phase.len()))
        .filter(|&i| phase[i] == LIQUID && pos[i][1] - y_w > 0.0 && pos[i][1] - y_w <= 1.2 * dx)
        .map(|i| pos[i][0])
        .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))))
        .map(|x| x + 0.5 * dx)
}

/// All three §10 estimates. Liquid area = n_liquid·Δx², doubled when the simulated domain is
/// mirrored at x = 0 (`mirrored`), so that it is the full-drop area §10.3 expects.
pub fn measure_all(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64, mirrored: bool) -> ContactAngles {
    let circle = circle_fit(pos, phase, dx, y_w).map(|c| c.theta_deg);
    ContactAngles { circle_fit: circle, ..estimates_besides_the_fit(pos, phase, dx, y_w, mirrored) }
}

/// [`measure_all`], or the allocation that failed (the circle fit's gas grid and points, at
/// most [`max_bytes`]).
pub fn try_measure_all(
    pos: &[[f64; 2]],
    phase: &[u32],
    dx: f64,
    y_w: f64,
    mirrored: bool,
) -> Result<ContactAngles, AllocError> {
    let circle = try_circle_fit(pos, phase, dx, y_w)?.map(|c| c.theta_deg);
    Ok(ContactAngles { circle_fit: circle, ..estimates_besides_the_fit(pos, phase, dx, y_w, mirrored) })
}

/// The two-point and area estimates (they allocate nothing).
fn estimates_besides_the_fit(pos: &[[f64; 2]], phase: &[u32], dx: f64, y_w: f64, mirrored: bool) -> ContactAngles {
    let n_liquid = phase.iter().take(pos.len()).filter(|&&p| p == LIQUID).count();
    let area = n_liquid as f64 * dx * dx * if mirrored { 2.0 } else { 1.0 };
    ContactAngles {
        two_point: two_point(pos, phase, dx, y_w),
        circle_fit: None,
        area: contact_half_width(pos, phase, dx, y_w).and_then(|x| area_inversion(area, x)),
    }
}
