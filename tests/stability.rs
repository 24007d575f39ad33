//! Numerical stability: a fixed dt above each stability limit is refused at load
//! naming the limit, `time.dt_policy = "scale"` reproduces the study's and the convergence
//! cases' dt, and the stability map of the oscillating drop finds where it becomes unstable.

use sphlab::backend_id::BackendId;
use sphlab::run::{run, RunOptions};
use sphlab::scene::builtin::builtin;
use sphlab::scene::dt_policy::{apply, effective_dt};
use sphlab::scene::overrides::apply_overrides;
use sphlab::stability::{cases, first_unstable, sweep, Record, StabilityOptions};

fn drop_with(sets: &[&str]) -> sphlab::scene::Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    apply_overrides(&builtin("oscillating-drop").unwrap(), &sets).unwrap()
}

#[test]
fn a_fixed_dt_above_each_limit_is_refused_naming_that_limit() {
    // oscillating-drop at nx = 30 (h = 1.2Δx): CFL 1.29e-4, viscous 1.0e-3, capillary 2.8e-4, no
    // gravity; with μ = 5 the viscous limit is 1.0e-5.
    let cases: [(&str, &[&str]); 4] = [
        ("cfl", &["time.dt=1.5e-4"]),
        ("viscous", &["phases.0.mu=5.0", "phases.1.mu=5.0", "time.dt=2e-5"]),
        ("force", &["gravity=[0.0,-1e6]", "time.dt=5e-5"]),
        ("capillary", &["surface_tension.sigma=100.0", "time.dt=5e-5"]),
    ];
    for (limit, sets) in cases {
        let s = drop_with(sets);
        let e = apply(&s).expect_err(limit);
        assert_eq!(e.field, "time.dt", "{limit}: {e}");
        assert!(e.msg.contains(&format!("{limit} limit")), "{limit} named: {e}");
        assert!(e.msg.contains("largest safe dt"), "{limit}: the largest safe dt is given: {e}");
        for other in ["cfl", "viscous", "force", "capillary"].into_iter().filter(|o| *o != limit) {
            assert!(!e.msg.contains(&format!("{other} limit")), "{limit}: only the exceeded limit is named: {e}");
        }
        // The same scene through the run driver: bad input (exit 2) before anything is built.
        let dir = tempfile::tempdir().unwrap();
        let opts = RunOptions { out: dir.path().join("o"), steps: Some(1), ..RunOptions::default() };
        let r = run(&s, &opts).expect_err(limit);
        assert_eq!(r.exit_code(), 2, "{limit}: {r}");
        assert!(!dir.path().join("o").exists(), "{limit}: refused before any output");
        // `warn` lets it through with the warning; the dt is unchanged.
        let w = drop_with(&[sets, &["time.dt_policy=warn"]].concat());
        let a = apply(&w).unwrap();
        assert_eq!(a.scene.time.dt, w.time.dt);
        assert!(a.warnings.iter().any(|x| x.starts_with(limit)), "{limit}: {:?}", a.warnings);
    }
    // The example: nx = 60 with the nx = 30 dt is refused for CFL and capillary.
    let e = apply(&drop_with(&["domain.nx=60"])).unwrap_err();
    assert!(e.msg.contains("cfl limit") && e.msg.contains("capillary limit"), "{e}");
}

#[test]
fn scale_gives_the_study_and_convergence_dt() {
    for nx in [30, 45, 60, 100] {
        let dt = sphlab::study::study_scene(nx).time.dt;
        let hand = 1e-4 * 30.0 / nx as f64;
        assert!((dt / hand - 1.0).abs() < 1e-12, "nx = {nx}: scale {dt} vs the study's {hand}");
    }
    // At nx = 160 the capillary limit (∝ Δx^1.5) binds (from nx ≈ 143 with h = 1.2Δx): scale keeps
    // the nx = 30 fraction of it, 5.5 % below the CFL-scaled 1.875e-5.
    let dt = sphlab::study::study_scene(160).time.dt;
    assert!(dt < 0.99 * 1.875e-5 && dt > 0.9 * 1.875e-5, "nx = 160: {dt}");
    // The convergence cases' old hand formula 7e-5·(65/nx)² is the viscous (Δx²) law: scale
    // reproduces it where the viscous limit binds (μ = 0.15, sessile-90's viscosity). With
    // relax-60's own μ = 0.05 (thesis §4.2.3) another limit binds, and scale keeps that limit's
    // fraction instead (a different dt from the Δx² law), always within every limit.
    for nx in [45, 65, 85, 105] {
        let hand = 7e-5 * (65.0 / nx as f64).powi(2);
        let base = builtin("relax-60").unwrap();
        let sets = |extra: &[&str]| {
            let mut v = vec![format!("domain.nx={nx}"), "time.dt_policy=scale".to_string()];
            v.extend(extra.iter().map(|s| s.to_string()));
            apply_overrides(&base, &v).unwrap()
        };
        let viscous = sets(&["phases.0.mu=0.15", "phases.1.mu=0.15"]);
        let dt = effective_dt(&viscous);
        assert!((dt / hand - 1.0).abs() < 1e-12, "relax-60 μ = 0.15 nx = {nx}: {dt} vs {hand}");
        assert!(apply(&viscous).is_ok(), "nx = {nx}: the scaled dt passes the check");
        let own = sets(&[]);
        assert!(apply(&own).is_ok(), "nx = {nx}: the scaled dt passes the check");
    }
}

#[test]
fn the_oscillating_drop_map_is_stable_up_to_the_limit_and_finds_where_it_breaks() {
    let base = builtin("oscillating-drop").unwrap();
    let o = StabilityOptions {
        dt_factors: vec![0.5, 1.0, 4.0, 16.0],
        density_ratios: vec![],
        viscosity_ratios: vec![],
        targets: vec![BackendId::default()],
        steps: 30,
        sample: 5,
        ..StabilityOptions::default()
    };
    assert_eq!(cases(&base, &o).len(), 1);
    let s = sweep(&base, &o, None, true);
    assert!(s.not_run.is_empty(), "{:?}", s.not_run);
    let recs: Vec<&Record> = s.records.iter().collect();
    assert_eq!(recs.len(), 4);
    for r in &recs {
        assert_eq!(r.nx, 30);
        assert_eq!(r.tightest_limit, "cfl");
        if r.dt_factor <= 1.0 {
            assert!(r.stable, "stable at {}× the tightest limit: {r:?}", r.dt_factor);
            assert!(r.max_density_error < 0.05 && r.mass_drift == 0.0, "{r:?}");
        }
    }
    let first = first_unstable(&recs).expect("unstable somewhere up to 16× the CFL limit");
    assert!(first > 1.0, "{first}");
    let bad = recs.iter().find(|r| r.dt_factor == first).unwrap();
    assert!(bad.fail_step.is_some() && !bad.reason.is_empty(), "{bad:?}");
}
