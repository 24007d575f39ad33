//! `index.md`: one line per case with its verdict counts, then every FAIL with its measured value
//! and reason and every pass with what it depends on, read from the cases' `case.json`.

use super::{cell, io, CaseReport, RunRecord};
use crate::validate::{ValidateError, ValidateOptions, CASES};
use std::fmt::Write as _;

/// Writes `index.md` from every `<case>/case.json` under the report root, plus cases that
/// failed in this invocation.
pub fn write_index(
    opts: &ValidateOptions,
    _reps: &[CaseReport],
    failed: &[(String, String)],
) -> Result<(), ValidateError> {
    let mut m = String::from(concat!(
        "# sphlab validation index\n\nEach case's `summary.md` has the table `quantity | sphlab | thesis | ",
        "analytic | difference | verdict`, the plots and the provenance of every run.\n\n",
        "| case | reference | full resolution | p_b and c0 | kernel | verdicts | run wall time (s) |\n|---|---|---|---|---|---|---|\n",
    ));
    let mut not_full = Vec::new();
    let mut judged = String::new();
    for c in CASES {
        let j = opts.out.join(c).join("case.json");
        let Some(rep) = std::fs::read_to_string(&j).ok().and_then(|t| serde_json::from_str::<CaseReport>(&t).ok())
        else {
            let why =
                failed.iter().find(|f| f.0 == c).map_or("not run yet".to_string(), |f| format!("failed: {}", f.1));
            let _ = writeln!(m, "| {c} | — | no | — | — | — | — |");
            not_full.push((c.to_string(), why));
            continue;
        };
        let count = |v: &str| rep.rows.iter().filter(|r| r.verdict.starts_with(v)).count();
        let (pass, fail, inv) = (count("pass"), count("FAIL"), count("invariant"));
        let records = run_records(&opts.out.join(c), &rep);
        let _ = writeln!(
            m,
            "| [{c}]({c}/summary.md) | {} | {} | {} | {} | {pass} pass{}, {fail} FAIL, {inv} invariant, {} info | {:.0} |",
            rep.reference.lines().next().unwrap_or(""),
            if rep.not_full.is_none() { "yes" } else { "no" },
            pressure_rule(&records),
            kernel_column(&records),
            pass_bands(&rep.rows),
            rep.rows.len() - pass - fail - inv,
            rep.runs.iter().map(|r| r.wall_time_s).filter(|w| w.is_finite()).sum::<f64>()
        );
        for r in rep.rows.iter().filter(|r| r.verdict.starts_with("pass") || r.verdict.starts_with("FAIL")) {
            let _ = writeln!(judged, "| {c} | {} | {} | {} |", cell(&r.quantity), cell(&r.sphlab), cell(&r.verdict));
        }
        if let Some(w) = rep.not_full {
            not_full.push((c.to_string(), w));
        }
    }
    let _ = writeln!(
        m,
        "\nVerdicts: pass and FAIL judge a result against a bound stated before measuring; invariant rows hold by \
         construction (e.g. mass with fixed particle masses) and guard the code, so they are counted apart and not as \
         passes; info rows carry no bound. Each pass and FAIL names the parameters it depends on and, where \
         committed runs give one, the result across a sensitivity band (the capillary rule's α × 0.5 and × 2, its \
         resolutions, or the background-pressure runs made before the rule, each named), with whether the bound still \
         holds there. Results held to theory or the thesis (Young's angle for both contact modes, the \
         thesis's own two-point angle beside the circle fit, the Mode A / Mode B wall-shear ratio, the trend with \
         refinement) are FAIL until the result meets them."
    );
    let _ = writeln!(
        m,
        "\n## Every pass and FAIL\n\nEach with its measured value, its bound, what it depends on and its sensitivity \
         band.\n\n| case | quantity | sphlab | verdict |\n|---|---|---|---|\n{judged}"
    );
    let _ = writeln!(
        m,
        "\nRegenerate: `sphlab validate all` (runs everything; `--t-end T` shortens the sessile-90 / relax-60 / convergence runs, `--quick` for the test-suite sizes). `--reuse` analyses finished runs of exactly the same scene and end time found under `runs/` (e.g. started by hand with the `sphlab run` commands listed in each summary.md); `--skip-missing` lists the others as not run. Particle snapshots are not committed (`.gitignore`); re-running a case recreates them, and `--rejudge` applies the verdicts again to a committed case.json without them.\n"
    );
    let _ = writeln!(
        m,
        "Beside the cases: the background-pressure sweep ([pb-sweep/summary.md](pb-sweep/summary.md), \
         `examples/analysis/pb_sweep.sh`), time to solution against physical error \
         ([speed-vs-physical-error/summary.md](speed-vs-physical-error/summary.md), \
         `examples/analysis/speed_vs_physical_error.sh`), the kernel of the capillary scenes and where p_b acts \
         ([form-and-kernel/README.md](form-and-kernel/README.md)), the shear rigidity p_b gives the \
         particles, kernel by kernel ([kernel-rigidity/README.md](kernel-rigidity/README.md)), and the \
         cross-code check's short-time test (`tests/cross_code.rs`; the whole record is the `cross-code` case).\n"
    );
    let _ = writeln!(m, "\n## Cases not run at full resolution\n");
    if not_full.is_empty() {
        let _ = writeln!(m, "None.");
    }
    for (c, w) in not_full {
        let _ = writeln!(m, "* **{c}**: {w}");
    }
    let _ = writeln!(
        m,
        "\n## Findings\n\nWhat these cases show, case by case, with the choices behind the scenes (kernel and h, the \
         background-pressure rules, where p_b acts, the time-step policy) and the investigations under each case: \
         [docs/physics-choices.md](../../docs/physics-choices.md). The equations the cases test are in \
         [docs/PHYSICS.md](../../docs/PHYSICS.md) (§9 for the scenes, §10 for the contact-angle measures)."
    );
    let _ = writeln!(
        m,
        "\nThe column p_b and c0 reads each case's run records (`runs/<id>/summary.json`): \"the capillary rule\" when \
         its runs carry the rule's constants (docs/PHYSICS.md §3.1), \"the scene's own\" when its scenes are ones the \
         rule does not apply to (the impact: water's c0, p_b = B; PySPH's rod: PySPH's parameters), \"**stale**\" for \
         a capillary case whose runs were made under the per-scene background pressures before it (its numbers do \
         not describe the current code). The column kernel says \"the scene's\" when every run took the kernel \
         and h its built-in scene takes now or asked for another (`kernel.kind=` or `kernel.h_ratio=`), and \
         \"**stale**\" with the runs' kernel when one took another without asking (the scene's kernel was changed \
         after the runs)."
    );
    std::fs::create_dir_all(&opts.out).map_err(|e| io(&opts.out, e))?;
    let p = opts.out.join("index.md");
    std::fs::write(&p, m).map_err(|e| io(&p, e))
}

/// The `summary.json` of each of the case's runs: where the run is (a reused run may sit in
/// another case's directory), else the case's own `runs/<id>`.
fn run_records(case_dir: &std::path::Path, rep: &CaseReport) -> Vec<(String, serde_json::Value)> {
    rep.runs.iter().filter_map(|r| Some((r.command.clone(), run_summary(case_dir, r)?))).collect()
}

/// The `summary.json` of run `run` of the case in `case_dir`: at the run's recorded directory,
/// else under the case's `runs/<id>/` (where a committed report keeps it).
pub(in crate::validate) fn run_summary(case_dir: &std::path::Path, run: &RunRecord) -> Option<serde_json::Value> {
    [std::path::PathBuf::from(&run.dir), case_dir.join("runs").join(&run.id)].iter().find_map(|d| summary_at(d))
}

/// The `summary.json` of the run in `dir`, parsed.
pub(in crate::validate) fn summary_at(dir: &std::path::Path) -> Option<serde_json::Value> {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).ok()?).ok()
}

/// The kernel section (kind and h) built-in `scene` takes now, as a run's record writes it.
pub(in crate::validate) fn kernel_now(scene: &str) -> Option<serde_json::Value> {
    crate::scene::builtin::builtin(scene).and_then(|s| serde_json::to_value(s.kernel).ok())
}

/// How a case's runs set p_b and c0, read from their records: "the capillary rule" when one
/// carries the rule's section; the scene's own when every run's scene is one the rule does not
/// apply to (a built-in without the rule, e.g. the impact, or a scene file, e.g. PySPH's rod);
/// else stale (a capillary built-in measured before the rule, or no record to tell).
fn pressure_rule(records: &[(String, serde_json::Value)]) -> &'static str {
    let records: Vec<&serde_json::Value> = records.iter().map(|r| &r.1).collect();
    let ruled_scene = |v: &serde_json::Value| {
        v["scene"].as_str().and_then(crate::scene::builtin::builtin).is_some_and(|s| s.capillary_rule.is_some())
    };
    if records.iter().any(|v| v["parameters"]["capillary_rule"].is_object()) {
        "the capillary rule"
    } else if !records.is_empty() && !records.iter().any(|v| ruled_scene(v)) {
        "the scene's own (the capillary rule does not apply)"
    } else {
        "**stale**: per-scene p_b (before the rule)"
    }
}

/// Whether a case's runs took the kernel and h their built-in scenes take now: "the scene's"
/// when every run of a built-in scene did, or set its kernel itself (`kernel.kind=` or
/// `kernel.h_ratio=` in its command: a deliberate variant, as the oscillating drop's other
/// kernels are); a scene file keeps its own. Else stale, naming each scene with a run of another
/// kernel it did not ask for.
fn kernel_column(records: &[(String, serde_json::Value)]) -> String {
    if records.is_empty() {
        return "—".into();
    }
    let label = |k: &serde_json::Value| {
        format!("{} h = {}Δx", k["kind"].as_str().unwrap_or("?"), k["h_ratio"].as_f64().unwrap_or(f64::NAN))
    };
    let mut stale: Vec<String> = Vec::new();
    for (command, v) in records {
        let Some(name) = v["scene"].as_str() else { continue };
        let Some(now) = kernel_now(name) else {
            continue;
        };
        let asked = command.contains("kernel.kind=") || command.contains("kernel.h_ratio=");
        if v["parameters"]["kernel"] != now && !asked {
            let line =
                format!("{name} runs with {} (the scene now: {})", label(&v["parameters"]["kernel"]), label(&now));
            if !stale.contains(&line) {
                stale.push(line);
            }
        }
    }
    if stale.is_empty() {
        "the scene's".into()
    } else {
        format!("**stale**: {}", stale.join("; "))
    }
}

/// How the passes stand against their sensitivity bands (as `Row::qualify` words them):
/// " (h held across their band, n not, z without one)", with ", s shown one they are not judged
/// by" where a pass carries a band without a verdict on it; nothing without a pass.
fn pass_bands(rows: &[super::Row]) -> String {
    let passes: Vec<&str> = rows.iter().filter(|r| r.is_pass()).map(|r| r.verdict.as_str()).collect();
    if passes.is_empty() {
        return String::new();
    }
    let n = |what: &str| passes.iter().filter(|v| v.contains(what)).count();
    let (held, not, none) =
        (n("bound met across the band"), n("bound not met across the band"), n("no committed sensitivity run"));
    let shown = passes.iter().filter(|v| v.contains("; sensitivity ") && !v.contains("met across the band")).count();
    let shown = if shown > 0 { format!(", {shown} shown one they are not judged by") } else { String::new() };
    format!(" ({held} held across their band, {not} not, {none} without one{shown})")
}

#[cfg(test)]
mod tests {
    use super::super::{Band, Row};
    use super::{kernel_column, pass_bands};
    use serde_json::json;

    fn record(scene: &str, kind: &str, h: f64) -> (String, serde_json::Value) {
        let v = json!({ "scene": scene, "parameters": { "kernel": { "kind": kind, "h_ratio": h } } });
        (format!("sphlab run {scene} --t-end 5"), v)
    }

    fn with_set(mut r: (String, serde_json::Value), set: &str) -> (String, serde_json::Value) {
        r.0.push_str(&format!(" --set {set}"));
        r
    }

    #[test]
    fn a_case_is_stale_when_a_run_took_another_kernel_than_its_scenes_without_asking() {
        let k = crate::scene::builtin::builtin("relax-60").unwrap().kernel;
        let kind = serde_json::to_value(k.kind).unwrap();
        let kind = kind.as_str().unwrap();
        let other = if kind == "quintic" { "cubic-spline" } else { "quintic" };
        assert_eq!(kernel_column(&[record("relax-60", kind, k.h_ratio)]), "the scene's");
        // a run that asked for another kernel is a variant (the oscillating drop's case)
        let variant = with_set(record("relax-60", other, 1.2), &format!("kernel.kind={other}"));
        assert_eq!(kernel_column(&[variant, record("relax-60", kind, k.h_ratio)]), "the scene's");
        // one run of another kernel that did not ask for it makes the case stale, beside current ones
        let stale = kernel_column(&[record("relax-60", kind, k.h_ratio), record("relax-60", other, k.h_ratio)]);
        assert!(
            stale.starts_with("**stale**: relax-60 runs with") && stale.contains(other) && stale.contains(kind),
            "{stale}"
        );
        // the same kind at another h is another kernel
        assert!(kernel_column(&[record("relax-60", kind, k.h_ratio + 0.3)]).starts_with("**stale**"));
        // each scene is judged by its own kernel
        let drop = crate::scene::builtin::builtin("oscillating-drop").unwrap().kernel;
        let drop_kind = serde_json::to_value(drop.kind).unwrap();
        let mixed =
            [record("oscillating-drop", drop_kind.as_str().unwrap(), drop.h_ratio), record("relax-60", other, 1.2)];
        let col = kernel_column(&mixed);
        assert!(col.starts_with("**stale**: relax-60 runs with") && !col.contains("oscillating-drop"), "{col}");
        // a scene file keeps its own kernel; no records, nothing to say
        assert_eq!(kernel_column(&[record("/some/scene.toml", other, 1.0)]), "the scene's");
        assert_eq!(kernel_column(&[]), "—");
    }

    #[test]
    fn passes_are_counted_by_how_their_band_stands_and_fails_are_not() {
        let band = |holds| Band { varied: "α".into(), values: vec![], source: "s".into(), holds: Some(holds) };
        let mut rows: Vec<Row> = (0..5).map(|k| Row::new(&format!("q{k}"), 0.0, 1, None, None)).collect();
        rows[0] = rows[0].clone().check(true, "c");
        rows[0].qualify("d", Some(&band(true)));
        rows[1] = rows[1].clone().check(true, "c");
        rows[1].qualify("d", Some(&band(false)));
        rows[2] = rows[2].clone().check(true, "c");
        rows[2].qualify("d", None);
        rows[3] = rows[3].clone().check(false, "c");
        rows[3].qualify("d", Some(&band(false)));
        assert_eq!(pass_bands(&rows), " (1 held across their band, 1 not, 1 without one)");
        assert_eq!(pass_bands(&rows[3..]), "");
        // A pass shown a band it is not judged by is counted apart.
        rows[4] = rows[4].clone().check(true, "c");
        rows[4].qualify("d", Some(&Band { holds: None, ..band(true) }));
        assert_eq!(
            pass_bands(&rows),
            " (1 held across their band, 1 not, 1 without one, 1 shown one they are not judged by)"
        );
        // A pass never qualified (a report not judged) is counted in none of them.
        rows.push(Row::new("q5", 0.0, 1, None, None).check(true, "c"));
        assert!(pass_bands(&rows).ends_with("1 without one, 1 shown one they are not judged by)"));
    }
}
