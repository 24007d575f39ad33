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
use sphlab::diagnostics::rod::{pysph_rod_reference, rms_over_amplitude, rod_measures, ROD_CURVES};
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

/// rms(sphlab − PySPH) / amplitude for each curve, rows up to `ROD_STEPS`
/// ([`sphlab::diagnostics::rod`], shared with `sphlab validate cross-code`).
fn rod_errors(gradient: ColourGradient) -> [f64; 6] {
    let mut scene = rod_scene();
    scene.surface_tension.as_mut().expect("surface tension").colour_gradient = gradient;
    let mut layout = build_layout(&scene).expect("layout");
    let v = initial_velocities(&scene, &layout, None);
    layout.vel[..layout.n_fluid].copy_from_slice(&v);
    let mut s = CpuSolver::<f64>::new(&scene, &layout, Exec::Parallel, SearchKind::Cells);
    let rows: Vec<_> = pysph_rod_reference().into_iter().filter(|r| r.step <= ROD_STEPS).collect();
    assert!(rows.len() >= 15 && rows.last().expect("rows").step == ROD_STEPS, "reference rows up to step {ROD_STEPS}");
    let mut sim = Vec::new();
    for r in &rows {
        while s.step < r.step {
            s.advance().unwrap_or_else(|e| panic!("pysph-rod: {e}"));
        }
        let pos: Vec<[f64; 2]> = s.pos[..s.n_fluid].iter().map(|p| [p.x, p.y]).collect();
        sim.push(rod_measures(&pos, &s.phase[..s.n_fluid]));
    }
    let reference: Vec<[f64; 6]> = rows.iter().map(|r| r.v).collect();
    rms_over_amplitude(&sim, &reference)
}

/// PySPH's single-field colour gradient: every curve within 0.5 % of its amplitude (measured:
/// a_x 0.02 %, b_y 0.03 %, mean |x|, |y| 0.03 %, quarter
/// centroids 0.26 % and 0.21 %; with γ = 7 instead of 1.4 a_x is off by 0.6 % and cx_quarter 9 %).
#[test]
fn pysph_rod_single_field_matches_pysph() {
    let e = rod_errors(ColourGradient::SingleField);
    eprintln!("single-field rms/amplitude {e:?}");
    for (k, e) in e.iter().enumerate() {
        assert!(*e < 0.005, "{}: rms {:.4} of the amplitude ≥ 0.5 %", ROD_CURVES[k], e);
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
        assert!(*e < 0.03, "{}: rms {:.4} of the amplitude ≥ 3 %", ROD_CURVES[k], e);
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
