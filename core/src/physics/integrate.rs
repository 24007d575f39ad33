//! Time integration updates (docs/PHYSICS.md §7.2). CPU twin of `shaders/integrate.wgsl`.
//! Midpoint predictor–corrector (default, sph-blitz `step`, as in §7.2) and velocity Verlet.
//! `vt` is the advection velocity (v, or the XSPH-smoothed velocity).
//!
//! The velocity Verlet sphlab runs (`time.integrator = "verlet"`, CPU `CpuSolver::verlet_drift`
//! / `verlet_kick`, WGSL `integrate.wgsl`) is not §7.2's form: the evaluation after the drift
//! sees the predicted velocity, so the viscous force does not lag and the scheme is second
//! order in dt with viscosity (measured 2.007 in x, 2.018 in v):
//! ```text
//! v_{n+½} = v_n + (dt/2) a_n
//! r_{n+1} = r_n + dt (v_{n+½} + ṽ_n − v_n)            (ṽ − v: the XSPH correction, 0 without XSPH)
//! a_{n+1} = A(r_{n+1}, v_n + dt a_n)
//! v_{n+1} = v_{n+½} + (dt/2) a_{n+1}
//! ```
//! §7.2's form, `a_{n+1} = A(r_{n+1}, v_{n+½})` (PySPH's PEC integrator), is kept as
//! `time.integrator = "verlet-pec"` (CPU only, first order with viscosity) for the PySPH
//! cross-code scene `scenes/pysph-rod.toml`.

use crate::real::{Real, V2};

/// Midpoint predictor: `r* = r + (dt/2) ṽ`, `v* = v + (dt/2) a`. Returns `(r*, v*)`.
#[inline(always)]
pub fn integrate_predict<T: Real>(r: V2<T>, v: V2<T>, vt: V2<T>, a: V2<T>, dt: T) -> (V2<T>, V2<T>) {
    let half = T::c(0.5) * dt;
    (r + vt * half, v + a * half)
}

/// Midpoint corrector from the start-of-step state: `v = v⁰ + dt a*`, `r = r⁰ + dt ṽ*`.
#[inline(always)]
pub fn integrate_correct<T: Real>(r0: V2<T>, v0: V2<T>, vt_star: V2<T>, a_star: V2<T>, dt: T) -> (V2<T>, V2<T>) {
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
