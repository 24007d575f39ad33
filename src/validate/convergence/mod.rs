//! Case `convergence` (docs/PHYSICS.md §9(d), thesis §4.2.4): relax-60, Mode B, no-slip, at
//! Δx = 0.5/33 (below the thesis's range) and the thesis's 0.5/45, 0.5/65, 0.5/85, 0.5/105 with
//! `time.dt_policy = "scale"` (7e-5 at 65; the viscous limit binds, so dt ∝ Δx²). D/D0 and θ at
//! the end against the analytic cap, realisations from jittered starts at the coarser
//! resolutions (`realisations`), observed orders and Richardson estimates, the lattice runs
//! under the tangential stress form (`tangential`), and time to solution against error.
//! Thesis: all but 0.5/45 converge in D/D0 and θ.

use super::data::{col, read_series};
use super::relax::{analytic_spread, wall_spread};
use super::report::{plot, write_csv, CaseReport, Row, RunRecord};
use super::retime::Retimed;
use super::sessile::shear_window;
use super::{Ctx, RunSpec, ValidateError};
use crate::plot::{PlotSpec, RefLine, Series};
use std::path::PathBuf;

mod band_density;
mod realisations;
mod tangential;
pub use band_density::relax_last_state;
use realisations::{band_density_row, capillary_rule_dir, end_values, End};
pub use tangential::TANGENTIAL_NX;

/// Resolutions (particles across 0.5) of the full study.
pub const FULL_NX: [u32; 5] = [33, 45, 65, 85, 105];
/// Resolutions of the quick study.
pub const QUICK_NX: [u32; 3] = [20, 26, 33];

/// The background pressure of the long runs at `nx`: the capillary rule
/// ([`crate::scene::capillary::background_pressure`]) with relax-60's kernel.
pub fn pb_for(nx: u32) -> f64 {
    let s = crate::scene::builtin::relax_60();
    crate::scene::capillary::background_pressure(1.0, &s.kernel, 0.5 / nx as f64)
}

/// The overrides at `nx`: the capillary rule's p_b and c0 at that resolution
/// ([`crate::scene::capillary::sets_at`]) and `time.dt_policy = "scale"` from relax-60's own dt
/// at nx = 65 (dt follows the tightest limit); quick: from 1.4e-4 at 26.
fn dt_sets(nx: u32, quick: bool) -> Vec<String> {
    let mut sets = crate::scene::capillary::sets_at(&crate::scene::builtin::relax_60(), nx);
    sets.push("time.dt_policy=scale".into());
    if quick {
        sets.extend(["time.dt=1.4e-4".into(), "time.dt_nx=26".into()]);
    }
    sets
}

/// dt at `nx` (see [`dt_sets`]).
pub fn dt_for(nx: u32, quick: bool) -> f64 {
    let base = crate::scene::builtin::builtin("relax-60").expect("built-in");
    let scene = crate::scene::overrides::apply_overrides(&base, &dt_sets(nx, quick)).expect("valid convergence scene");
    crate::scene::dt_policy::effective_dt(&scene)
}

/// The run spec at `nx`.
pub fn spec(nx: u32, quick: bool, t_end: f64) -> RunSpec<'static> {
    let mut sets = dt_sets(nx, quick);
    if quick {
        sets.push("output.every=100".into());
    } else {
        // keep a series row every ~0.035 time units at every resolution
        sets.push(format!("output.every={}", (0.035 / dt_for(nx, quick)).round() as u64));
    }
    RunSpec::new(format!("nx{nx}"), "relax-60", &sets, Some(t_end), if quick { 0 } else { 10 })
}

/// Runs (or reuses) one of the case's runs; a run skipped for CPU time (`--skip-missing`, `--only`)
/// is None and says so in `rep`.
fn run_or_skip(
    ctx: &Ctx,
    rep: &mut CaseReport,
    spec: &RunSpec,
    also: &[PathBuf],
) -> Result<Option<RunRecord>, ValidateError> {
    match ctx.run(spec, also) {
        Ok(r) => Ok(Some(r)),
        Err(ValidateError::Skipped(id)) => {
            rep.not_full_because(format!("{id} not run (CPU time)"));
            Ok(None)
        }
        Err(e) => Err(e),
    }
}

/// The lattice runs' end states by resolution, coarse to fine.
pub type Ends = Vec<(u32, End)>;

/// One point of the speed/error study: `(label, time to solution s, ms/step, |D/D0 − analytic|/analytic,
/// θ error deg)`, the cost measured now in this process ([`super::retime`]).
pub type Point = (String, f64, f64, f64, f64);

/// Runs (or reuses) the lattice runs and returns their points and end states (by resolution,
/// coarse to fine); fills `rep`.
pub fn study(ctx: &Ctx, rep: &mut CaseReport) -> Result<(Vec<Point>, Ends), ValidateError> {
    let quick = ctx.opts.quick;
    let t_end = ctx.opts.long_t_end(0.3);
    let (wa, wb, wtext) = shear_window(t_end);
    let d_an = analytic_spread();
    let nxs: Vec<u32> = if quick { QUICK_NX.to_vec() } else { FULL_NX.to_vec() };
    let mut spread =
        PlotSpec::new("Convergence: D/D0 at the wall vs time (§4.2.4)", "t (nondimensional)", "D/D0 at the wall");
    let mut angle = PlotSpec::new("Convergence: θ (circle fit) vs time (§4.2.4)", "t (nondimensional)", "θ (degrees)");
    let mut pts = Vec::new();
    let mut csv = Vec::new();
    let mut ends = Vec::new();
    for nx in nxs {
        let s = spec(nx, quick, t_end);
        let relax_dir = ctx.opts.out.join("relax-60").join("runs").join("b-noslip");
        let Some(rec) = run_or_skip(ctx, rep, &s, &[relax_dir, capillary_rule_dir(&ctx.opts.out, nx, None)])? else {
            continue;
        };
        let cost = super::retime::retime(&s, &rec, ctx.opts.backend)?;
        let rows = read_series(&PathBuf::from(&rec.dir));
        let d = wall_spread(&rows, 0.5 / nx as f64);
        let th = col(&rows, |r| r.theta_circle_fit);
        spread.series.push(Series::line(format!("Δx = 0.5/{nx}"), d.clone()));
        angle.series.push(Series::line(format!("Δx = 0.5/{nx}"), th.clone()));
        let end = end_values(&PathBuf::from(&rec.dir), nx, wa, wb);
        let (d_end, th_end) = (end.spread, end.theta);
        ends.push((nx, end));
        let err = (d_end / d_an - 1.0).abs();
        resolution_rows(rep, nx, &end, &rec, &cost, &wtext, d_an);
        csv.push(vec![
            nx as f64,
            dt_for(nx, quick),
            pb_for(nx),
            d_end,
            th_end,
            err,
            rec.wall_time_s,
            rec.ms_per_step,
            cost.ms_per_step,
            cost.time_to_solution_s,
        ]);
        pts.push((format!("relax-60 nx={nx}"), cost.time_to_solution_s, cost.ms_per_step, err, (th_end - 60.0).abs()));
        rep.runs.push(rec);
    }
    let end_list: Vec<(f64, f64, f64)> = csv.iter().map(|r| (r[0], r[4], r[3])).collect();
    end_notes(rep, &end_list, &wtext, d_an);
    spread.refs = vec![RefLine::horizontal(format!("analytic equilibrium {d_an:.3}"), d_an)];
    angle.refs = vec![RefLine::horizontal("target 60°", 60.0)];
    plot(ctx, rep, "spread_factor_vs_resolution.svg", &spread)?;
    plot(ctx, rep, "angle_vs_resolution.svg", &angle)?;
    write_csv(
        ctx,
        rep,
        "convergence.csv",
        "nx,dt,p_b,spread_end,theta_circle_end,spread_rel_error,wall_time_s,ms_per_step,ms_per_step_now,time_to_solution_now_s",
        &csv,
    )?;
    Ok((pts, ends))
}

/// The rows of one lattice resolution: its end values, the thesis's two-point angle, the density
/// error, the run's own wall time and the time to solution timed now.
fn resolution_rows(rep: &mut CaseReport, nx: u32, end: &End, rec: &RunRecord, cost: &Retimed, wtext: &str, d_an: f64) {
    let (d_end, th_end) = (end.spread, end.theta);
    rep.rows.push(Row::new(&format!("Δx = 0.5/{nx}: D/D0 at the wall, mean over {wtext}"), d_end, 3, None, Some(d_an)));
    rep.rows.push(Row::new(
        &format!("Δx = 0.5/{nx}: θ circle fit, mean over {wtext} (deg)"),
        th_end,
        2,
        None,
        Some(60.0),
    ));
    rep.rows.push(Row::new(
        &format!("Δx = 0.5/{nx}: θ by the thesis's two-point metric (rows 1–2 at the wall), mean over {wtext} (deg)"),
        end.two_point,
        2,
        None,
        Some(60.0),
    ));
    rep.rows.push(Row::new(&format!("Δx = 0.5/{nx}: max |ρ/ρ0 − 1| for t ≥ 1"), end.density, 4, None, None));
    if let Some(b) = end.band {
        rep.rows.push(band_density_row(&format!("Δx = 0.5/{nx}"), &[b]));
    }
    rep.rows.push(Row::new(
        &format!("Δx = 0.5/{nx}: the run's own wall time (s) at {:.2} ms/step (its machine and load)", rec.ms_per_step),
        rec.wall_time_s,
        1,
        None,
        None,
    ));
    rep.rows.push(Row::new(
        &format!("Δx = 0.5/{nx}: time to solution (s) timed now, {} × {} steps", cost.text(), rec.steps),
        cost.time_to_solution_s,
        1,
        None,
        None,
    ));
}

/// The notes on the background pressure at each resolution and on the spread of the end values;
/// `end_list` holds `(nx, θ, D/D0)` by resolution.
fn end_notes(rep: &mut CaseReport, end_list: &[(f64, f64, f64)], wtext: &str, d_an: f64) {
    let pbs: Vec<String> = end_list.iter().map(|e| format!("{:.2} at nx = {}", pb_for(e.0 as u32), e.0)).collect();
    rep.notes.push(format!(
        "Background pressure: the capillary rule p_b = 2·σ|∇C|_max/2 with c0 from σ|∇C|_max/2 = 1 % of ρ0c0² \
         (docs/PHYSICS.md §3.1, ../capillary-rule/README.md): p_b {}. Under the earlier rule p_b = σ/(2Δx) \
         at c0 = 20, θ ended at 61.6°, 66.5°, 68.8°, 70.3° at nx = 45, 65, 85, 105 (pb-check/README.md).",
        pbs.join(", ")
    ));
    if end_list.len() >= 2 {
        let span = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
            end_list.iter().map(f).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let ((t0, t1), (d0, d1)) = (span(&|e| e.1), span(&|e| e.2));
        let list: Vec<String> =
            end_list.iter().map(|(nx, th, d)| format!("nx = {nx}: θ {th:.2}°, D/D0 {d:.3}")).collect();
        let trend = if end_list.len() >= 3 && end_list.windows(2).all(|w| w[1].1 > w[0].1) {
            "; θ rises with every refinement, away from 60°"
        } else {
            ""
        };
        rep.notes.push(format!(
            "End values ({wtext}): {}. Across the resolutions θ spans {t0:.2}–{t1:.2}° ({:.2}°) and D/D0 {d0:.3}–{d1:.3} \
             ({:.1} % of {d_an:.3}){trend}.",
            list.join("; "),
            t1 - t0,
            100.0 * (d1 - d0) / d_an
        ));
    }
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    let quick = ctx.opts.quick;
    let mut rep = CaseReport::new(
        "convergence",
        "Thesis §4.2.4 (docs/PHYSICS.md §9(d)): resolution study of relax-60, Mode B, no-slip",
        quick,
    );
    let t_end = ctx.opts.long_t_end(0.3);
    if !quick && t_end < 5.0 {
        rep.not_full_because(format!("t_end = {t_end} instead of the thesis's 5 (CPU time)"));
    }
    let (pts, lattice) = study(ctx, &mut rep)?;
    if !quick {
        realisations::add(ctx, &mut rep, &lattice, t_end)?;
        tangential::add(ctx, &mut rep, &lattice, t_end)?;
    }
    let sc: Vec<(f64, f64, String)> = pts.iter().map(|p| (p.1, p.3.max(1e-6), p.0.clone())).collect();
    let path = ctx.path("time_vs_error.svg");
    crate::plot::scatter_labeled_svg(
        &path,
        "Convergence: time to solution vs |D/D0 − 1.385|/1.385",
        "time to solution (s), timed now",
        "relative error of D/D0",
        &sc,
        true,
        true,
    )
    .map_err(|e| ValidateError::Io(e.to_string()))?;
    rep.plots.push("time_vs_error.svg".into());
    rep.notes.push(retime_note());
    rep.notes.push("Thesis: every resolution but 0.5/45 converges in D/D0 and θ (no numbers given).".into());
    rep.notes.push("D/D0 at the wall: the first-row D/D0 of series.csv carried down Δx/2 along the row's circle-fit angle (relax::wall_spread; see ../relax-60/summary.md).".into());
    Ok(rep)
}

/// How the time-to-solution rows and plots are measured (shared with `speed-vs-error`).
pub fn retime_note() -> String {
    format!(
        "Time to solution: each configuration's scene stepped {} times {} steps in this `validate` process, one \
         configuration after the other, relaxation off (../provenance.json names the machine and date); the median \
         ms/step times the long run's steps. The long runs' own wall times (the Runs table) come from machines and \
         loads of their own and are not compared.",
        super::retime::RETIME_REPEATS,
        super::retime::RETIME_STEPS
    )
}
