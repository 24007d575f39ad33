//! The `oscillation` case as a spec for the executor: the default drop (and, for the long
//! runs, the other kernels, smoothing lengths, background pressures and initial fields), and
//! per run the period, first-cycle amplitude and late centroid against the thesis and theory.

use super::{
    kernel_sets, measure, spec, KERNEL_PERIOD_TOL, LATE_T, PERIOD_BAND, THESIS_AMPLITUDE, THESIS_AMPLITUDE_TOL,
    THESIS_PERIOD, THESIS_PERIOD_TOL, VISCOUS_BAND,
};
use crate::diagnostics::drop_mode2_period;
use crate::plot::{PlotSpec, RefLine, Series};
use crate::validate::case::{Case, CaseOutput, CasePlot, CaseRun, CaseSpec};
use crate::validate::data::{col, read_series};
use crate::validate::report::{Row, RunRecord};
use crate::validate::{Ctx, ValidateError};

const CENTROID_PLOT: &str = "fig4_1_centroid.svg";
/// The drop at rest's centroid: 4R/(3π) of the R = 0.1875 half-disc.
const CIRCLE_CENTROID: f64 = 4.0 * 0.1875 / (3.0 * std::f64::consts::PI);

/// The case: the analytic period, and what the rows and notes across runs need.
pub(super) struct Oscillation {
    quick: bool,
    analytic: f64,
    quintic_period: f64,
    /// (run id, period, first-cycle amplitude) of every run made.
    periods: Vec<(String, f64, f64)>,
    /// Time of the first centroid maximum (t < 0.2) of the first run, to place the thesis period.
    first_max: Option<f64>,
}

impl Oscillation {
    /// The case under the options of `ctx`.
    pub(super) fn new(ctx: &Ctx) -> Self {
        Oscillation {
            quick: ctx.opts.quick,
            analytic: drop_mode2_period(1.0, 1.0, 1.0, 0.1875),
            quintic_period: f64::NAN,
            periods: Vec::new(),
            first_max: None,
        }
    }

    /// The variants: id, label, overrides (the long runs: every kernel and h, p_b and field).
    fn variants(&self) -> Vec<(&'static str, &'static str, Vec<&'static str>)> {
        let mut variants: Vec<(&str, &str, Vec<&str>)> =
            vec![("quintic", "field on all particles, quintic h = 1.2Δx, p_b by the capillary rule (default)", vec![])];
        if self.quick {
            return variants;
        }
        variants.extend(kernel_sets());
        variants.extend([
            (
                "wendland13",
                "Wendland C2 h = 1.3Δx (support 2.6Δx)",
                vec!["kernel.kind=wendland-c2", "kernel.h_ratio=1.3"],
            ),
            (
                "johnson15",
                "Johnson quadratic h = 1.5Δx (support 3Δx)",
                vec!["kernel.kind=johnson", "kernel.h_ratio=1.5"],
            ),
            (
                "johnson12",
                "Johnson quadratic h = 1.2Δx (support 2.4Δx)",
                vec!["kernel.kind=johnson", "kernel.h_ratio=1.2"],
            ),
            ("quintic-h10", "quintic h = Δx (support 3Δx; the former default)", vec!["kernel.h_ratio=1.0"]),
            ("pb-b", "p_b = B = 175 (the former default)", vec!["phases.0.p_b=175", "phases.1.p_b=175"]),
            ("pb0", "p_b = 0 (thesis-literal pressure)", vec!["phases.0.p_b=0", "phases.1.p_b=0"]),
            ("drop-only", "field on the drop only (thesis text)", vec!["initial_velocity.phase=liquid"]),
        ]);
        variants
    }

    /// The period row: the default drop in the quick band or within 5 % of the thesis, the
    /// other kernels within 15 % of the default's period.
    fn period_row(&mut self, id: &str, what: &str, period: f64) -> Row {
        let (quick, analytic) = (self.quick, self.analytic);
        let band = if quick { (0.25, 0.45) } else { PERIOD_BAND };
        let row = Row::new(&format!("period, {what}"), period, 4, Some(THESIS_PERIOD), Some(analytic))
            .analytic_text(&format!("{analytic:.4} inviscid; {:.2}–{:.2} viscous", VISCOUS_BAND.0, VISCOUS_BAND.1));
        match id {
            "quintic" if quick => {
                self.quintic_period = period;
                row.check(period >= band.0 && period <= band.1, &format!("{} ≤ T ≤ {}", band.0, band.1))
            }
            "quintic" => {
                self.quintic_period = period;
                row.check(
                    (period / THESIS_PERIOD - 1.0).abs() <= THESIS_PERIOD_TOL,
                    &format!("within {:.0} % of the thesis's 0.37", THESIS_PERIOD_TOL * 100.0),
                )
            }
            k if kernel_sets().iter().any(|s| s.0 == k) => {
                let quintic = self.quintic_period;
                row.check(
                    (period / quintic - 1.0).abs() <= KERNEL_PERIOD_TOL,
                    &format!("within {:.0} % of the quintic's {quintic:.3}", KERNEL_PERIOD_TOL * 100.0),
                )
            }
            _ => row,
        }
    }

    /// Notes across the kernels and smoothing lengths (long runs): each period against the
    /// default quintic's, and the default's amplitude against its first excursion.
    fn kernel_notes(&self, ctx: &Ctx, notes: &mut Vec<String>) {
        let quintic = self.quintic_period;
        let find = |k: &str| self.periods.iter().find(|p| p.0 == k).map(|p| (p.1, p.2));
        let pct = |t: f64| (t / quintic - 1.0) * 100.0;
        if let (Some((tw13, _)), Some((tw, _))) = (find("wendland13"), find("wendland")) {
            notes.push(format!(
                "Wendland C2 at h = 1.3Δx (support 2.6Δx): period {tw13:.3}, {:+.1} % from the quintic's {quintic:.3}; at \
                 h = 1.5Δx (support 3Δx; the h this case uses) {tw:.3} ({:+.1} %).",
                pct(tw13),
                pct(tw)
            ));
        }
        if let (Some((tj12, _)), Some((tj15, _)), Some((tj, _))) =
            (find("johnson12"), find("johnson15"), find("johnson"))
        {
            notes.push(format!(
                "Johnson quadratic, period against the quintic's {quintic:.3}: h = 1.2Δx (support 2.4Δx) {tj12:.3} \
                 ({:+.1} %), h = 1.5Δx (support 3Δx) {tj15:.3} ({:+.1} %), h = 2Δx (support 4Δx; the h this case uses) \
                 {tj:.3} ({:+.1} %). Its gradient does not vanish at r → 0 (docs/PHYSICS.md §1); the kernels against p_b: \
                 pb-sweep/summary.md.",
                pct(tj12),
                pct(tj15),
                pct(tj)
            ));
        }
        if let (Some((tq, a)), Some((t10, a10)), Some((_, ab))) = (find("quintic"), find("quintic-h10"), find("pb-b")) {
            notes.push(format!(
                "Quintic h = 1.2Δx (default) against h = Δx: period {tq:.3} vs {t10:.3}, first-cycle amplitude {a:.4} vs {a10:.4}; \
                 at p_b = B = 175 the amplitude is {ab:.4} (reports/validation/pb-sweep; the drop at rest: spurious/summary.md)."
            ));
        }
        if let Some((_, a)) = find("quintic") {
            let rows = read_series(&ctx.dir.join("runs").join("quintic"));
            let first_max = rows.iter().filter(|r| r.t < 0.2).map(|r| r.centroid_x).fold(f64::NAN, f64::max);
            if !self.quick {
                notes.push(format!(
                    "The first-cycle amplitude ½(max − min) = {a:.4} of a viscously damped oscillation is smaller than its first \
                     excursion x_c,max − 4R/(3π) = {:.4}; docs/PHYSICS.md §9(a) defines the thesis's 0.012 as the former.",
                    first_max - CIRCLE_CENTROID
                ));
            }
        }
    }
}

impl Case for Oscillation {
    fn spec(&self, _ctx: &Ctx) -> CaseSpec {
        let analytic = self.analytic;
        let runs =
            self.variants().into_iter().map(|(id, what, extra)| CaseRun::new(spec(id, self.quick, &extra), what));
        CaseSpec {
            name: "oscillation",
            reference: "Thesis §4.2.1, Fig. 4.1 (docs/PHYSICS.md §9(a)): oscillating drop",
            runs: runs.collect(),
            not_full: Vec::new(),
            plots: vec![CasePlot {
                file: CENTROID_PLOT,
                plot: PlotSpec::new(
                    "Oscillating drop: liquid centroid x_c(t) (Fig. 4.1)",
                    "t (nondimensional)",
                    "centroid x_c (nondimensional)",
                ),
            }],
            tables: Vec::new(),
            method_notes: vec![
                format!(
                    "Analytic mode-2 period of a 2D drop in an equal-density outer fluid: T = {analytic:.4} (inviscid); weak \
                     viscous damping puts it at ≈ 0.31 (inner fluid) to ≈ 0.35 (both fluids). The thesis's 0.37 is ~25 % \
                     above inviscid theory."
                ),
                format!(
                    "The mean centroid over t ≥ {LATE_T} is info, with no verdict: it tests that the drop ends near a \
                     circle, which a drop that never oscillates also does, so it does not validate the oscillation."
                ),
                "Period = weighted least-squares spacing of the centroid maxima; amplitude = ½(max − min) over the first full cycle (diagnostics::oscillation). Where fewer than two maxima stand out above the record mean (strongly damped coarse runs), period = 2 × (first minimum − first maximum) and amplitude = ½(first max − first min) instead.".into(),
            ],
        }
    }

    fn measure(
        &mut self,
        _ctx: &Ctx,
        run: &CaseRun,
        rec: &RunRecord,
        out: &mut CaseOutput,
    ) -> Result<(), ValidateError> {
        let (id, what, quick) = (run.spec.id.as_str(), run.label.as_str(), self.quick);
        let dir = std::path::PathBuf::from(&rec.dir);
        let rows = read_series(&dir);
        out.plot(CENTROID_PLOT)
            .series
            .push(Series::line(format!("sphlab: {what}"), col(&rows, |r| Some(r.centroid_x))));
        let (period, amp) = measure(&dir).unwrap_or((f64::NAN, f64::NAN));
        if self.first_max.is_none() {
            self.first_max =
                rows.iter().filter(|r| r.t < 0.2).max_by(|a, b| a.centroid_x.total_cmp(&b.centroid_x)).map(|r| r.t);
        }
        let row = self.period_row(id, what, period);
        let rep = &mut out.rep;
        rep.rows.push(row);
        if !quick && !(PERIOD_BAND.0..=PERIOD_BAND.1).contains(&period) {
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
        rep.rows.push(if id == "quintic" && !quick {
            amp_row.check(
                (amp / THESIS_AMPLITUDE - 1.0).abs() <= THESIS_AMPLITUDE_TOL,
                &format!("within ±{:.0} % of 0.012", THESIS_AMPLITUDE_TOL * 100.0),
            )
        } else {
            amp_row
        });
        let late: Vec<f64> = rows.iter().filter(|r| r.t >= LATE_T).map(|r| r.centroid_x).collect();
        let late_mean = late.iter().sum::<f64>() / late.len().max(1) as f64;
        let late_row =
            Row::new(&format!("mean centroid t ≥ {LATE_T}, {what}"), late_mean, 4, None, Some(CIRCLE_CENTROID));
        // Info, not a pass: a drop that never oscillates (p_b = 0) also sits on the circle's centroid.
        rep.rows.push(late_row);
        self.periods.push((id.to_string(), period, amp));
        Ok(())
    }

    fn skipped(&mut self, _run: &CaseRun, id: &str, out: &mut CaseOutput) {
        out.rep.notes.push(format!("variant {id} was not run (--skip-missing)."));
    }

    fn compare(&mut self, ctx: &Ctx, out: &mut CaseOutput) -> Result<(), ValidateError> {
        self.kernel_notes(ctx, &mut out.rep.notes);
        let eq = CIRCLE_CENTROID;
        out.plot(CENTROID_PLOT).refs = vec![
            RefLine::horizontal("equilibrium 4R/(3π) = 0.0796", eq),
            RefLine::horizontal("thesis amplitude: 0.0796 + 0.012", eq + THESIS_AMPLITUDE),
            RefLine::horizontal("thesis amplitude: 0.0796 − 0.012", eq - THESIS_AMPLITUDE),
            RefLine::vertical("first maximum + thesis period 0.37", self.first_max.unwrap_or(0.0) + THESIS_PERIOD),
        ];
        Ok(())
    }
}
