//! Cross-code and time-accuracy checks of the CPU reference.
//!
//! * `pysph_rod_*`: `scenes/pysph-rod.toml` (PySPH's `oscillating_rod.py --scheme adami_stress`
//!   set-up) against PySPH's own curve `data/reference/pysph-oscillating-rod.csv`: the liquid's
//!   half-extents `a_x`, `b_y` (PySPH's estimator ½(max − min)), its centroid folded into the
//!   first quadrant `mean_abs_x`, `mean_abs_y` (= the quarter-domain drop's centroid of thesis
//!   Fig. 4.1) and PySPH's quarter centroid `cx_quarter`, `cy_quarter` (liquid with x > 0 and
//!   y > 0: it jumps whenever one of the particles on the axes moves off them), at every
//!   committed row up to step [`ROD_STEPS`] (t = 0.08, past the first maximum of `a_x` at
//!   t ≈ 0.07). Each curve's rms difference is divided by the curve's amplitude (half its range
//!   over the same rows). Cost: 2 × 854 steps of 17,689 particles, 30–60 s each on the shared
//!   2-core machine.
//! * `*_second_order_in_dt`: positions after a fixed time at dt, dt/2, dt/4 and dt/8 on a coarse
//!   drop; successive differences must shrink ≈ 4× per halving (observed order ≥ 1.7).

use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::neighbours::SearchKind;
use sphlab::scene::build::build_layout;
use sphlab::scene::initial::initial_velocities;
use sphlab::scene::{ColourGradient, Integrator, Scene};

/// Last step compared (the reference row at t = 0.08).
const ROD_STEPS: u64 = 854;

fn rod_scene() -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/pysph-rod.toml");
    Scene::from_toml(&std::fs::read_to_string(path).expect("scenes/pysph-rod.toml")).expect("valid scene")
}

/// The compared curves, in the order of [`rod_measures`].
const NAMES: [&str; 6] = ["a_x", "b_y", "mean_abs_x", "mean_abs_y", "cx_quarter", "cy_quarter"];

/// (step, the [`NAMES`] values) rows of the committed PySPH curve.
fn reference() -> Vec<(u64, [f64; 6])> {
    let text = include_str!("../data/reference/pysph-oscillating-rod.csv");
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap_or_else(|| panic!("column {n}"));
    let (s, cols) = (col("step"), NAMES.map(col));
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            (v[s].parse().expect("step"), cols.map(|c| v[c].parse::<f64>().expect("number")))
        })
        .collect()
}

/// The [`NAMES`] estimators on the liquid (phase 0) of the first `n_fluid` particles.
fn rod_measures(pos: &[[f64; 2]], phase: &[u32], n_fluid: usize) -> [f64; 6] {
    let (mut lo, mut hi, mut abs) = ([f64::MAX; 2], [f64::MIN; 2], [0.0; 2]);
    let (mut sx, mut sy, mut nq, mut n) = (0.0, 0.0, 0.0, 0.0);
    for (p, _) in pos[..n_fluid].iter().zip(&phase[..n_fluid]).filter(|(_, &ph)| ph == 0) {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
            abs[k] += p[k].abs();
        }
        n += 1.0;
        if p[0] > 0.0 && p[1] > 0.0 {
            sx += p[0];
            sy += p[1];
            nq += 1.0;
        }
    }
    [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1]), abs[0] / n, abs[1] / n, sx / nq, sy / nq]
}

/// rms(sphlab − PySPH) / amplitude for each of the four curves, rows up to `ROD_STEPS`.
fn rod_errors(gradient: ColourGradient) -> [f64; 6] {
    let mut scene = rod_scene();
    scene.surface_tension.as_mut().expect("surface tension").colour_gradient = gradient;
    let mut layout = build_layout(&scene).expect("layout");
    let v = initial_velocities(&scene, &layout, None);
    layout.vel[..layout.n_fluid].copy_from_slice(&v);
    let mut s = CpuSolver::<f64>::new(&scene, &layout, Exec::Parallel, SearchKind::Cells);
    let rows: Vec<_> = reference().into_iter().filter(|r| r.0 <= ROD_STEPS).collect();
    assert!(rows.len() >= 15 && rows.last().expect("rows").0 == ROD_STEPS, "reference rows up to step {ROD_STEPS}");
    let mut sq = [0.0; 6];
    let (mut lo, mut hi) = ([f64::MAX; 6], [f64::MIN; 6]);
    for (step, r) in &rows {
        while s.step < *step {
            s.advance().unwrap_or_else(|e| panic!("pysph-rod: {e}"));
        }
        let pos: Vec<[f64; 2]> = s.pos.iter().map(|p| [p.x, p.y]).collect();
        let m = rod_measures(&pos, &s.phase, s.n_fluid);
        for k in 0..6 {
            sq[k] += (m[k] - r[k]).powi(2);
            lo[k] = lo[k].min(r[k]);
            hi[k] = hi[k].max(r[k]);
        }
    }
    std::array::from_fn(|k| (sq[k] / rows.len() as f64).sqrt() / (0.5 * (hi[k] - lo[k])))
}

/// PySPH's single-field colour gradient: every curve within 0.5 % of its amplitude (measured:
/// a_x 0.02 %, b_y 0.03 %, mean |x|, |y| 0.03 %, quarter
/// centroids 0.26 % and 0.21 %; with γ = 7 instead of 1.4 a_x is off by 0.6 % and cx_quarter 9 %).
#[test]
fn pysph_rod_single_field_matches_pysph() {
    let e = rod_errors(ColourGradient::SingleField);
    eprintln!("single-field rms/amplitude {e:?}");
    for (k, e) in e.iter().enumerate() {
        assert!(*e < 0.005, "{}: rms {:.4} of the amplitude ≥ 0.5 %", NAMES[k], e);
    }
}

/// The thesis's colour gradient (T71) on the same set-up: half-extents and folded centroid within
/// 3 % of the amplitude (measured: 1.4 %, 1.9 %, 2.2 %, 2.1 %), and the half-extents above 0.5 %
/// (single-field: 0.02–0.03 %), so that the option is seen to switch the form. PySPH's quarter centroid
/// is not held to 3 % here: its axis-particle jumps differ once the arrangement differs (19 %
/// and 9 % measured).
#[test]
fn pysph_rod_thesis_gradient_close_to_pysph() {
    let e = rod_errors(ColourGradient::Thesis);
    eprintln!("thesis rms/amplitude {e:?}");
    for (k, e) in e.iter().enumerate().take(4) {
        assert!(*e < 0.03, "{}: rms {:.4} of the amplitude ≥ 3 %", NAMES[k], e);
    }
    assert!(e[0] > 0.005 && e[1] > 0.005, "thesis form indistinguishable from single-field: {e:?}");
}

/// Fluid positions and velocities of the coarse oscillating drop (nx = 16, no relaxation,
/// viscosity `mu`) after `t` at `dt`.
fn drop_state(integrator: Integrator, mu: f64, dt: f64, t: f64) -> [Vec<[f64; 2]>; 2] {
    let mut scene = sphlab::scene::builtin::builtin("oscillating-drop").expect("built-in");
    for p in &mut scene.phases {
        p.mu = mu;
    }
    scene.domain.nx = 16;
    scene.relax = None;
    scene.time.integrator = integrator;
    scene.time.dt = dt;
    let mut layout = build_layout(&scene).expect("layout");
    let v = initial_velocities(&scene, &layout, None);
    layout.vel[..layout.n_fluid].copy_from_slice(&v);
    let mut s = CpuSolver::<f64>::new(&scene, &layout, Exec::Serial, SearchKind::Cells);
    let n = (t / dt).round() as u64;
    while s.step < n {
        s.advance().unwrap_or_else(|e| panic!("drop dt = {dt}: {e}"));
    }
    let nf = s.n_fluid;
    [s.pos[..nf].iter().map(|p| [p.x, p.y]).collect(), s.vel[..nf].iter().map(|v| [v.x, v.y]).collect()]
}

/// Observed orders in dt of the position error (`[0..2]`) and of the velocity error (`[2..4]`)
/// from successive differences: `log2(|x_dt − x_dt/2| / |x_dt/2 − x_dt/4|)` and the same one
/// halving finer (max norm over the fluid particles); exactly p for an error C·dt^p.
fn observed_orders(integrator: Integrator, mu: f64) -> [f64; 4] {
    let (dt, t) = (2e-4, 0.02);
    let xs: Vec<[Vec<[f64; 2]>; 2]> =
        [1.0, 2.0, 4.0, 8.0].iter().map(|k| drop_state(integrator, mu, dt / k, t)).collect();
    let diff = |a: &[[f64; 2]], b: &[[f64; 2]]| {
        a.iter().zip(b).map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()).fold(0.0, f64::max)
    };
    let d = |c: usize| -> Vec<f64> { (0..3).map(|k| diff(&xs[k][c], &xs[k + 1][c])).collect() };
    let (dx, dv) = (d(0), d(1));
    eprintln!("{integrator:?}, μ = {mu}: successive differences x {dx:?}, v {dv:?}");
    [(dx[0] / dx[1]).log2(), (dx[1] / dx[2]).log2(), (dv[0] / dv[1]).log2(), (dv[1] / dv[2]).log2()]
}

/// Midpoint, with the scene's viscosity μ = 0.05: measured position orders 2.04, 2.04.
#[test]
fn midpoint_second_order_in_dt() {
    let p = observed_orders(Integrator::Midpoint, 0.05);
    assert!(p.iter().all(|p| *p > 1.7), "midpoint: observed orders (x, x, v, v) {p:?} (need ≥ 1.7)");
}

/// Velocity Verlet (kick–drift–kick, one evaluation per step) with the scene's viscosity
/// μ = 0.05, in position and velocity. The evaluation after the drift sees the predicted
/// velocity v_n + dt·a_n; with v_{n+½} there (`verlet-pec`, PySPH's PEC scheme) the
/// viscous force of the closing kick lagged by O(dt) and the observed orders were 1.007, 1.003.
#[test]
fn verlet_second_order_in_dt_with_viscosity() {
    let p = observed_orders(Integrator::Verlet, 0.05);
    assert!(p.iter().all(|p| *p > 1.7), "Velocity Verlet: observed orders (x, x, v, v) {p:?} (need ≥ 1.7)");
}
