//! Case `oscillation` (PHYSICS.md §9(a), thesis §4.2.1 / Fig. 4.1): the oscillating 2D drop.
//! Period and first-cycle amplitude of the liquid centroid x_c(t) by
//! [`crate::diagnostics::oscillation`], against the thesis (0.37 / 0.012) and the analytic
//! mode-2 period (0.2945 inviscid; ≈ 0.31–0.35 with viscous damping).

use super::data::{col, read_series};
use super::report::{plot, CaseReport, Row};
use super::{Ctx, RunSpec, ValidateError};
use crate::diagnostics::{drop_mode2_period, oscillation};
use crate::plot::{PlotSpec, RefLine, Series};

/// Thesis Fig. 4.1: period and amplitude.
pub const THESIS_PERIOD: f64 = 0.37;
/// Thesis first-cycle amplitude.
pub const THESIS_AMPLITUDE: f64 = 0.012;
/// Viscous estimate band of the period (§9(a): inner-fluid damping 0.31, both fluids 0.35).
pub const VISCOUS_BAND: (f64, f64) = (0.31, 0.35);
/// The drop must return to a circle: mean centroid over t ≥ `LATE_T` within `LATE_TOL` of
/// 4R/(3π) = 0.0796 (with p_b = B the cubic-spline drop settled at 0.084).
pub const LATE_T: f64 = 0.4;
/// See [`LATE_T`].
pub const LATE_TOL: f64 = 0.002;
/// The other kernels' periods must lie within this fraction of the quintic's.
pub const KERNEL_PERIOD_TOL: f64 = 0.15;
/// The default scene's period must lie within this fraction of the thesis's 0.37.
pub const THESIS_PERIOD_TOL: f64 = 0.05;
/// The default scene's first-cycle amplitude must lie within this fraction of the thesis's 0.012.
pub const THESIS_AMPLITUDE_TOL: f64 = 0.2;

/// The smoothing length of each kernel on this case (`kernel.h_ratio` overrides), chosen by the
/// period against the quintic's at nx = 30, p_b = σ/(2Δx) = 30:
/// * quintic h = 1.2Δx (support 3.6Δx): the scene's default (amplitude and spurious speed, see
///   `scene::builtin::oscillating_drop`); h = Δx kept as an info run;
/// * cubic spline h = 1.2Δx (support 2.4Δx): the thesis's choice for §4.2.2–4.2.4 (PHYSICS.md §7.4);
///   period 0.316, −14 % from the quintic's 0.366 (h = 1.5Δx was no closer: 0.320);
/// * Wendland C2 h = 1.5Δx (support 3Δx): 0.358, −2 %; at h = 1.3Δx (support 2.6Δx) the drop
///   rings 16 % fast, outside the 15 % of [`KERNEL_PERIOD_TOL`] (kept as an info run);
/// * Johnson quadratic h = 2Δx (support 4Δx): 0.338, −8 %; at h = 1.5Δx 0.268 (−27 %) and at
///   h = 1.2Δx 0.206 (−44 %), both kept as info runs (its gradient does not vanish at r → 0);
/// * truncated Gaussian h = 1.2Δx (support 3.6Δx, as the quintic): 0.364, −0.5 % (5d2f8fb's tree).
pub fn kernel_sets() -> [(&'static str, &'static str, Vec<&'static str>); 4] {
    [
        ("cubic", "cubic spline h = 1.2Δx", vec!["kernel.kind=cubic-spline", "kernel.h_ratio=1.2"]),
        ("wendland", "Wendland C2 h = 1.5Δx (support 3Δx)", vec!["kernel.kind=wendland-c2", "kernel.h_ratio=1.5"]),
        ("johnson", "Johnson quadratic h = 2Δx (support 4Δx)", vec!["kernel.kind=johnson", "kernel.h_ratio=2.0"]),
        (
            "gaussian",
            "truncated Gaussian h = 1.2Δx (support 3.6Δx)",
            vec!["kernel.kind=gaussian", "kernel.h_ratio=1.2"],
        ),
    ]
}
/// Accepted SPH period band (§9(a) "expect SPH in [0.30, 0.37]", widened by 0.01 each side).
pub const PERIOD_BAND: (f64, f64) = (0.29, 0.38);

/// Quick-mode overrides: 24×24 quarter (Δx = 1/48, 9 particles per radius), relax t = 0.1
/// (at 20×20 the second maximum is damped into the noise and no period is found).
pub fn quick_sets() -> Vec<String> {
    vec!["domain.nx=24".into(), "relax.t=0.1".into()]
}

/// Period and first-cycle amplitude of a run directory's centroid record:
/// [`oscillation`], or, when the record resolves fewer than two maxima above its mean (a
/// strongly damped coarse run), [`half_cycle`].
pub fn measure(dir: &std::path::Path) -> Option<(f64, f64)> {
    let rows = read_series(dir);
    let t: Vec<f64> = rows.iter().map(|r| r.t).collect();
    let x: Vec<f64> = rows.iter().map(|r| r.centroid_x).collect();
    oscillation(&t, &x).map(|o| (o.period, o.amplitude_first_cycle)).or_else(|| half_cycle(&t, &x))
}

/// Fallback: period = 2 × (time of the first minimum after the first maximum − time of that
/// maximum), amplitude = ½(max − min), on a 5-sample moving average.
pub fn half_cycle(t: &[f64], x: &[f64]) -> Option<(f64, f64)> {
    let n = t.len().min(x.len());
    if n < 7 {
        return None;
    }
    let s: Vec<f64> = (0..n)
        .map(|i| {
            x[i.saturating_sub(2)..(i + 3).min(n)].iter().sum::<f64>() / ((i + 3).min(n) - i.saturating_sub(2)) as f64
        })
        .collect();
    let imax = (1..n - 1).find(|&i| s[i] >= s[i - 1] && s[i] > s[i + 1])?;
    let imin = (imax + 1..n - 1).find(|&i| s[i] <= s[i - 1] && s[i] < s[i + 1])?;
    Some((2.0 * (t[imin] - t[imax]), 0.5 * (s[imax] - s[imin])))
}

/// The spec of one oscillation run with extra overrides.
pub fn spec(id: &str, quick: bool, extra: &[&str]) -> RunSpec<'static> {
    let mut sets = if quick { quick_sets() } else { vec![] };
    sets.extend(extra.iter().map(|s| s.to_string()));
    RunSpec::new(id, "oscillating-drop", &sets, None, 0)
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    let quick = ctx.opts.quick;
    let mut rep = CaseReport::new("oscillation", "Thesis §4.2.1, Fig. 4.1 (PHYSICS.md §9(a)): oscillating drop", quick);
    let analytic = drop_mode2_period(1.0, 1.0, 1.0, 0.1875);
    let mut variants: Vec<(&str, &str, Vec<&str>)> =
        vec![("quintic", "field on all particles, quintic h = 1.2Δx, p_b = σ/(2Δx) (default)", vec![])];
    if !quick {
        variants.extend(kernel_sets());
        variants.push((
            "wendland13",
            "Wendland C2 h = 1.3Δx (support 2.6Δx)",
            vec!["kernel.kind=wendland-c2", "kernel.h_ratio=1.3"],
        ));
        variants.push((
            "johnson15",
            "Johnson quadratic h = 1.5Δx (support 3Δx)",
            vec!["kernel.kind=johnson", "kernel.h_ratio=1.5"],
        ));
        variants.push((
            "johnson12",
            "Johnson quadratic h = 1.2Δx (support 2.4Δx)",
            vec!["kernel.kind=johnson", "kernel.h_ratio=1.2"],
        ));
        variants.push(("quintic-h10", "quintic h = Δx (support 3Δx; the former default)", vec!["kernel.h_ratio=1.0"]));
        variants.push(("pb-b", "p_b = B = 175 (the former default)", vec!["phases.0.p_b=175", "phases.1.p_b=175"]));
        variants.push(("pb0", "p_b = 0 (thesis-literal pressure)", vec!["phases.0.p_b=0", "phases.1.p_b=0"]));
        variants.push(("drop-only", "field on the drop only (thesis text)", vec!["initial_velocity.phase=liquid"]));
    }
    let mut quintic_period = f64::NAN;
    let mut periods: Vec<(&str, f64, f64)> = Vec::new();
    let mut spec_plot = PlotSpec::new(
        "Oscillating drop: liquid centroid x_c(t) (Fig. 4.1)",
        "t (nondimensional)",
        "centroid x_c (nondimensional)",
    );
    let mut first_max: Option<f64> = None;
    for (id, what, extra) in &variants {
        let rec = match ctx.run(&spec(id, quick, extra), &[]) {
            Ok(r) => r,
            Err(ValidateError::Skipped(s)) => {
                rep.notes.push(format!("variant {s} was not run (--skip-missing)."));
                continue;
            }
            Err(e) => return Err(e),
        };
        let dir = std::path::PathBuf::from(&rec.dir);
        let rows = read_series(&dir);
        spec_plot.series.push(Series::line(format!("sphlab: {what}"), col(&rows, |r| Some(r.centroid_x))));
        let (period, amp) = measure(&dir).unwrap_or((f64::NAN, f64::NAN));
        if first_max.is_none() {
            // time of the first centroid maximum (t < 0.2), to place the thesis period
            first_max =
                rows.iter().filter(|r| r.t < 0.2).max_by(|a, b| a.centroid_x.total_cmp(&b.centroid_x)).map(|r| r.t);
        }
        let band = if quick { (0.25, 0.45) } else { PERIOD_BAND };
        let row = Row::new(&format!("period, {what}"), period, 4, Some(THESIS_PERIOD), Some(analytic))
            .analytic_text(&format!("{analytic:.4} inviscid; {:.2}–{:.2} viscous", VISCOUS_BAND.0, VISCOUS_BAND.1));
        rep.rows.push(match *id {
            "quintic" if quick => {
                quintic_period = period;
                row.check(period >= band.0 && period <= band.1, &format!("{} ≤ T ≤ {}", band.0, band.1))
            }
            "quintic" => {
                quintic_period = period;
                row.check(
                    (period / THESIS_PERIOD - 1.0).abs() <= THESIS_PERIOD_TOL,
                    &format!("within {:.0} % of the thesis's 0.37", THESIS_PERIOD_TOL * 100.0),
                )
            }
            k if kernel_sets().iter().any(|s| s.0 == k) => row.check(
                (period / quintic_period - 1.0).abs() <= KERNEL_PERIOD_TOL,
                &format!("within {:.0} % of the quintic's {quintic_period:.3}", KERNEL_PERIOD_TOL * 100.0),
            ),
            _ => row,
        });
        if !quick && !(band.0..=band.1).contains(&period) {
            let best = |f: fn(f64, f64) -> bool| {
                rows.iter().fold(None::<(f64, f64)>, |m, r| match m {
                    Some(b) if !f(r.centroid_x, b.1) => Some(b),
                    _ => Some((r.t, r.centroid_x)),
                })
            };
            if let (Some(mx), Some(mn)) = (best(|a, b| a > b), best(|a, b| a < b)) {
                rep.notes.push(format!(
                    "{what}: no regular oscillation in t ≤ 0.6 (period {period:.3} is outside the band): global maximum x_c = {:.4} at t = {:.3}, global minimum {:.4} at t = {:.3}; see the plot.",
                    mx.1, mx.0, mn.1, mn.0
                ));
            }
        }
        let amp_row = Row::new(&format!("first-cycle amplitude, {what}"), amp, 4, Some(THESIS_AMPLITUDE), None);
        rep.rows.push(if *id == "quintic" && !quick {
            amp_row.check(
                (amp / THESIS_AMPLITUDE - 1.0).abs() <= THESIS_AMPLITUDE_TOL,
                &format!("within ±{:.0} % of 0.012", THESIS_AMPLITUDE_TOL * 100.0),
            )
        } else {
            amp_row
        });
        let late: Vec<f64> = rows.iter().filter(|r| r.t >= LATE_T).map(|r| r.centroid_x).collect();
        let late_mean = late.iter().sum::<f64>() / late.len().max(1) as f64;
        let circle = 4.0 * 0.1875 / (3.0 * std::f64::consts::PI);
        let late_row = Row::new(&format!("mean centroid t ≥ {LATE_T}, {what}"), late_mean, 4, None, Some(circle));
        let judged = *id == "quintic" || kernel_sets().iter().any(|s| s.0 == *id);
        rep.rows.push(if judged && !quick {
            late_row.check((late_mean - circle).abs() <= LATE_TOL, &format!("within {LATE_TOL} of the circle's"))
        } else {
            late_row
        });
        periods.push((id, period, amp));
        rep.runs.push(rec);
    }
    let find = |k: &str| periods.iter().find(|p| p.0 == k).map(|p| (p.1, p.2));
    if let (Some((tw13, _)), Some((tw, _))) = (find("wendland13"), find("wendland")) {
        rep.notes.push(format!(
            "Wendland C2 at h = 1.3Δx (support 2.6Δx): period {tw13:.3}, {:+.1} % from the quintic's {quintic_period:.3}; at \
             h = 1.5Δx (support 3Δx; the h this case uses) {tw:.3} ({:+.1} %): the period follows the \
             support radius in particle spacings, and both drops oscillate like a liquid (centroid back to the circle's).",
            (tw13 / quintic_period - 1.0) * 100.0,
            (tw / quintic_period - 1.0) * 100.0
        ));
    }
    if let (Some((tj12, _)), Some((tj15, _)), Some((tj, _))) = (find("johnson12"), find("johnson15"), find("johnson")) {
        let pct = |t: f64| (t / quintic_period - 1.0) * 100.0;
        rep.notes.push(format!(
            "Johnson quadratic, period against the quintic's {quintic_period:.3}: h = 1.2Δx (support 2.4Δx) {tj12:.3} \
             ({:+.1} %), h = 1.5Δx (support 3Δx) {tj15:.3} ({:+.1} %), h = 2Δx (support 4Δx; the h this case uses) \
             {tj:.3} ({:+.1} %). Its gradient does not vanish at r → 0 (PHYSICS.md §1), so close pairs repel stiffly: \
             with a narrow support the drop rings like a solid at every p_b > 0 (pb-sweep/summary.md). Use h ≥ 2Δx.",
            pct(tj12),
            pct(tj15),
            pct(tj)
        ));
    }
    if let (Some((tq, a)), Some((t10, a10)), Some((_, ab))) = (find("quintic"), find("quintic-h10"), find("pb-b")) {
        rep.notes.push(format!(
            "Quintic h = 1.2Δx (default) against h = Δx: period {tq:.3} vs {t10:.3}, first-cycle amplitude {a:.4} vs {a10:.4}. \
             The amplitude falls as the arrangement stiffens: with p_b ({ab:.4} at B = 175; reports/validation/pb-sweep at \
             nx = 24) and with a narrower support (h = Δx), whose noisier colour gradient and pressure sum also raise the \
             spurious speeds of the drop at rest (spurious/summary.md)."
        ));
    }
    if let Some((_, a)) = find("quintic") {
        let eq = 4.0 * 0.1875 / (3.0 * std::f64::consts::PI);
        let rows = read_series(&ctx.dir.join("runs").join("quintic"));
        let first_max = rows.iter().filter(|r| r.t < 0.2).map(|r| r.centroid_x).fold(f64::NAN, f64::max);
        if !quick {
            rep.notes.push(format!(
                "The first-cycle amplitude ½(max − min) = {a:.4} of a viscously damped oscillation is smaller than its first \
                 excursion x_c,max − 4R/(3π) = {:.4}; PHYSICS.md §9(a) defines the thesis's 0.012 as the former.",
                first_max - eq
            ));
        }
    }
    let eq = 4.0 * 0.1875 / (3.0 * std::f64::consts::PI);
    spec_plot.refs = vec![
        RefLine::horizontal("equilibrium 4R/(3π) = 0.0796", eq),
        RefLine::horizontal("thesis amplitude: 0.0796 + 0.012", eq + THESIS_AMPLITUDE),
        RefLine::horizontal("thesis amplitude: 0.0796 − 0.012", eq - THESIS_AMPLITUDE),
        RefLine::vertical("first maximum + thesis period 0.37", first_max.unwrap_or(0.0) + THESIS_PERIOD),
    ];
    plot(ctx, &mut rep, "fig4_1_centroid.svg", &spec_plot)?;
    rep.notes.push(format!(
        "Analytic mode-2 period of a 2D drop in an equal-density outer fluid: T = {analytic:.4} (inviscid); weak \
         viscous damping puts it at ≈ 0.31 (inner fluid) to ≈ 0.35 (both fluids). The thesis's 0.37 is ~25 % \
         above inviscid theory."
    ));
    rep.notes.push("Period = weighted least-squares spacing of the centroid maxima; amplitude = ½(max − min) over the first full cycle (diagnostics::oscillation). Where fewer than two maxima stand out above the record mean (strongly damped coarse runs), period = 2 × (first minimum − first maximum) and amplitude = ½(first max − first min) instead.".into());
    Ok(rep)
}
