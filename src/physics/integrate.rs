//! Time integration updates (PHYSICS.md §7.2). CPU twin of `shaders/integrate.wgsl`.
//! Midpoint predictor–corrector (default, sph-blitz `step`) and velocity Verlet.
//! `vt` is the advection velocity (v, or the XSPH-smoothed velocity).

use crate::real::{Real, V2};

/// Midpoint predictor: `r* = r + (dt/2) ṽ`, `v* = v + (dt/2) a`. Returns `(r*, v*)`.
#[inline(always)]
pub fn integrate_predict<T: Real>(
    r: V2<T>,
    v: V2<T>,
    vt: V2<T>,
    a: V2<T>,
    dt: T,
) -> (V2<T>, V2<T>) {
    let half = T::c(0.5) * dt;
    (r + vt * half, v + a * half)
}

/// Midpoint corrector from the start-of-step state: `v = v⁰ + dt a*`, `r = r⁰ + dt ṽ*`.
#[inline(always)]
pub fn integrate_correct<T: Real>(
    r0: V2<T>,
    v0: V2<T>,
    vt_star: V2<T>,
    a_star: V2<T>,
    dt: T,
) -> (V2<T>, V2<T>) {
    (r0 + vt_star * dt, v0 + a_star * dt)
}

/// Velocity-Verlet half kick: `v + (dt/2) a`.
#[inline(always)]
pub fn integrate_kick<T: Real>(v: V2<T>, a: V2<T>, dt: T) -> V2<T> {
    v + a * (T::c(0.5) * dt)
}

/// Velocity-Verlet drift: `r + dt ṽ`.
#[inline(always)]
pub fn integrate_drift<T: Real>(r: V2<T>, vt: V2<T>, dt: T) -> V2<T> {
    r + vt * dt
}
