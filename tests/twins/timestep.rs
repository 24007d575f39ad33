//! Twin check of `timestep.wgsl` (the device's adaptive dt) against `DtLimits::compute(...).min()`
//! (part of `tests/wgsl_twins.rs`; same harness, error measure and tolerances, see its module doc).

use super::{check, N, TOL32, TOL64};
use crate::common::{Case, Rng, Twin};
use sphlab::gpu::GpuContext;
use sphlab::physics::timestep::DtLimits;
use sphlab::real::Real;

pub fn timestep_twins<T: Real>(ctx: &GpuContext) {
    let mut rng = Rng::new(0xd7);
    // Edge cases: each of ν, |a|, σ absent (0) in turn and together, |v| = 0; otherwise every
    // limit present, so each one binds in some cases.
    let cases: Vec<Case<T>> = (0..N)
        .map(|k| {
            let mut log = |lo: f64, hi: f64| rng.signed_log::<f64>(lo, hi).abs();
            let h = log(1e-4, 1e-1);
            let cfl = log(0.05, 0.5);
            let c_max = log(1.0, 100.0);
            let v_max = if k % 11 == 0 { 0.0 } else { log(1e-4, 10.0) };
            let nu_max = if k % 5 == 1 || k == 0 { 0.0 } else { log(1e-8, 1e-2) };
            let a_max = if k % 5 == 2 || k == 0 { 0.0 } else { log(1e-3, 1e6) };
            let rho_mean = log(1.0, 1000.0);
            let sigma_max = if k % 5 == 3 || k == 0 { 0.0 } else { log(1e-3, 1.0) };
            Case::new([h, cfl, c_max, v_max, nu_max, a_max, rho_mean, sigma_max].map(T::c).to_vec(), vec![])
        })
        .collect();
    let body =
        "put(i, 0u, dt_limits_min(a(i, 0u), a(i, 1u), a(i, 2u), a(i, 3u), a(i, 4u), a(i, 5u), a(i, 6u), a(i, 7u)));";
    let limits = |c: &Case<T>| {
        let x: Vec<f64> = c.args.iter().map(|v| v.f64()).collect();
        DtLimits::compute(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7])
    };
    check(ctx, Twin { name: "dt_limits_min", module: "timestep", body, nout: 1 }, &cases, (TOL32, TOL64), |c| {
        let dt = limits(c).min();
        vec![(T::c(dt), T::c(dt))]
    });
    let mut bound = [0usize; 4];
    for c in &cases {
        let l = limits(c);
        bound[[l.cfl, l.viscous, l.force, l.capillary].iter().position(|v| *v == l.min()).unwrap_or(0)] += 1;
    }
    assert!(bound.iter().all(|&b| b > 0), "every limit binds in some case: {bound:?}");
}
