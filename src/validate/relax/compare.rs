//! The relax-60 rows across runs: each mode's end angle approached from both sides, and Mode B
//! at the thesis's own dt against the scaled dt (when a finished run of it exists).

use super::{analytic_spread, wall_spread, Variant};
use crate::plot::{PlotSpec, Series};
use crate::validate::data::{col, read_series, window_stats};
use crate::validate::report::{CaseReport, Row};
use crate::validate::sessile::geometry;
use crate::validate::{Ctx, RunSpec};

/// One variant's end angle: (id, label, start angle, its 90° counterpart, circle-fit angle as a
/// mean over the end window).
pub(super) type EndAngle = (&'static str, &'static str, f64, Option<&'static str>, f64);

/// Each mode's end angle approached from both sides: the no-slip runs from 90° (advancing) and
/// from [`super::START_BELOW_DEG`] (receding). Both ends on the same side of 60° put the model's
/// own equilibrium off 60°; ends on either side bracket 60° and their spread is pinning
/// (hysteresis). Mode B's midpoint is checked against 60°; for an equilibrium off 60° the note
/// gives cos θ / cos 60°, the fraction of the wall's tension difference that the model's
/// equilibrium shows. Which variants are held to 60° is [`Variant::held_to_young`].
pub(super) fn two_starts(end_angle: &[EndAngle], wtext: &str, rep: &mut CaseReport) {
    let variants = super::variants();
    for &(_, _, start, from_90, lo) in end_angle {
        let Some(above) = from_90 else { continue };
        let Some(&(_, mode, _, _, hi)) = end_angle.iter().find(|e| e.0 == above) else { continue };
        let (mid, half) = (0.5 * (hi + lo), 0.5 * (hi - lo).abs());
        let row = Row::new(
            &format!(
                "{mode}: end angle approached from both sides, midpoint − 60° (circle fit, mean over {wtext}; deg)"
            ),
            mid - 60.0,
            2,
            None,
            Some(0.0),
        )
        .sphlab_text(format!("{:.2} (from {start}°: {lo:.2}°, from 90°: {hi:.2}°)", mid - 60.0));
        let held = variants.iter().find(|v| v.id == above).is_some_and(Variant::held_to_young);
        rep.rows.push(if held {
            row.check((mid - 60.0).abs() < 3.0, "|midpoint − 60°| < 3°: the model's equilibrium, from either side")
        } else {
            row
        });
        let young = 60f64.to_radians().cos();
        let reading = if lo.min(hi) <= 60.0 && lo.max(hi) >= 60.0 {
            format!(
                "the two starts bracket 60°: the contact line stops within ±{half:.1}° of {mid:.1}°, pinning (contact-angle hysteresis) about the right equilibrium"
            )
        } else {
            format!(
                "both starts end on the same side of 60°, so the model's own equilibrium is off 60°, near {mid:.1}° (cos θ = {:.3} = {:.2} × Young's {young:.1}; mode-a-check/README.md, tests/force_balance.rs), with ±{half:.1}° of hysteresis: not a pinned contact line",
                mid.to_radians().cos(),
                mid.to_radians().cos() / young
            )
        };
        rep.notes.push(format!(
            "{mode}, from {start}° (an equal-area cap) and from 90°: {lo:.2}° and {hi:.2}°: {reading} (starts from 60° and other resolutions: start-angle/README.md)."
        ));
    }
}

/// `y` of the piecewise-linear series `pts` at `t` (None outside it).
fn interpolate(pts: &[(f64, f64)], t: f64) -> Option<f64> {
    let k = pts.partition_point(|p| p.0 < t);
    let (a, b) = (pts.get(k.checked_sub(1)?)?, pts.get(k)?);
    Some(if b.0 > a.0 { a.1 + (b.1 - a.1) * (t - a.0) / (b.0 - a.0) } else { b.1 })
}

/// Mode B no-slip at the thesis's own dt = 7e-5 (`runs/b-noslip-dt7e-5`, the built-in's dt at
/// any nx), when a finished run of it exists (it is never started here: 1.7× the steps of the
/// scaled run): its end values, and how far its circle-fit angle lies from the scaled-dt run's
/// early (t ≤ 0.5) and late (t ≥ 1).
pub(super) fn dt_comparison(
    ctx: &Ctx,
    nx: u32,
    t_end: f64,
    (wa, wb, wtext): (f64, f64, &str),
    scaled: &[(f64, f64)],
    rep: &mut CaseReport,
    angle: &mut PlotSpec,
) {
    let spec = RunSpec::new("b-noslip-dt7e-5", "relax-60", &ctx.opts.long_sets("relax-60"), Some(t_end), 2);
    let dir = ctx.dir.join("runs").join(&spec.id);
    let Ok(scene) = spec.scene() else { return };
    let Some(rec) = crate::validate::RunRecord::reuse(&dir, &scene, Some(t_end), &spec.command(&dir)) else {
        return;
    };
    let rows = read_series(&dir);
    let circle = col(&rows, |r| r.theta_circle_fit.map(|v| v - 60.0));
    let area = col(&rows, |r| r.theta_area.map(|v| v - 60.0));
    let d = wall_spread(&rows, geometry(nx).0);
    let label = "Mode B, no-slip at dt = 7e-5";
    angle.series.push(Series::line(format!("{label}: circle fit"), circle.clone()));
    if let Some((m, sd, n)) = window_stats(&d, wa, wb) {
        rep.rows.push(
            Row::new(&format!("{label}: D/D0 at the wall, mean over {wtext}"), m, 3, None, Some(analytic_spread()))
                .sphlab_text(format!("{m:.3} ± {sd:.3} (n = {n})")),
        );
    }
    for (name, pts) in [("circle fit", &circle), ("area inversion", &area)] {
        if let Some((m, sd, n)) = window_stats(pts, wa, wb) {
            rep.rows.push(
                Row::new(&format!("{label}: θ − 60°, {name}, mean over {wtext} (deg)"), m, 2, None, Some(0.0))
                    .sphlab_text(format!("{m:.2} ± {sd:.2} (n = {n})")),
            );
        }
    }
    let gap = |keep: &dyn Fn(f64) -> bool| {
        circle
            .iter()
            .filter(|p| keep(p.0))
            .filter_map(|p| interpolate(scaled, p.0).map(|q| (q - p.1).abs()))
            .fold(0.0, f64::max)
    };
    let (early, late) = (gap(&|t| t <= 0.5), gap(&|t| t >= 1.0));
    rep.notes.push(format!(
        "dt: Mode B no-slip at the thesis's dt = 7e-5 against the scaled dt = {:.4e} (nx = {nx}): the circle-fit angles differ by at most {early:.2}° for t ≤ 0.5 and by up to {late:.2}° for t ≥ 1 (a test of the same at nx = 20: tests/scenes.rs `relax_60_angle_does_not_depend_on_dt`; runs at other dt and in f32: dt-check/README.md).",
        crate::validate::convergence::dt_for(nx, false)
    ));
    rep.runs.push(rec);
}
