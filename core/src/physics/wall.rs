//! Wall boundary physics (docs/PHYSICS.md §6): Morris no-slip ghost velocity with its cap, the
//! free-slip variant, the Holmes state ratio option, and Monaghan's Lennard-Jones repulsion.
//! CPU twin of `shaders/wall.wgsl`.

use crate::real::{Real, V2};

/// Morris factor `β = min(β_max, 1 + d_j/d_i)` for a fluid particle at distance `d_i` in front
/// of the wall line and a wall particle at `d_j` behind it (T45). `d_j ≤ 0` (not behind the
/// nearest wall line, a corner case) gives β = 1. `d_i` is floored at `1e-6 Δx`.
#[inline(always)]
pub fn noslip_beta<T: Real>(d_i: T, d_j: T, beta_max: T, dx: T) -> T {
    if d_j <= T::zero() {
        return T::one();
    }
    let di = d_i.max(T::c(1e-6) * dx);
    (T::one() + d_j / di).min(beta_max)
}

/// Relative velocity `v_ij = v_i − v_ghost` for a fluid/wall pair: `β v_i` (no-slip) or
/// `β (v_i·n̂_w) n̂_w` (free-slip, only the wall-normal part remains, §6.3).
#[inline(always)]
pub fn wall_relative_velocity<T: Real>(v_i: V2<T>, beta: T, free_slip: bool, n_w: V2<T>) -> V2<T> {
    if free_slip {
        n_w * (v_i.dot(n_w) * beta)
    } else {
        v_i * beta
    }
}

/// Holmes variant of the factor (T49 reconstruction): χ − ½ replaces the distances,
/// `β = min(β_max, 1 + (χ_j − ½)/max(χ_i − ½, χ_floor))`, where for a wall particle χ_j − ½
/// measures its depth. `χ_j ≤ ½` gives β = 1.
#[inline(always)]
pub fn holmes_beta<T: Real>(chi_i: T, chi_j: T, chi_floor: T, beta_max: T) -> T {
    let dj = chi_j - T::c(0.5);
    if dj <= T::zero() {
        return T::one();
    }
    let di = (chi_i - T::c(0.5)).max(chi_floor);
    (T::one() + dj / di).min(beta_max)
}

/// Lennard-Jones repulsion from one boundary point (T44), acceleration on i:
/// `D[(r0/r)^p1 − (r0/r)^p2] r_ib/r²` for r < r0, else 0 (p1 = 12, p2 = 4).
#[inline(always)]
pub fn lj_wall_acc<T: Real>(r_ib: V2<T>, r0: T, d: T) -> V2<T> {
    let r2 = r_ib.norm2();
    if r2 >= r0 * r0 || r2 <= T::zero() {
        return V2::zero();
    }
    let q2 = r0 * r0 / r2;
    let q4 = q2 * q2;
    let q12 = q4 * q4 * q4;
    r_ib * (d * (q12 - q4) / r2)
}
