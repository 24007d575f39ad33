//! `sphlab validate --quick` through the library API: every case at coarse resolution and
//! short times (seconds each), checking direction and rough size only. Each test states its
//! tolerance; the numbers in the comments were measured on the CPU backend (f64).

use sphlab::validate::{run_case, CaseReport, ValidateOptions};

fn quick(case: &str) -> (CaseReport, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("tempdir");
    let opts = ValidateOptions { quick: true, out: dir.path().to_path_buf(), ..ValidateOptions::default() };
    let rep = run_case(case, &opts).unwrap_or_else(|e| panic!("validate {case} --quick: {e}"));
    assert!(dir.path().join(case).join("summary.md").exists(), "summary.md written");
    assert!(dir.path().join("index.md").exists(), "index.md written");
    (rep, dir)
}

fn value(rep: &CaseReport, prefix: &str) -> f64 {
    rep.row(prefix).unwrap_or_else(|| panic!("no row `{prefix}` in {:#?}", rep.rows)).value
}

fn verdict(rep: &CaseReport, prefix: &str) -> String {
    rep.row(prefix).unwrap_or_else(|| panic!("no row `{prefix}`")).verdict.clone()
}

/// Oscillating drop at 24×24 (Δx = 1/48), relax 0.1: period 0.316 measured (the half-cycle
/// fallback: the coarse drop is strongly damped). Band 0.25–0.45: the full-resolution value
/// is 0.33, the thesis's 0.37, inviscid theory 0.2945; a coarse run only has to land near them.
#[test]
fn oscillation_period_in_band() {
    let (rep, _d) = quick("oscillation");
    let t = value(&rep, "period, field on all particles");
    assert!((0.25..=0.45).contains(&t), "period {t} outside 0.25–0.45");
    let a = value(&rep, "first-cycle amplitude, field on all");
    // measured 0.0071; the drop must move visibly but less than the thesis's 0.012 × 2
    assert!(a > 0.002 && a < 0.024, "amplitude {a}");
}

/// Mode B sessile drop at 26×26 to t = 0.3: circle-fit deviation ≤ 0.99° measured; tolerance
/// 3° (the thesis's bound at full resolution). Mode A's peak wall shear must exceed Mode B's
/// (9.6× measured at this resolution; the thesis reports ~160× at 65×65 and t ≈ 4.4), and so
/// must its mean flow along the wall at the contact line (9.6× measured over t ∈ [0.15, 0.3];
/// required 3×; 74× at nx = 45 to t = 5; 7.4× at nx = 65 to t = 5, reports/validation/sessile-90,
/// where Mode A's mean flow peaks at the right wall's corner and Mode B's beside the drop).
#[test]
fn sessile_mode_b_holds_90() {
    let (rep, _d) = quick("sessile-90");
    let dev = value(&rep, "Mode B: max |θ − 90°|, circle fit");
    assert!(dev < 3.0, "Mode B circle-fit deviation {dev}° ≥ 3°");
    let ratio = value(&rep, "peak wall shear rate ratio");
    assert!(ratio > 1.0, "Mode A / Mode B peak shear {ratio} ≤ 1");
    let flow = value(&rep, "peak mean-flow wall shear rate ratio");
    assert!(flow > 3.0, "Mode A / Mode B mean-flow wall shear {flow} ≤ 3");
}

/// relax-60 Mode B no-slip at 26×26 to t = 0.3: θ (circle fit) goes from 91° to 85° and D/D0
/// from 1.00 to 1.13 (measured). Required: θ decreases by at least 2° and D/D0 grows by at
/// least 0.03, towards 60° / 1.385; neither may overshoot the equilibrium.
#[test]
fn relax_60_moves_towards_60() {
    let (rep, _d) = quick("relax-60");
    let th = value(&rep, "Mode B, no-slip: θ − 60°, circle fit") + 60.0;
    let d = value(&rep, "Mode B, no-slip: D/D0");
    assert!(verdict(&rep, "Mode B, no-slip: θ − 60°, circle fit").starts_with("pass"), "θ did not decrease");
    assert!(verdict(&rep, "Mode B, no-slip: D/D0").starts_with("pass"), "D/D0 did not grow");
    assert!(th < 88.0 && th > 55.0, "θ = {th}° at the end of the quick run");
    assert!(d > 1.03 && d < 1.45, "D/D0 = {d}");
    reused_without_snapshots_keeps_the_wall_shear(&rep, _d.path());
}

/// The quick relax-60 case analysed again with `--reuse` after its runs' particle snapshots are
/// deleted (as in a checkout, where they are not committed): the wall-shear rows and table are
/// the committed report's, with a note; without a committed report they are gone.
fn reused_without_snapshots_keeps_the_wall_shear(rep: &CaseReport, root: &std::path::Path) {
    let peaks = |r: &CaseReport| -> Vec<(String, f64)> {
        r.rows
            .iter()
            .filter(|x| x.quantity.contains("peak wall shear"))
            .map(|x| (x.quantity.clone(), x.value))
            .collect()
    };
    let before = peaks(rep);
    assert!(!before.is_empty(), "the quick case measures the wall shear");
    let case = root.join("relax-60");
    let table = std::fs::read_to_string(case.join("wall_shear_profiles.csv")).unwrap();
    for run in std::fs::read_dir(case.join("runs")).unwrap().flatten() {
        for f in std::fs::read_dir(run.path()).unwrap().flatten() {
            if f.file_name().to_string_lossy().starts_with("particles_") {
                std::fs::remove_file(f.path()).unwrap();
            }
        }
    }
    let opts = ValidateOptions { quick: true, reuse: true, out: root.to_path_buf(), quiet: true, ..Default::default() };
    let again = run_case("relax-60", &opts).expect("reused");
    assert!(again.runs.iter().all(|r| r.reused), "every run reused");
    assert_eq!(peaks(&again), before);
    assert_eq!(std::fs::read_to_string(case.join("wall_shear_profiles.csv")).unwrap(), table);
    assert!(again.notes.iter().any(|n| n.contains("wall shear as the committed report measured it")));
    std::fs::remove_file(case.join("case.json")).unwrap();
    let bare = run_case("relax-60", &opts).expect("reused");
    assert!(peaks(&bare).is_empty(), "no snapshots and no committed report: no wall shear rows");
}

/// Impact at 24×24 (Δx = 46.9 µm) to 0.35 ms, θ = 50° and 160°: D/D0 2.24 vs 1.67 at the end
/// (measured). Required: 50° spreads more than 160° at the same time, the water mass is exact
/// (relative drift < 1e-12), no blow-up, no NaN.
#[test]
fn impact_spreads_more_when_hydrophilic_and_conserves_mass() {
    let (rep, _d) = quick("impact");
    let diff = value(&rep, "D/D0 at t = 0.35 ms");
    assert!(diff > 0.1, "D/D0(50°) − D/D0(160°) = {diff} ≤ 0.1");
    for th in [50, 160] {
        let v = verdict(&rep, &format!("θ = {th}°: max relative drift"));
        assert!(v.starts_with("invariant"), "θ = {th}°: {v}");
    }
    assert!(rep.runs.iter().all(|r| r.status == "ok"), "a run blew up");
}

/// The drop at rest (20×20, no initial velocity, no relax) to t = 0.3: after the start
/// transient (t ≥ 0.1) max speed 0.077 and liquid KE 2.0e-5 measured. Bounds (stated in
/// `validate::spurious`): max speed < 0.1, KE < 1e-4.
#[test]
fn spurious_currents_below_bound() {
    let (rep, _d) = quick("spurious");
    let v = value(&rep, "max fluid speed over 0.1");
    assert!(v < 0.1, "spurious max speed {v} ≥ 0.1");
    let ke = value(&rep, "max liquid kinetic energy");
    assert!(ke < 1e-4, "spurious KE {ke} ≥ 1e-4");
}

/// Unknown cases are input errors, not panics.
#[test]
fn unknown_case_is_an_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let opts = ValidateOptions { quick: true, out: dir.path().to_path_buf(), ..ValidateOptions::default() };
    assert!(matches!(run_case("nope", &opts), Err(sphlab::validate::ValidateError::Input(_))));
}

/// The default oscillating drop (30×30, relax 0.5, quintic h = 1.2Δx, p_b = 30; full resolution: coarser
/// lattices damp the amplitude below the band) against the thesis: period within 5 % of 0.37
/// (0.366 measured), first-cycle amplitude within 20 % of 0.012
/// (0.0100); every other kernel (`oscillation::kernel_sets`: cubic spline h = 1.2Δx, Wendland C2
/// h = 1.5Δx, Johnson h = 2Δx, Gaussian h = 1.2Δx) oscillates like a liquid: period within 15 %
/// of the quintic's (−14 %, −2 %, −8 %, −0.5 % measured) and the centroid back within 0.002 of
/// the circle's 0.0796 for t ≥ 0.4. Five runs of 11,000 steps of 900 particles.
#[test]
fn oscillating_drop_matches_thesis_with_every_kernel() {
    use sphlab::validate::oscillation::{self as osc, kernel_sets, measure};
    let dir = tempfile::tempdir().expect("tempdir");
    let run = |id: &str, sets: &[&str]| -> (f64, f64, f64) {
        let base = sphlab::scene::builtin::builtin("oscillating-drop").expect("built-in");
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let scene = sphlab::scene::overrides::apply_overrides(&base, &sets).expect("overrides");
        let out = dir.path().join(id);
        let opts = sphlab::run::RunOptions { out: out.clone(), every: 0, ..Default::default() };
        sphlab::run::run(&scene, &opts).unwrap_or_else(|e| panic!("{id}: {e}"));
        let (period, amp) = measure(&out).unwrap_or_else(|| panic!("{id}: no oscillation found"));
        let rows = sphlab::validate::data::read_series(&out);
        let late: Vec<f64> = rows.iter().filter(|r| r.t >= osc::LATE_T).map(|r| r.centroid_x).collect();
        let late = late.iter().sum::<f64>() / late.len().max(1) as f64;
        eprintln!(
            "{id}: period {period:.4}, first-cycle amplitude {amp:.4}, centroid for t ≥ {} {late:.4}",
            osc::LATE_T
        );
        (period, amp, late)
    };
    let circle = 4.0 * 0.1875 / (3.0 * std::f64::consts::PI);
    let (tq, aq, lq) = run("quintic", &[]);
    assert!((tq / osc::THESIS_PERIOD - 1.0).abs() <= osc::THESIS_PERIOD_TOL, "period {tq} not within 5 % of 0.37");
    assert!(
        (aq / osc::THESIS_AMPLITUDE - 1.0).abs() <= osc::THESIS_AMPLITUDE_TOL,
        "amplitude {aq} not within 20 % of 0.012"
    );
    assert!((lq - circle).abs() <= osc::LATE_TOL, "quintic centroid {lq} not back on the circle's {circle:.4}");
    for (id, _, sets) in kernel_sets() {
        let (t, _, late) = run(id, &sets);
        assert!(
            (t / tq - 1.0).abs() <= osc::KERNEL_PERIOD_TOL,
            "{id}: period {t} not within 15 % of the quintic's {tq}"
        );
        assert!((late - circle).abs() <= osc::LATE_TOL, "{id}: centroid {late} not back on the circle's {circle:.4}");
    }
}

/// PySPH's oscillating rod to t = 0.08 (`--quick`) with both colour-gradient forms: a_x, b_y and
/// the folded centroid within the stated bounds of the PySPH curve (0.5 % of the amplitude
/// single-field, 3 % thesis form), the single-field form closer on a_x than the thesis form.
#[test]
fn cross_code_quick_matches_pysph() {
    let (rep, _d) = quick("cross-code");
    let rms = |curve: &str, form: &str| {
        rep.rows
            .iter()
            .find(|r| r.quantity.starts_with(&format!("rms/amplitude of {curve} ")) && r.quantity.contains(form))
            .unwrap_or_else(|| panic!("no row for {curve}, {form}"))
    };
    for form in ["single-field", "thesis colour"] {
        for curve in ["a_x", "b_y", "mean_abs_x", "mean_abs_y"] {
            let r = rms(curve, form);
            assert!(r.verdict.starts_with("pass"), "{curve}, {form}: {} {}", r.sphlab, r.verdict);
        }
    }
    let (single, thesis) = (rms("a_x", "single-field").value, rms("a_x", "thesis colour").value);
    assert!(single < thesis, "a_x rms: single-field {single} not below thesis form {thesis}");
}

/// Capillary wave at 24 × 24 (Δx = λ/24, p_b = σ/(2Δx) = 12): equal densities over 0.6 (about
/// one period), rms of a/a0 against Prosperetti 0.098 measured; density ratio 1000 over 0.2
/// (half a period), 0.19 measured. Required: the equal-density rms below 0.2 and the
/// density-ratio-1000 run finished with a finite rms.
#[test]
fn capillary_wave_follows_prosperetti_roughly() {
    let (rep, _d) = quick("capillary-wave");
    let r1 = value(&rep, "rms of a/a0 − Prosperetti, t ≤ 0.600 (the record), density ratio 1");
    assert!(r1 < 0.2, "equal densities: rms {r1}");
    let r1000 = value(&rep, "rms of a/a0 − Prosperetti, t ≤ 0.200 (the record), density ratio 1000");
    assert!(r1000.is_finite(), "density ratio 1000: rms {r1000}");
    assert!(verdict(&rep, "rms of a/a0 − Prosperetti, t ≤ 0.600").starts_with("pass"));
}
