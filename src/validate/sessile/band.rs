//! The sensitivity band of `sessile-90`'s Mode B rows: Mode B at nx = 33 under the capillary
//! rule's α × 0.5 / × 1 / × 2 (docs/PHYSICS.md §3.1), its runs and their rows, which the judge
//! reads as the band.

use super::{band_label, measure, BAND_NX, BAND_RUNS};
use crate::validate::case::{CaseOutput, CaseRun};
use crate::validate::committed::Committed;
use crate::validate::data::{col, snapshot_files, window_stats};
use crate::validate::report::Row;
use crate::validate::{Ctx, RunSpec};
use std::path::Path;

/// Mode B at nx = [`BAND_NX`] under the capillary rule's α × 0.5 / × 1 / × 2 ([`BAND_RUNS`]),
/// dt scaled from the scene's, a snapshot every series row (four or more in the end window):
/// none in quick mode.
pub(super) fn band_runs(quick: bool, t_end: f64) -> Vec<CaseRun> {
    let runs = if quick { &[][..] } else { &BAND_RUNS[..] };
    runs.iter()
        .map(|&(id, alpha)| {
            let mut sets = vec![format!("domain.nx={BAND_NX}"), "time.dt_policy=scale".into(), "contact.mode=b".into()];
            if alpha != crate::scene::capillary::BAND_PB_FACTOR {
                sets.push(format!("capillary_rule.alpha={alpha:.1}"));
            }
            CaseRun::new(RunSpec::new(id, "sessile-90", &sets, Some(t_end), 1), band_label(alpha))
        })
        .collect()
}

/// A band run's rows (info; the judge reads them as the band of Mode B's rows): the largest
/// |θ − 90°| of the circle fit over the run and the max normal deviation in the end window,
/// as Mode B's rows measure them (the normal deviation as the committed report measured it
/// where this checkout holds none of the run's snapshots).
pub(super) fn band_rows(
    ctx: &Ctx,
    (wa, wb, wtext): (f64, f64, &str),
    t_end: f64,
    alpha: f64,
    dir: &Path,
    out: &mut CaseOutput,
) {
    let m = measure(dir, BAND_NX, wa, wb, t_end);
    let label = band_label(alpha);
    let circle = col(&m.rows, |r| r.theta_circle_fit.map(|v| (v - 90.0).abs()));
    let max_circle = circle.iter().map(|p| p.1).fold(f64::NAN, f64::max);
    let nd_name = format!("{label}: max normal deviation, mean over {wtext} (deg)");
    let nd = if snapshot_files(dir).is_empty() {
        Committed::load(ctx).and_then(|c| c.value(&nd_name)).unwrap_or(f64::NAN)
    } else {
        window_stats(&m.normal, wa, wb).map_or(f64::NAN, |s| s.0)
    };
    let rows = &mut out.rep.rows;
    rows.push(Row::new(&format!("{label}: max |θ − 90°|, circle fit, whole run (deg)"), max_circle, 2, None, None));
    rows.push(Row::new(&nd_name, nd, 2, None, Some(0.0)));
}
