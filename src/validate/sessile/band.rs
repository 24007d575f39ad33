//! The sensitivity band of `sessile-90`'s judged rows: each mode at nx = 33 under the capillary
//! rule's α × 0.5 / × 1 / × 2 (docs/PHYSICS.md §3.1), its runs and their rows, which the judge
//! reads as the band (Mode B's for Mode B's rows, both modes' for the shear ratio).

use super::{band_label, measure, peak_shear, BAND_NX, BAND_RUNS};
use crate::validate::case::{CaseOutput, CaseRun};
use crate::validate::committed::Committed;
use crate::validate::data::{col, snapshot_files, window_stats};
use crate::validate::report::Row;
use crate::validate::{Ctx, RunSpec};
use std::path::Path;

/// Each mode at nx = [`BAND_NX`] under the capillary rule's α × 0.5 / × 1 / × 2 ([`BAND_RUNS`]),
/// dt scaled from the scene's, a snapshot every series row (four or more in the end window):
/// none in quick mode.
pub(super) fn band_runs(quick: bool, t_end: f64) -> Vec<CaseRun> {
    let runs = if quick { &[][..] } else { &BAND_RUNS[..] };
    runs.iter()
        .map(|&(id, alpha, mode_b)| {
            let mode = if mode_b { "b" } else { "a" };
            let mut sets =
                vec![format!("domain.nx={BAND_NX}"), "time.dt_policy=scale".into(), format!("contact.mode={mode}")];
            if alpha != crate::scene::capillary::BAND_PB_FACTOR {
                sets.push(format!("capillary_rule.alpha={alpha:.1}"));
            }
            CaseRun::new(RunSpec::new(id, "sessile-90", &sets, Some(t_end), 1), band_label(mode_b, alpha))
        })
        .collect()
}

/// A band run's rows (info; the judge reads them as the band of the judged rows): the largest
/// |θ − 90°| of the circle fit over the run, the max normal deviation and the peak wall shear rate
/// in the end window, as the nx = 65 runs' rows measure them (the windowed ones as the committed
/// report measured them where this checkout holds none of the run's snapshots).
pub(super) fn band_rows(
    ctx: &Ctx,
    (wa, wb, wtext): (f64, f64, &str),
    t_end: f64,
    (alpha, mode_b): (f64, bool),
    dir: &Path,
    out: &mut CaseOutput,
) {
    let m = measure(dir, BAND_NX, wa, wb, t_end);
    let label = band_label(mode_b, alpha);
    let circle = col(&m.rows, |r| r.theta_circle_fit.map(|v| (v - 90.0).abs()));
    let max_circle = circle.iter().map(|p| p.1).fold(f64::NAN, f64::max);
    let nd_name = format!("{label}: max normal deviation, mean over {wtext} (deg)");
    let shear_name = format!("{label}: {}", peak_shear(wtext));
    let measured = !snapshot_files(dir).is_empty();
    let committed = |name: &str| Committed::load(ctx).and_then(|c| c.value(name)).unwrap_or(f64::NAN);
    let (nd, shear) = if measured {
        let nd = window_stats(&m.normal, wa, wb).map_or(f64::NAN, |s| s.0);
        (nd, m.shear.iter().map(|p| p.1).fold(f64::NAN, f64::max))
    } else {
        (committed(&nd_name), committed(&shear_name))
    };
    let rows = &mut out.rep.rows;
    rows.push(Row::new(&format!("{label}: max |θ − 90°|, circle fit, whole run (deg)"), max_circle, 2, None, None));
    rows.push(Row::new(&nd_name, nd, 2, None, Some(0.0)));
    rows.push(Row::new(&shear_name, shear, 4, None, None));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_mode_gets_the_three_alpha_runs_at_nx33_and_quick_mode_none() {
        assert!(band_runs(true, 5.0).is_empty());
        let runs = band_runs(false, 5.0);
        let got: Vec<(String, Vec<String>)> = runs.iter().map(|r| (r.spec.id.clone(), r.spec.sets.clone())).collect();
        for (id, alpha, mode_b) in BAND_RUNS {
            let (_, sets) = got.iter().find(|g| g.0 == id).unwrap_or_else(|| panic!("no run {id}"));
            let mode = format!("contact.mode={}", if mode_b { "b" } else { "a" });
            assert!(sets.contains(&mode) && sets.contains(&"domain.nx=33".to_string()), "{id}: {sets:?}");
            // The rule's own α sets nothing; the ends set theirs.
            let alpha_set = sets.iter().find(|s| s.starts_with("capillary_rule.alpha="));
            assert_eq!(alpha_set.is_some(), alpha != 2.0, "{id}: {sets:?}");
        }
        assert_eq!(runs.len(), 6);
        assert_eq!(runs[3].label, "Mode A, nx = 33, α = 1");
    }

    #[test]
    fn a_band_run_without_snapshots_takes_its_windowed_rows_from_the_committed_report() {
        use crate::validate::report::CaseReport;
        use crate::validate::ValidateOptions;
        let dir = tempfile::tempdir().unwrap();
        let opts = ValidateOptions { out: dir.path().to_path_buf(), ..ValidateOptions::default() };
        let ctx = Ctx::new(&opts, "sessile-90");
        let run = ctx.dir.join("runs/mode-a-nx33-alpha4");
        std::fs::create_dir_all(&run).unwrap();
        let w = "t ∈ [4.3, 4.5]";
        let label = band_label(false, 4.0);
        let (nd, shear) =
            (format!("{label}: max normal deviation, mean over {w} (deg)"), format!("{label}: {}", peak_shear(w)));
        let mut committed = CaseReport::new("sessile-90", "test", false);
        committed.rows.push(Row::new(&nd, 7.24, 2, None, None));
        committed.rows.push(Row::new(&shear, 9.8888, 4, None, None));
        // another α's row of the same quantity is not this run's
        committed.rows.push(Row::new(&format!("{}: {}", band_label(false, 1.0), peak_shear(w)), 8.26, 4, None, None));
        std::fs::write(ctx.path("case.json"), serde_json::to_string(&committed).unwrap()).unwrap();
        let mut out =
            CaseOutput { rep: CaseReport::new("sessile-90", "test", false), plots: Vec::new(), tables: Vec::new() };
        band_rows(&ctx, (4.3, 4.5, w), 5.0, (4.0, false), &run, &mut out);
        let value = |q: &str| out.rep.rows.iter().find(|r| r.quantity == q).map(|r| r.value);
        assert_eq!((value(&nd), value(&shear)), (Some(7.24), Some(9.8888)));
        // without a committed report the windowed rows are NaN, not another run's
        std::fs::remove_file(ctx.path("case.json")).unwrap();
        let mut out =
            CaseOutput { rep: CaseReport::new("sessile-90", "test", false), plots: Vec::new(), tables: Vec::new() };
        band_rows(&ctx, (4.3, 4.5, w), 5.0, (4.0, false), &run, &mut out);
        assert!(out.rep.rows.iter().filter(|r| r.quantity == nd || r.quantity == shear).all(|r| r.value.is_nan()));
    }
}
