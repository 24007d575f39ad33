//! The contact angle θ_d at a contact point, measured from the particles for Mode A's unbalanced
//! Young force (docs/PHYSICS.md §8.2.5). In each of the first [`ANGLE_ROWS`] rows above the wall
//! the interface lies half-way between the outermost liquid particle on the point's side and the
//! nearest gas particle beyond it (Δx/2 beyond the liquid when no gas particle is there); a
//! quadratic through those points gives the interface's slope at the wall. Positions only: the
//! colour field near the wall is not used, since the wall typed at the last θ_d would bias it
//! towards that angle.

use super::stages::Ctx;
use crate::fields::ContactPoint;
use crate::real::Real;

/// Rows above the wall whose interface positions the slope is fitted to.
pub const ANGLE_ROWS: usize = 6;

/// Half-width, in Δx, of the window around the contact point searched for each row's interface.
pub const ANGLE_REACH_DX: f64 = 12.0;

/// cos θ_d at `cp`, θ_d measured through the liquid from the wall (so cos θ_d > 0 when the
/// interface leans over the liquid); None when fewer than two rows above the wall hold liquid
/// in the window. Mirror and periodic images are not searched (the window is local to the point).
pub fn measured_contact_cos<T: Real>(c: &Ctx<T>, cp: &ContactPoint<T>) -> Option<T> {
    let m = c.m;
    let reach = T::c(ANGLE_REACH_DX) * m.dx;
    // u = s·(x − x_cp): how far past the contact point, on the gas side, a particle lies.
    let row_u = |i: usize| -> Option<(usize, T)> {
        let d = c.pos[i].y - m.y_wall;
        let u = cp.s * (c.pos[i].x - cp.r.x);
        if d <= T::zero() || u.abs() > reach {
            return None;
        }
        let row = (d / m.dx).floor().f64() as usize;
        (row < ANGLE_ROWS).then_some((row, u))
    };
    let mut liquid: [Option<T>; ANGLE_ROWS] = [None; ANGLE_ROWS];
    for i in 0..c.n_fluid {
        if let (0, Some((row, u))) = (c.phase[i], row_u(i)) {
            liquid[row] = Some(liquid[row].map_or(u, |l: T| l.max(u)));
        }
    }
    let mut gas: [Option<T>; ANGLE_ROWS] = [None; ANGLE_ROWS];
    for i in 0..c.n_fluid {
        if let (1, Some((row, u))) = (c.phase[i], row_u(i)) {
            if liquid[row].is_some_and(|l| u > l) {
                gas[row] = Some(gas[row].map_or(u, |g: T| g.min(u)));
            }
        }
    }
    let half = T::c(0.5);
    let points: Vec<(T, T)> = liquid
        .iter()
        .zip(&gas)
        .enumerate()
        .map_while(|(k, (l, g))| {
            let l = (*l)?;
            Some((T::c(k as f64 + 0.5), g.map_or(l + half * m.dx, |g| half * (l + g))))
        })
        .collect();
    let slope = interface_slope(&points)? / m.dx;
    Some(-slope / (T::one() + slope * slope).sqrt())
}

/// du/dt at t = 0 of the least-squares quadratic through `(t, u)` (a straight line through two
/// points); None for fewer than two.
pub fn interface_slope<T: Real>(points: &[(T, T)]) -> Option<T> {
    match points.len() {
        0 | 1 => None,
        2 => Some((points[1].1 - points[0].1) / (points[1].0 - points[0].0)),
        _ => {
            // Normal equations of u = a + b t + c t², solved by Cramer's rule for b.
            let mut s = [T::zero(); 5];
            let mut r = [T::zero(); 3];
            for &(t, u) in points {
                let mut p = T::one();
                for k in 0..5 {
                    if k < 3 {
                        r[k] += p * u;
                    }
                    s[k] += p;
                    p *= t;
                }
            }
            let det3 = |a: [[T; 3]; 3]| {
                a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
                    + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
            };
            let a = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
            let d = det3(a);
            let ab = [[s[0], r[0], s[2]], [s[1], r[1], s[3]], [s[2], r[2], s[4]]];
            (d != T::zero()).then(|| det3(ab) / d)
        }
    }
}
