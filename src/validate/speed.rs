//! Case `speed-vs-error`: time to solution against error, (1) for the oscillation case across kernels
//! {quintic h = 1.2Δx, cubic h = 1.2Δx, Wendland C2 h = 1.5Δx} (error of the period against the
//! thesis's 0.37) and (2) for the convergence resolutions (error of D/D0 against 1.385).
//! Reuses the oscillation and convergence runs when they are there (same scene, finished) and
//! times every configuration again now (`retime`), one after the other. The
//! wider study (kernels × p_b × resolution × precision, Pareto front) is
//! `scripts/speed_vs_physical_error.sh` → reports/validation/speed-vs-physical-error/.

use super::report::{write_csv, CaseReport, Row};
use super::{convergence, oscillation, Ctx, ValidateError};
use std::path::PathBuf;

/// Kernel variants: (id, label, overrides): the default quintic and the oscillation case's
/// other kernels (`oscillation::kernel_sets`, the one list of kernels and their h).
pub fn kernels() -> Vec<(String, &'static str, Vec<&'static str>)> {
    let mut v = vec![("quintic".to_string(), "quintic h = 1.2Δx (default)", vec![])];
    v.extend(oscillation::kernel_sets().into_iter().map(|(id, label, sets)| (format!("osc-{id}"), label, sets)));
    v
}

fn scatter(
    ctx: &Ctx,
    rep: &mut CaseReport,
    name: &str,
    title: &str,
    y: &str,
    pts: &[(f64, f64, String)],
) -> Result<(), ValidateError> {
    let pts: Vec<(f64, f64, String)> = pts.iter().map(|p| (p.0, p.1.max(1e-6), p.2.clone())).collect();
    crate::plot::scatter_labeled_svg(ctx.path(name), title, "time to solution (s), timed now", y, &pts, true, true)
        .map_err(|e| ValidateError::Io(e.to_string()))?;
    rep.plots.push(name.into());
    Ok(())
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    let quick = ctx.opts.quick;
    let mut rep = CaseReport::new(
        "speed-vs-error",
        "Time to solution vs error: kernels on the oscillating drop, resolutions on relax-60",
        quick,
    );
    let mut osc = Vec::new();
    let mut csv = Vec::new();
    let osc_runs = ctx.opts.out.join("oscillation").join("runs");
    for (k, (id, label, sets)) in kernels().into_iter().enumerate() {
        // the oscillation case's runs of the same scene (quintic, cubic, wendland)
        let also = vec![osc_runs.join(id.trim_start_matches("osc-"))];
        let mut s = oscillation::spec(&id, quick, &sets);
        s.id = format!("osc-{}", id.trim_start_matches("osc-"));
        let rec = match ctx.run(&s, &also) {
            Ok(r) => r,
            Err(ValidateError::Skipped(s)) => {
                rep.not_full_because(format!("{s} not run"));
                continue;
            }
            Err(e) => return Err(e),
        };
        let cost = super::retime::retime(&s, &rec, ctx.opts.backend)?;
        let (period, amp) = oscillation::measure(&PathBuf::from(&rec.dir)).unwrap_or((f64::NAN, f64::NAN));
        let err = (period / oscillation::THESIS_PERIOD - 1.0).abs();
        rep.rows.push(Row::new(&format!("{label}: period"), period, 4, Some(oscillation::THESIS_PERIOD), None));
        rep.rows.push(Row::new(
            &format!("{label}: first-cycle amplitude"),
            amp,
            4,
            Some(oscillation::THESIS_AMPLITUDE),
            None,
        ));
        rep.rows.push(Row::new(
            &format!("{label}: time to solution (s) timed now, {} × {} steps", cost.text(), rec.steps),
            cost.time_to_solution_s,
            1,
            None,
            None,
        ));
        osc.push((cost.time_to_solution_s, err, label.to_string()));
        csv.push(vec![0.0, k as f64, cost.time_to_solution_s, cost.ms_per_step, period, err]);
        rep.runs.push(rec);
    }
    scatter(
        ctx,
        &mut rep,
        "oscillation_time_vs_error.svg",
        "Oscillating drop: time to solution vs period error (kernels)",
        "|T − 0.37| / 0.37",
        &osc,
    )?;
    let cctx = Ctx::new(ctx.opts, "convergence");
    let mut crep = CaseReport::new("convergence", "", quick);
    let (pts, _) = convergence::study(&cctx, &mut crep)?;
    if let Some(w) = crep.not_full {
        rep.not_full_because(format!("convergence: {w}"));
    }
    let conv: Vec<(f64, f64, String)> = pts.iter().map(|p| (p.1, p.3, p.0.clone())).collect();
    for (i, p) in pts.iter().enumerate() {
        rep.rows.push(Row::new(&format!("{}: |D/D0 − 1.385|/1.385 at the end", p.0), p.3, 4, None, Some(0.0)));
        csv.push(vec![1.0, i as f64, p.1, p.2, f64::NAN, p.3]);
    }
    rep.runs.extend(crep.runs);
    scatter(
        ctx,
        &mut rep,
        "convergence_time_vs_error.svg",
        "relax-60 Mode B: time to solution vs D/D0 error (resolutions)",
        "|D/D0 − 1.385| / 1.385",
        &conv,
    )?;
    write_csv(
        ctx,
        &mut rep,
        "speed_vs_error.csv",
        "study,index,time_to_solution_now_s,ms_per_step_now,period,rel_error",
        &csv,
    )?;
    rep.notes.push("Study 0 = kernels on the oscillating drop (error of the period against the thesis's 0.37); study 1 = resolutions 0.5/nx of relax-60 (error of the end D/D0 against the analytic 1.385).".into());
    rep.notes.push(convergence::retime_note());
    Ok(rep)
}
