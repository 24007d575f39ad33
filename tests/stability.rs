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
        // c0 named, so the capillary rule keeps it (the rule would raise it with σ, and the CFL
        // limit with it).
        ("capillary", &["surface_tension.sigma=100.0", "phases.0.c0=35", "phases.1.c0=35", "time.dt=5e-5"]),
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
    // Under the capillary rule c0 ∝ Δx^{-1/2}: scale keeps the fraction of the tightest limit the
    // drop's dt = 1e-4 has at nx = 30 (the CFL limit, at that resolution's c0), and the scaled
    // dt passes the strict check at every resolution.
    let fraction = |s: &sphlab::scene::Scene| {
        let l = sphlab::scene::dt_policy::limits_at(s, s.domain.nx);
        (effective_dt(s) / l.limits.min(), l.c_max.0)
    };
    let (f30, c30) = fraction(&sphlab::study::study_scene(30));
    assert!((sphlab::study::study_scene(30).time.dt - 1e-4).abs() < 1e-15);
    for nx in [45, 60, 100, 160] {
        let s = sphlab::study::study_scene(nx);
        let (f, c) = fraction(&s);
        assert!((f / f30 - 1.0).abs() < 1e-9, "nx = {nx}: fraction {f} vs {f30} at nx = 30");
        // c0 follows the rule: (nx/30)^{1/2} times nx = 30's.
        assert!((c / c30 - (nx as f64 / 30.0).sqrt()).abs() < 1e-9, "nx = {nx}: c0 {c} vs {c30}");
        // Finer than the old CFL-only law 1e-4·30/nx, by the rise of c0.
        assert!(s.time.dt < 1e-4 * 30.0 / nx as f64, "nx = {nx}: {}", s.time.dt);
    }
    // relax-60 (the convergence cases) from its own dt at nx = 65, at both viscosities.
    for nx in [45, 65, 85, 105] {
        let base = builtin("relax-60").unwrap();
        let sets = |extra: &[&str]| {
            let mut v = vec![format!("domain.nx={nx}"), "time.dt_policy=scale".to_string()];
            v.extend(extra.iter().map(|s| s.to_string()));
            apply_overrides(&base, &v).unwrap()
        };
        let (f65, _) = fraction(&base);
        for s in [sets(&["phases.0.mu=0.15", "phases.1.mu=0.15"]), sets(&[])] {
            assert!(apply(&s).is_ok(), "nx = {nx}: the scaled dt passes the check");
            assert!(fraction(&s).0 <= f65 * (1.0 + 1e-9), "nx = {nx}: {} vs {f65}", fraction(&s).0);
        }
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
