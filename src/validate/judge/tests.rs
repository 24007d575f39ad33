//! Tests of the verdicts: an invariant row is not counted as a pass, results off Young's angle,
//! off the thesis's shear ratio or diverging with refinement get FAIL, and re-judging is
//! idempotent.

use super::*;
use crate::validate::{ValidateOptions, CASES};

pub(super) fn report(name: &str, rows: Vec<Row>) -> CaseReport {
    CaseReport { rows, ..CaseReport::new(name, "test", false) }
}

fn judged(name: &str, rows: Vec<Row>) -> CaseReport {
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateOptions { out: dir.path().to_path_buf(), ..ValidateOptions::default() };
    let mut rep = report(name, rows);
    judge(name, &Ctx::new(&opts, name), &mut rep);
    rep
}

fn verdict<'a>(rep: &'a CaseReport, prefix: &str) -> &'a str {
    &rep.row(prefix).unwrap_or_else(|| panic!("no row {prefix}")).verdict
}

#[test]
fn an_invariant_row_is_counted_apart_and_not_as_a_pass() {
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateOptions { out: dir.path().to_path_buf(), ..ValidateOptions::default() };
    let rep = report(
        CASES[0],
        vec![
            Row::new("water mass drift", 0.0, 1, None, Some(0.0)).invariant(true, "mass exact"),
            Row::new("period", 0.366, 3, None, None).check(true, "within 5 %"),
            Row::new("broken", 1.0, 1, None, None).invariant(false, "mass exact"),
        ],
    );
    assert!(!rep.rows[0].is_pass() && rep.rows[1].is_pass() && !rep.rows[2].is_pass());
    let ctx = Ctx::new(&opts, CASES[0]);
    std::fs::create_dir_all(&ctx.dir).unwrap();
    crate::validate::report::write_summary(&ctx, &rep).unwrap();
    let index = std::fs::read_to_string(dir.path().join("index.md")).unwrap();
    // The pass names no band (this report was not judged): counted neither held nor not.
    assert!(
        index.contains("| 1 pass (0 held across their band, 0 not, 0 without one), 1 FAIL, 1 invariant, 0 info |"),
        "{index}"
    );
    // No run record carries the capillary rule: the case is listed as stale; one that does is not.
    assert!(index.contains("| **stale**: per-scene p_b (before the rule) | — | 1 pass ("), "{index}");
    let mut ruled = rep.clone();
    ruled.runs.push(
        serde_json::from_value(serde_json::json!({"id": "r", "dir": "x", "command": "c", "backend": "cpu1",
        "precision": "f64", "adapter": "CPU", "git_commit": "c", "date": "d", "wall_time_s": 1.0, "ms_per_step": 1.0,
        "steps": 1, "t_final": 1.0, "n_fluid": 1, "status": "ok", "reused": false}))
        .unwrap(),
    );
    let run = ctx.dir.join("runs/r");
    std::fs::create_dir_all(&run).unwrap();
    std::fs::write(run.join("summary.json"), r#"{"parameters": {"capillary_rule": {"alpha": 2.0, "epsilon": 0.01}}}"#)
        .unwrap();
    crate::validate::report::write_summary(&ctx, &ruled).unwrap();
    let index = std::fs::read_to_string(dir.path().join("index.md")).unwrap();
    assert!(index.contains("| the capillary rule | the scene's | 1 pass"), "{index}");
}

#[test]
fn relax_60_off_youngs_angle_fails_and_mode_b_passes_with_the_thesis_metric_beside() {
    let w = "mean over t ∈ [4.3, 4.5]";
    let rep = judged(
        "relax-60",
        vec![
            Row::new(&format!("Mode B, no-slip: θ − 60°, circle fit, {w} (deg)"), 0.99, 2, None, Some(0.0)),
            Row::new(&format!("Mode B, no-slip: θ − 60°, two-point, {w} (deg)"), -8.46, 2, None, Some(0.0)),
            Row::new(&format!("Mode A, no-slip: θ − 60°, circle fit, {w} (deg)"), 18.07, 2, None, Some(0.0)),
            Row::new(&format!("Mode A, no-slip: D/D0 at the wall, {w}"), 1.124, 3, None, Some(1.385)),
            Row::new("Mode A, no-slip: end angle approached from both sides, midpoint − 60°", 15.0, 2, None, None),
        ],
    );
    let b = verdict(&rep, "Mode B, no-slip: θ − 60°, circle fit");
    assert!(b.starts_with("pass") && b.contains("two-point metric: 51.5°") && b.contains("depends on p_b"), "{b}");
    assert!(verdict(&rep, "Mode B, no-slip: θ − 60°, two-point").starts_with("FAIL"));
    assert!(verdict(&rep, "Mode A, no-slip: θ − 60°, circle fit").starts_with("FAIL"));
    assert!(verdict(&rep, "Mode A, no-slip: D/D0").starts_with("FAIL"));
    assert!(verdict(&rep, "Mode A, no-slip: end angle").starts_with("FAIL"));
    // Mode A at Young's angle passes the same rule.
    let rep = judged(
        "relax-60",
        vec![Row::new(&format!("Mode A, no-slip: θ − 60°, circle fit, {w} (deg)"), 1.0, 2, None, None)],
    );
    assert!(verdict(&rep, "Mode A").starts_with("pass"));
    // The unbalanced Young force's rows are judged by the same bounds, each wall on its own.
    let young = "Mode A, unbalanced Young force";
    let rep = judged(
        "relax-60",
        vec![
            Row::new(&format!("{young}, no-slip: θ − 60°, circle fit, {w} (deg)"), 0.4, 2, None, Some(0.0)),
            Row::new(&format!("{young}, free-slip: D/D0 at the wall, {w}"), 1.30, 3, None, Some(1.385)),
            Row::new(
                &format!("{young}, no-slip: end angle approached from both sides, midpoint − 60°"),
                3.2,
                2,
                None,
                None,
            ),
        ],
    );
    let v = verdict(&rep, &format!("{young}, no-slip: θ − 60°"));
    assert!(v.starts_with("pass") && v.contains("mode-a-line/README.md"), "{v}");
    assert!(verdict(&rep, &format!("{young}, free-slip: D/D0")).starts_with("FAIL"));
    assert!(verdict(&rep, &format!("{young}, no-slip: end angle")).starts_with("FAIL"));
}

#[test]
fn the_shear_ratio_is_judged_against_the_thesis_not_its_direction() {
    let row = |v| {
        Row::new("peak wall shear rate ratio, Mode A / Mode B", v, 1, Some(160.0), None).check(v > 1.0, "direction")
    };
    assert!(verdict(&judged("sessile-90", vec![row(4.3)]), "peak").starts_with("FAIL"));
    assert!(verdict(&judged("sessile-90", vec![row(150.0)]), "peak").starts_with("pass"));
}

#[test]
fn an_angle_that_moves_away_from_young_with_refinement_fails_the_trend() {
    let rows = |th: [f64; 4]| {
        [45, 65, 85, 105]
            .iter()
            .zip(th)
            .map(|(nx, t)| Row::new(&format!("Δx = 0.5/{nx}: θ circle fit, mean (deg)"), t, 2, None, Some(60.0)))
            .collect::<Vec<_>>()
    };
    let rep = judged("convergence", rows([61.58, 60.99, 62.24, 63.40]));
    let v = verdict(&rep, "trend with refinement: |θ − 60°| at nx = 65, 85, 105");
    assert!(v.starts_with("FAIL"), "{v}");
    let rep = judged("convergence", rows([65.0, 63.0, 61.5, 60.5]));
    assert!(verdict(&rep, "trend with refinement").starts_with("pass"));
    // Judged again: one trend row, not two.
    let mut again = rep.clone();
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateOptions { out: dir.path().to_path_buf(), ..ValidateOptions::default() };
    judge("convergence", &Ctx::new(&opts, "convergence"), &mut again);
    assert_eq!(again.rows.len(), rep.rows.len());
    assert!(falls(&[3.0, 2.0, 1.0]) && !falls(&[1.0, 2.0, 3.0]) && !falls(&[1.0]));
}

#[test]
fn qualifying_a_verdict_twice_gives_the_same_text_and_leaves_info_rows_alone() {
    let band = Band {
        varied: "p_b × 0.5 / × 1".into(),
        values: vec!["1".into(), "2".into()],
        source: "f.csv".into(),
        holds: Some(false),
    };
    let mut r = Row::new("x", 1.0, 1, None, None).check(true, "< 3° (thesis)");
    r.qualify("p_b", Some(&band));
    let once = r.verdict.clone();
    r.qualify("p_b", Some(&band));
    assert_eq!(r.verdict, once);
    assert_eq!(once, "pass (< 3° (thesis); depends on p_b; sensitivity p_b × 0.5 / × 1: 1 / 2 (f.csv), bound not met across the band)");
    let mut info = Row::new("y", 1.0, 1, None, None);
    info.qualify("p_b", None);
    assert_eq!(info.verdict, "info");
}

#[test]
fn rejudge_applies_the_verdicts_to_a_committed_report_once_and_needs_one() {
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateOptions { out: dir.path().to_path_buf(), rejudge: true, ..ValidateOptions::default() };
    let missing = crate::validate::run_case("relax-60", &opts);
    assert!(matches!(missing, Err(crate::validate::ValidateError::Input(_))), "{missing:?}");
    let w = "mean over t ∈ [4.3, 4.5]";
    let rep = report(
        "relax-60",
        vec![Row::new(&format!("Mode A, no-slip: θ − 60°, circle fit, {w} (deg)"), 18.0, 2, None, None)],
    );
    let ctx = Ctx::new(&opts, "relax-60");
    std::fs::create_dir_all(&ctx.dir).unwrap();
    crate::validate::report::write_summary(&ctx, &rep).unwrap();
    crate::validate::run_case("relax-60", &opts).unwrap();
    let again = crate::validate::run_case("relax-60", &opts).unwrap();
    assert!(again.rows[0].verdict.starts_with("FAIL"), "{}", again.rows[0].verdict);
    assert_eq!(again.notes.iter().filter(|n| n.contains("--rejudge")).count(), 1);
}

/// A report root holding only the capillary rule's table with `csv` as its content.
fn rule_table(csv: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("capillary-rule")).unwrap();
    std::fs::write(dir.path().join("capillary-rule/capillary_rule.csv"), csv).unwrap();
    dir
}

#[test]
fn verdicts_name_the_capillary_rule_and_read_its_bands_from_the_committed_table() {
    let dir = rule_table(
        "alpha,nx,kernel,period,jump\n2.0,30,quintic,0.366,5.2\n2.0,45,quintic,0.374,5.24\n\
         1.0,30,quintic,0.432,nan\n4.0,30,quintic,0.366,nan\n2.0,30,johnson,0.35,5.3\n",
    );
    let ok = |v: f64| (v / 0.37 - 1.0).abs() <= 0.05;
    let a = alpha_band(dir.path(), "quintic", "period", ok).unwrap();
    assert_eq!(a.values, ["0.4320", "0.3660", "0.3660"]);
    assert!(a.varied.starts_with("α × 0.5 / × 1 / × 2") && a.holds == Some(false), "{a}");
    let n = nx_band(dir.path(), "quintic", "period", "x", ok).unwrap();
    assert_eq!((n.values.clone(), n.holds), (vec!["0.3660".to_string(), "0.3740".to_string()], Some(true)));
    // One point is no band; a missing column or table is none either.
    assert!(nx_band(dir.path(), "johnson", "period", "x", ok).is_none());
    assert!(nx_band(dir.path(), "quintic", "amplitude", "x", ok).is_none());
    assert!(alpha_band(&dir.path().join("none"), "quintic", "period", ok).is_none());
}

#[test]
fn the_spurious_kinetic_energy_carries_the_rules_alpha_band_of_the_drop_at_rest() {
    let dir = rule_table(
        "alpha,nx,kernel,rest_max_ke\n2.0,30,quintic,1.1e-5\n1.0,30,quintic,6.8e-4\n4.0,30,quintic,4.7e-6\n",
    );
    let opts = ValidateOptions { out: dir.path().to_path_buf(), ..ValidateOptions::default() };
    let ke = Row::new("max liquid kinetic energy for t ≥ 0.1", 1.1e-5, 6, None, Some(0.0)).check(true, "< 1e-4");
    let mut rep = report("spurious", vec![ke]);
    judge("spurious", &Ctx::new(&opts, "spurious"), &mut rep);
    let v = verdict(&rep, "max liquid kinetic energy");
    assert!(v.starts_with("pass (< 1e-4; depends on"), "{v}");
    assert!(
        v.contains(
            "α × 0.5 / × 1 / × 2 of the rule at nx = 30 (the drop at rest to t = 1): 6.80e-4 / 1.10e-5 / 4.70e-6"
        ),
        "{v}"
    );
    assert!(v.ends_with("bound not met across the band)"), "α × 0.5 is above 1e-4: {v}");
}

#[test]
fn every_kernel_is_held_to_the_thesis_at_both_resolutions_once() {
    let dir = rule_table(
        "alpha,nx,kernel,period,jump\n2.0,30,quintic,0.366,5.2\n2.0,45,quintic,0.374,5.24\n\
         2.0,30,cubic-spline,0.32,4.98\n2.0,45,cubic-spline,0.297,4.76\n2.0,30,johnson,0.35,5.3\n\
         1.0,30,cubic-spline,0.36,5.0\n4.0,30,cubic-spline,0.268,5.17\n",
    );
    let mut rep = report("oscillation", Vec::new());
    for _ in 0..2 {
        at_both_resolutions(dir.path(), &mut rep, ("period", "period"), (0.37, 0.05), 4, "the rule at each nx");
    }
    // One row per kernel with both points (Johnson has one: no row), not duplicated by a second judging.
    assert_eq!(rep.rows.len(), 2, "{:?}", rep.rows.iter().map(|r| &r.quantity).collect::<Vec<_>>());
    let quintic = verdict(&rep, "period under the rule at nx = 30 / 45, quintic");
    assert!(
        quintic.starts_with("pass") && quintic.contains("the rule at each nx; no committed sensitivity run"),
        "{quintic}"
    );
    let cubic = rep.row("period under the rule at nx = 30 / 45, cubic spline").unwrap();
    assert!(cubic.verdict.starts_with("FAIL") && cubic.sphlab.starts_with("0.3200 / 0.2970"), "{cubic:?}");
    // The kernel's own α band, its values in α order, judged by the row's bound at each.
    assert!(
        cubic.verdict.contains("α × 0.5 / × 1 / × 2 of the rule at nx = 30: 0.3600 / 0.3200 / 0.2680"),
        "{cubic:?}"
    );
    assert!(cubic.verdict.contains("bound not met across the band"), "{cubic:?}");
}

/// A run record of built-in `scene` with its kernel set to `kind` (the rule applied to it), as
/// `sphlab run` writes it, in `dir/<case>/runs/<id>`.
fn recorded_run(dir: &Path, case: &str, id: &str, scene: &str, kind: &str) -> crate::validate::report::RunRecord {
    let mut s = crate::scene::builtin::builtin(scene).unwrap();
    s.kernel.kind = serde_json::from_value(serde_json::json!(kind)).unwrap();
    if s.capillary_rule.is_some() {
        crate::scene::capillary::apply(&mut s); // at the new kernel, as a run with it would be
    }
    let run = dir.join(case).join("runs").join(id);
    std::fs::create_dir_all(&run).unwrap();
    let summary = serde_json::json!({ "scene": scene, "parameters": s, "backend": "cpu.cells.f64" });
    std::fs::write(run.join("summary.json"), summary.to_string()).unwrap();
    crate::validate::report::RunRecord::load(&run, "sphlab run", false).unwrap()
}

#[test]
fn the_rule_text_names_the_values_the_runs_were_made_at() {
    let dir = tempfile::tempdir().unwrap();
    let mut rep = report("relax-60", Vec::new());
    assert!(rule_text(dir.path(), &rep, "b-noslip").contains("run `b-noslip` has no record"));
    // A run of the cubic spline, made before the scene took the quintic: its own 60.7 / 55.1,
    // not the scene's 53.6 / 51.8 now.
    rep.runs.push(recorded_run(dir.path(), "relax-60", "b-noslip", "relax-60", "cubic-spline"));
    let then = rule_text(dir.path(), &rep, "b-noslip");
    assert!(
        then.contains("= 60.7 and c0 = 55.1") && then.contains("α = 2, ε = 0.01") && then.contains("nx = 65"),
        "{then}"
    );
    rep.runs[0] = recorded_run(dir.path(), "relax-60", "b-noslip", "relax-60", "quintic");
    assert!(rule_text(dir.path(), &rep, "b-noslip").contains("= 53.6 and c0 = 51.8"));
    let mut drop = report("oscillation", Vec::new());
    drop.runs.push(recorded_run(dir.path(), "oscillation", "quintic", "oscillating-drop", "quintic"));
    let at30 = rule_text(dir.path(), &drop, "quintic");
    assert!(at30.contains("= 24.7 and c0 = 35.2") && at30.contains("nx = 30"), "{at30}");
    // A scene without the rule's section says its values are the scene's own.
    let impact = recorded_run(dir.path(), "impact", "a", "impact", "quintic");
    let mut imp = report("impact", Vec::new());
    imp.runs.push(impact);
    let own = rule_text(dir.path(), &imp, "a");
    assert!(own.contains("set by the scene (before the capillary rule)"), "{own}");
}

#[test]
fn the_rods_rows_carry_their_p_b_band_from_the_cases_own_runs() {
    let sf = "single-field colour gradient (PySPH's)";
    let rms = |label: &str, v: f64| {
        Row::new(&format!("rms/amplitude of a_x over t ≤ 0.4967, {label}"), v, 5, None, None)
            .sphlab_text(format!("{:.3} %", 100.0 * v))
    };
    let damping =
        |label: &str, v: f64| Row::new(&format!("a_x damping rate β = Λ/(t_min − t_max), {label}"), v, 4, None, None);
    let th = "thesis colour gradient (T71)";
    let rep = judged(
        "cross-code",
        vec![
            rms(sf, 0.0007).check(true, "≤ 1.0 % (stated bound)"),
            rms(&format!("{sf}, p_b × 0.5"), 0.002),
            rms(&format!("{sf}, p_b × 2"), 0.02),
            damping(sf, 11.02).check(true, "within 2 % of PySPH's"),
            damping(&format!("{sf}, p_b × 0.5"), 11.1),
            damping(&format!("{sf}, p_b × 2"), 10.9),
            rms(th, 0.02).check(true, "≤ 3.0 % (stated bound)"),
        ],
    );
    let v = verdict(&rep, "rms/amplitude of a_x over t ≤ 0.4967, single-field colour gradient (PySPH's)");
    assert!(v.contains(": 0.200 % / 0.070 % / 2.000 % (curves_single-field-pb-half.csv, curves_single-field.csv, curves_single-field-pb-double.csv), bound not met across the band)"), "× 2 is past 1 %: {v}");
    // PySPH's damping rate is 11.02: 10.9 and 11.1 are within 2 % of it.
    let v = verdict(&rep, "a_x damping rate β = Λ/(t_min − t_max), single-field");
    assert!(v.ends_with("bound met across the band)"), "{v}");
    assert!(verdict(&rep, "rms/amplitude of a_x over t ≤ 0.4967, thesis").ends_with("no committed sensitivity run)"));
    assert_eq!(
        verdict(&rep, "rms/amplitude of a_x over t ≤ 0.4967, single-field colour gradient (PySPH's), p_b × 2"),
        "info"
    );
}

#[test]
fn sessile_mode_b_rows_carry_the_band_of_the_cases_own_alpha_runs() {
    let w = "mean over t ∈ [4.3, 4.5] (deg)";
    let band_rows = |nd: [f64; 3]| {
        let mut rows = vec![
            Row::new("Mode B: max |θ − 90°|, circle fit, whole run (deg)", 1.03, 2, Some(3.0), None)
                .check(true, "< 3°"),
            Row::new(&format!("Mode B: max normal deviation, {w}"), 10.13, 2, None, Some(0.0)).check(false, "0–8°"),
        ];
        for ((_, alpha, _), v) in crate::validate::sessile::BAND_RUNS.iter().zip(nd) {
            let label = crate::validate::sessile::band_label(true, *alpha);
            rows.push(Row::new(&format!("{label}: max |θ − 90°|, circle fit, whole run (deg)"), 2.0, 2, None, None));
            rows.push(Row::new(&format!("{label}: max normal deviation, {w}"), v, 2, None, Some(0.0)));
        }
        rows
    };
    let rep = judged("sessile-90", band_rows([7.0, 7.5, 8.5]));
    let nd = verdict(&rep, "Mode B: max normal deviation");
    assert!(
        nd.contains("7.00 / 7.50 / 8.50 (runs/mode-b-nx33-alpha1, runs/mode-b-nx33, runs/mode-b-nx33-alpha4)"),
        "{nd}"
    );
    assert!(nd.contains("bound not met across the band"), "8.5° is past the 0–8° band: {nd}");
    let circle = verdict(&rep, "Mode B: max |θ − 90°|");
    assert!(circle.contains("2.00 / 2.00 / 2.00") && circle.contains("bound met across the band"), "{circle}");
    let rep = judged("sessile-90", band_rows([7.0, 7.5, 7.9]));
    assert!(verdict(&rep, "Mode B: max normal deviation").contains("bound met across the band"));
    // One α run missing: no band, said so.
    let mut rows = band_rows([7.0, 7.5, 7.9]);
    rows.retain(|r| !r.quantity.starts_with(&crate::validate::sessile::band_label(true, 4.0)));
    let nd = judged("sessile-90", rows);
    assert!(verdict(&nd, "Mode B: max normal deviation").contains("no committed sensitivity run"));
    assert!(!verdict(&nd, "Mode B: max |θ − 90°|").contains("sensitivity the capillary rule"));
}

#[test]
fn the_sessile_shear_ratio_carries_mode_a_over_mode_b_at_each_alpha_and_holds_only_if_all_three_do() {
    use crate::validate::sessile::{band_label, peak_shear, BAND_RUNS};
    let w = "t ∈ [4.3, 4.5]";
    // Mode B's peaks 0.5, 1, 2; Mode A's chosen so the ratios at α = 1, 2, 4 are `ratios`.
    let rows = |ratios: [f64; 3]| {
        let mut rows = vec![Row::new("peak wall shear rate ratio, Mode A / Mode B", 7.9, 1, Some(160.0), None)];
        for (i, &(_, alpha, mode_b)) in BAND_RUNS.iter().enumerate() {
            let b = [0.5, 1.0, 2.0][i % 3];
            let v = if mode_b { b } else { b * ratios[i % 3] };
            rows.push(Row::new(&format!("{}: {}", band_label(mode_b, alpha), peak_shear(w)), v, 4, None, None));
        }
        rows
    };
    let rep = judged("sessile-90", rows([4.0, 8.0, 12.0]));
    let v = verdict(&rep, "peak wall shear rate ratio, Mode A / Mode B");
    assert!(v.starts_with("FAIL (within a factor 2"), "{v}");
    let a = "runs/mode-a-nx33-alpha1, runs/mode-a-nx33, runs/mode-a-nx33-alpha4";
    let b = "runs/mode-b-nx33-alpha1, runs/mode-b-nx33, runs/mode-b-nx33-alpha4";
    assert!(
        v.contains(&format!("(both modes): 4.0 / 8.0 / 12.0 ({a} over {b}), bound not met across the band)")),
        "{v}"
    );
    // Every end within a factor 2 of 160: the band holds (the row itself still FAILs).
    let ratio = |rows: Vec<Row>| verdict(&judged("sessile-90", rows), "peak wall shear rate ratio").to_string();
    let v = ratio(rows([100.0, 150.0, 300.0]));
    assert!(v.ends_with("bound met across the band)"), "{v}");
    // One end past the factor: not held.
    let v = ratio(rows([100.0, 150.0, 330.0]));
    assert!(v.ends_with("bound not met across the band)"), "{v}");
    // A Mode A run missing: no band, said so.
    let mut r = rows([100.0, 150.0, 300.0]);
    r.retain(|r| !r.quantity.starts_with(&band_label(false, 1.0)));
    let v = ratio(r);
    assert!(v.ends_with("no committed sensitivity run)"), "{v}");
}

#[test]
fn a_judged_row_no_rule_qualifies_says_it_has_no_band_and_other_rows_stay_as_they_are() {
    let rep = judged(
        "capillary-wave",
        vec![
            Row::new("some other judged row", 0.1, 2, None, None).check(false, "≤ 0.05"),
            Row::new("an info row", 0.1, 2, None, None),
            Row::new("mass", 0.0, 2, None, None).invariant(false, "mass exact"),
        ],
    );
    let v = verdict(&rep, "some other judged row");
    assert!(v.starts_with("FAIL (≤ 0.05; depends on ") && v.ends_with("; no committed sensitivity run)"), "{v}");
    assert_eq!(verdict(&rep, "an info row"), "info");
    assert_eq!(verdict(&rep, "mass"), "FAIL (invariant broken: mass exact)");
    // judging again changes nothing
    let mut again = rep.clone();
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateOptions { out: dir.path().to_path_buf(), ..ValidateOptions::default() };
    judge("capillary-wave", &Ctx::new(&opts, "capillary-wave"), &mut again);
    assert_eq!(
        again.rows.iter().map(|r| &r.verdict).collect::<Vec<_>>(),
        rep.rows.iter().map(|r| &r.verdict).collect::<Vec<_>>()
    );
}

#[test]
fn a_capillary_wave_row_carries_the_band_its_band_rows_give_and_holds_only_if_all_three_meet() {
    use crate::validate::band_rows::as_band;
    let q = "rms of a/a0 − Prosperetti, whole record, density ratio 1";
    let row = |v: f64| Row::new(q, v, 4, None, Some(0.0)).check(v <= 0.05, "≤ 0.05");
    let rows = vec![row(0.04), as_band(0, row(0.03)).unwrap(), as_band(1, row(0.06)).unwrap()];
    let rep = judged("capillary-wave", rows.clone());
    let v = verdict(&rep, q);
    assert!(v.contains("α × 0.5 / × 1 / × 2") && v.contains(": 0.0300 / 0.0400 / 0.0600 ("), "{v}");
    assert!(v.ends_with("bound not met across the band)"), "{v}");
    let mut met = rows.clone();
    met[2] = as_band(1, row(0.01)).unwrap();
    let rep = judged("capillary-wave", met);
    assert!(verdict(&rep, q).ends_with("bound met across the band)"));
    // One end missing: no band, said so; the band rows themselves stay information.
    let rep = judged("capillary-wave", rows[..2].to_vec());
    assert!(verdict(&rep, q).ends_with("no committed sensitivity run)"));
    assert!(rep.rows[1].verdict.starts_with("info (band of"));
}

#[test]
fn the_capillary_waves_p_b_tests_say_why_no_alpha_band_repeats_them() {
    let pb = "period error against p_b (× the rule's), density ratio 1, T70, Δx = λ/64";
    let other = "rms of a/a0 − Prosperetti over 3 periods at Δx = λ/32, λ/44, λ/64, λ/88, density ratio 1, T70";
    let rep = judged(
        "capillary-wave",
        vec![
            Row::new(pb, 3.78, 2, None, None).check(false, "falls with p_b"),
            Row::new(other, 0.0671, 4, None, None).check(false, "falls at every refinement"),
        ],
    );
    let v = verdict(&rep, pb);
    assert!(v.contains("the row itself tests how large p_b is") && v.ends_with("no committed sensitivity run)"), "{v}");
    assert!(!verdict(&rep, other).contains("itself tests"));
}
