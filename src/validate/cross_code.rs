//! Case `cross-code`: PySPH's oscillating rod (`scenes/pysph-rod.toml`, PySPH's
//! `oscillating_rod.py --scheme adami_stress` set-up) on the CPU with both colour-gradient forms
//! (single-field = PySPH's, and the thesis's), against PySPH's committed curve
//! `data/reference/pysph-oscillating-rod.csv` over its whole record (t ≤ 0.5; `--quick`: t ≤
//! 0.08). Estimators: [`crate::diagnostics::rod`], shared with `tests/cross_code.rs`. The full
//! case also runs each form at p_b × 0.5 and × 2 of PySPH's (sphlab's side only): the band
//! [`pb_bands`] gives every pass and FAIL row.

use super::case::{Case, CaseOutput, CasePlot, CaseRun, CaseSpec, CaseTable};
use super::data::{read_snapshot, snapshot_files};
use super::report::{Band, CaseReport, Row, RunRecord};
use super::{Ctx, RunSpec, ValidateError};
use crate::diagnostics::rod::{
    pysph_rod_reference, rms_over_amplitude, rod_measures, rod_oscillation, RodOscillation, RodRow, ROD_CURVES,
};
use crate::plot::{PlotSpec, Series};

/// The scene file the case runs.
pub const SCENE: &str = "scenes/pysph-rod.toml";
/// End time of `--quick` (the reference row at step 854, past the first maximum of a_x).
pub const QUICK_T_END: f64 = 0.08;
/// Period and damping rate of a_x(t) must lie within this fraction of PySPH's.
pub const OSCILLATION_TOL: f64 = 0.02;
/// Bound on rms/amplitude of a_x, b_y, mean |x|, mean |y|: (single-field, thesis) over the
/// whole record, stated before the first full run.
pub const RMS_TOL: (f64, f64) = (0.01, 0.03);
/// The same over t ≤ [`QUICK_T_END`] (the bounds of `tests/cross_code.rs`).
pub const RMS_TOL_QUICK: (f64, f64) = (0.005, 0.03);
/// The equilibrium of a_x is its mean over t ≥ this.
pub const EQUILIBRIUM_FROM: f64 = 0.4;
/// Half-width of the parabola fit around each extremum of a_x.
pub const VERTEX_WINDOW: f64 = 0.02;

/// The colour-gradient forms: run id (= `surface_tension.colour_gradient`) and label.
const FORMS: [(&str, &str); 2] =
    [("single-field", "single-field colour gradient (PySPH's)"), ("thesis", "thesis colour gradient (T71)")];
/// The sensitivity band's runs beside each form (full case only): id suffix, label suffix and
/// the factor on the scene's p_b (PySPH's ρ0c0² = 400) in both phases; c0, γ and dt unchanged.
const PB_BAND: [(&str, &str, f64); 2] = [("-pb-half", ", p_b × 0.5", 0.5), ("-pb-double", ", p_b × 2", 2.0)];
/// Each run's curve table, by run id.
const TABLES: [(&str, &str); 6] = [
    ("single-field", "curves_single-field.csv"),
    ("single-field-pb-half", "curves_single-field-pb-half.csv"),
    ("single-field-pb-double", "curves_single-field-pb-double.csv"),
    ("thesis", "curves_thesis.csv"),
    ("thesis-pb-half", "curves_thesis-pb-half.csv"),
    ("thesis-pb-double", "curves_thesis-pb-double.csv"),
];
const RMS_HEAD: &str = "rms/amplitude of ";
const PERIOD_HEAD: &str = "a_x period 2(t_min − t_max)";
const DAMPING_HEAD: &str = "a_x damping rate β = Λ/(t_min − t_max)";
const AX_PLOT: &str = "a_x.svg";
const BY_PLOT: &str = "b_y.svg";

struct CrossCode {
    quick: bool,
    reference: Vec<RodRow>,
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    super::executor::execute(ctx, &mut CrossCode { quick: ctx.opts.quick, reference: pysph_rod_reference() })
}

/// The scene's p_b in both phases (PySPH's ρ0c0²).
fn scene_pb() -> f64 {
    RunSpec::new("", SCENE, &[], None, 1).scene().map_or(f64::NAN, |s| s.phases[0].p_b)
}

fn table_file(id: &str) -> &'static str {
    TABLES.iter().find(|t| t.0 == id).map_or(TABLES[0].1, |t| t.1)
}

/// A stated bound: at most a value (rms/amplitude), or within a fraction of PySPH's value.
#[derive(Clone, Copy, Debug)]
enum Bound {
    AtMost(f64),
    WithinOf { pysph: f64, tol: f64 },
}

impl Bound {
    fn holds(self, v: f64) -> bool {
        match self {
            Bound::AtMost(max) => v <= max,
            Bound::WithinOf { pysph, tol } => (v / pysph - 1.0).abs() <= tol,
        }
    }

    fn text(self) -> String {
        match self {
            Bound::AtMost(max) => format!("≤ {:.1} % (stated bound)", max * 100.0),
            Bound::WithinOf { tol, .. } => format!("within {:.0} % of PySPH's", tol * 100.0),
        }
    }
}

/// The stated bound of a compared quantity, from its name: rms/amplitude against its form's
/// tolerance (`quick`: over t ≤ [`QUICK_T_END`]), a_x's period and damping rate within
/// [`OSCILLATION_TOL`] of PySPH's (`pysph`). None for an info row.
fn bound(quantity: &str, quick: bool, pysph: Option<RodOscillation>) -> Option<Bound> {
    let tol = if quick { RMS_TOL_QUICK } else { RMS_TOL };
    let tol = if quantity.contains(FORMS[1].1) { tol.1 } else { tol.0 };
    let curve = quantity.strip_prefix(RMS_HEAD).and_then(|q| q.split(' ').next());
    if let Some(k) = curve.and_then(|c| ROD_CURVES.iter().position(|n| *n == c)) {
        return (k < 4).then_some(Bound::AtMost(tol));
    }
    let p = pysph?;
    let reference = if quantity.starts_with(PERIOD_HEAD) {
        p.period
    } else if quantity.starts_with(DAMPING_HEAD) {
        p.damping_rate
    } else {
        return None;
    };
    Some(Bound::WithinOf { pysph: reference, tol: OSCILLATION_TOL })
}

/// PySPH's a_x period and damping rate over `reference` (its whole record, or the rows a run
/// matched), by the case's estimator.
fn pysph_oscillation(reference: &[RodRow]) -> Option<RodOscillation> {
    let t: Vec<f64> = reference.iter().map(|r| r.t).collect();
    let a: Vec<f64> = reference.iter().map(|r| r.v[0]).collect();
    rod_oscillation(&t, &a, EQUILIBRIUM_FROM, VERTEX_WINDOW)
}

/// For every pass and FAIL row of a form at PySPH's p_b, its sensitivity band: the same quantity
/// from the case's runs at p_b × 0.5 and × 2 ([`PB_BAND`]), with whether the row's bound holds at
/// all three. Rows whose band runs are not in the report get none.
pub(super) fn pb_bands(rep: &CaseReport) -> Vec<(String, Band)> {
    let pysph = pysph_oscillation(&pysph_rod_reference());
    let judged = rep.rows.iter().filter(|r| r.verdict.starts_with("pass (") || r.verdict.starts_with("FAIL ("));
    judged
        .filter_map(|r| {
            let at = |suffix: &str| rep.rows.iter().find(|b| b.quantity == format!("{}{suffix}", r.quantity));
            let three = [at(PB_BAND[0].1)?, r, at(PB_BAND[1].1)?];
            let b = bound(&r.quantity, rep.quick, pysph)?;
            let form = FORMS.iter().find(|f| r.quantity.ends_with(f.1))?.0;
            let band = Band {
                varied: format!(
                    "p_b × 0.5 / × 1 / × 2 of PySPH's ρ0c0² = {pb}, in sphlab only (c0, γ, dt unchanged; PySPH's \
                     curve stays at {pb})",
                    pb = scene_pb()
                ),
                values: three.iter().map(|x| x.sphlab.clone()).collect(),
                source: [PB_BAND[0].0, "", PB_BAND[1].0].map(|s| table_file(&format!("{form}{s}"))).join(", "),
                holds: Some(three.iter().all(|x| b.holds(x.value))),
            };
            Some((r.quantity.clone(), band))
        })
        .collect()
}

impl CrossCode {
    /// Notes on the method: the curves, their bounds, the half-cycle measures of period and
    /// damping and (full case) the p_b band's runs at the scene's `pb`.
    fn method_notes(&self, pb: f64) -> Vec<String> {
        let (tol, q) = if self.quick { (RMS_TOL_QUICK, " (quick)") } else { (RMS_TOL, "") };
        let mut notes = vec![
            "Curves (diagnostics::rod, as tests/cross_code.rs): the liquid's half-extents a_x, b_y = ½(max − min) \
             (PySPH's estimator), its centroid folded into the first quadrant mean |x|, mean |y|, and PySPH's quarter \
             centroid (liquid with x > 0, y > 0), from the particle snapshots at every committed PySPH row (every 50 \
             steps of PySPH's dt = 9.375e-5). Each curve's rms difference is divided by its amplitude, half the \
             PySPH curve's range over the same rows."
                .into(),
            format!(
                "Bounds{q}, stated before measuring: rms/amplitude of a_x, b_y, mean |x|, mean |y| ≤ {:.1} % \
                 (single-field, PySPH's own form) and ≤ {:.1} % (thesis form); the quarter centroids are info (they \
                 jump whenever a particle on an axis moves off it, so they measure the arrangement, not the drop).",
                tol.0 * 100.0,
                tol.1 * 100.0
            ),
            format!(
                "Period and damping of a_x(t), by the same estimator on sphlab's and PySPH's rows \
                 (diagnostics::rod::rod_oscillation): the first maximum (largest sample) and the first minimum after \
                 it (smallest sample before t = {EQUILIBRIUM_FROM}), each refined to the vertex of the least-squares \
                 parabola through the samples within ±{VERTEX_WINDOW}; equilibrium a_eq = mean of a_x over t ≥ \
                 {EQUILIBRIUM_FROM}; period = 2(t_min − t_max); log decrement per half period Λ = ln((a_max − a_eq)/\
                 (a_eq − a_min)); damping rate β = Λ/(t_min − t_max). Bound: within {:.0} % of PySPH's. The rod at \
                 ν = 0.05 is strongly damped: the record holds one maximum and one minimum, so these are half-cycle \
                 measures. --quick ends before the first minimum and reports neither.",
                OSCILLATION_TOL * 100.0
            ),
        ];
        if !self.quick {
            let ids: Vec<String> =
                FORMS.iter().flat_map(|(id, _)| PB_BAND.iter().map(move |b| format!("`{id}{}`", b.0))).collect();
            notes.push(format!(
                "Sensitivity band: each form is also run at p_b × 0.5 and × 2 of PySPH's ρ0c0² = {pb} in both phases \
                 (c0, γ and dt unchanged; PySPH's curve stays at {pb}): runs {}, curves in `curves_<run>.csv`. Their \
                 rows are info; the judge gives each form's pass and FAIL rows the band, judged by the row's own bound.",
                ids.join(", ")
            ));
        }
        notes
    }

    /// Period and damping-rate rows of a_x for one run, against PySPH's on the same rows; judged
    /// for a form at PySPH's p_b, info for a band run (`checked` false).
    fn oscillation_rows(
        &self,
        label: &str,
        checked: bool,
        sim: Option<RodOscillation>,
        pysph: Option<RodOscillation>,
    ) -> Vec<Row> {
        let get = |o: Option<RodOscillation>, f: fn(&RodOscillation) -> f64| o.as_ref().map_or(f64::NAN, f);
        let row = |what: &str, f: fn(&RodOscillation) -> f64| {
            let (v, r, q) = (get(sim, f), get(pysph, f), format!("{what}, {label}"));
            let row = Row::new(&q, v, 4, None, Some(r)).analytic_text(&format!("PySPH {r:.4}"));
            match bound(&q, self.quick, pysph).filter(|_| checked) {
                Some(b) => row.check(b.holds(v), &b.text()),
                None => row,
            }
        };
        vec![row(PERIOD_HEAD, |o| o.period), row(DAMPING_HEAD, |o| o.damping_rate)]
    }
}

impl Case for CrossCode {
    fn spec(&self, _ctx: &Ctx) -> CaseSpec {
        let t_end = self.quick.then_some(QUICK_T_END);
        let pb = scene_pb();
        let band: &[_] = if self.quick { &[] } else { &PB_BAND };
        let runs = FORMS.iter().flat_map(|(id, label)| {
            let form = format!("surface_tension.colour_gradient={id}");
            let at_pb =
                std::iter::once(CaseRun::new(RunSpec::new(*id, SCENE, std::slice::from_ref(&form), t_end, 1), *label));
            at_pb.chain(band.iter().map(move |(suffix, more, f)| {
                let mut sets = vec![form.clone()];
                sets.extend((0..2).map(|k| format!("phases.{k}.p_b={}", f * pb)));
                CaseRun::new(RunSpec::new(format!("{id}{suffix}"), SCENE, &sets, t_end, 1), format!("{label}{more}"))
            }))
        });
        let plot = |title: &str, y: &str| PlotSpec::new(title, "t (nondimensional)", y);
        let header = format!("t,step,{}", ROD_CURVES.join(","));
        let method_notes = self.method_notes(pb);
        CaseSpec {
            name: "cross-code",
            reference: "PySPH 1.0b2 oscillating_rod.py --scheme adami_stress (scenes/pysph-rod.toml): cross-code check",
            runs: runs.collect(),
            not_full: Vec::new(),
            plots: vec![
                CasePlot {
                    file: AX_PLOT, plot: plot("Oscillating rod: half-extent a_x(t)", "a_x = ½(max x − min x)")
                },
                CasePlot {
                    file: BY_PLOT, plot: plot("Oscillating rod: half-extent b_y(t)", "b_y = ½(max y − min y)")
                },
            ],
            tables: TABLES
                .iter()
                .filter(|t| !self.quick || FORMS.iter().any(|f| f.0 == t.0))
                .map(|(_, file)| CaseTable { file, header: header.clone(), rows: Vec::new() })
                .collect(),
            method_notes,
        }
    }

    fn measure(
        &mut self,
        _ctx: &Ctx,
        run: &CaseRun,
        rec: &RunRecord,
        out: &mut CaseOutput,
    ) -> Result<(), ValidateError> {
        let (id, label) = (run.spec.id.as_str(), run.label.as_str());
        let dir = std::path::PathBuf::from(&rec.dir);
        let (mut sim, mut reference, mut table) = (Vec::new(), Vec::new(), Vec::new());
        for (step, path) in snapshot_files(&dir) {
            let Some(r) = self.reference.iter().find(|r| r.step == step) else { continue };
            let s = read_snapshot(&path, step, r.t)
                .ok_or_else(|| ValidateError::Io(format!("{}: unreadable snapshot", path.display())))?;
            let m = rod_measures(&s.pos, &s.phase);
            table.push([r.t, step as f64].into_iter().chain(m).collect());
            sim.push((r.t, m));
            reference.push(*r);
        }
        if sim.len() < 2 {
            return Err(ValidateError::Io(format!(
                "{}: fewer than two particle snapshots at PySPH's rows (snapshots are not committed: run the case)",
                dir.display()
            )));
        }
        let t_last = sim[sim.len() - 1].0;
        let (sv, rv): (Vec<[f64; 6]>, Vec<[f64; 6]>) =
            (sim.iter().map(|s| s.1).collect(), reference.iter().map(|r| r.v).collect());
        let e = rms_over_amplitude(&sv, &rv);
        // A form at PySPH's p_b is judged; its band runs' rows are info, read by [`pb_bands`].
        let checked = FORMS.iter().any(|f| f.0 == id);
        for (k, name) in ROD_CURVES.iter().enumerate() {
            let q = format!("{RMS_HEAD}{name} over t ≤ {t_last:.4}, {label}");
            let row = Row::new(&q, e[k], 5, None, None).sphlab_text(format!("{:.3} %", 100.0 * e[k]));
            out.rep.rows.push(match bound(&q, self.quick, None).filter(|_| checked) {
                Some(b) => row.check(b.holds(e[k]) && rec.status == "ok", &b.text()),
                None => row,
            });
        }
        if !self.quick {
            let t: Vec<f64> = sim.iter().map(|s| s.0).collect();
            let osc = |v: &[[f64; 6]]| {
                rod_oscillation(&t, &v.iter().map(|v| v[0]).collect::<Vec<_>>(), EQUILIBRIUM_FROM, VERTEX_WINDOW)
            };
            let (so, ro) = (osc(&sv), pysph_oscillation(&reference));
            out.rep.rows.extend(self.oscillation_rows(label, checked, so, ro));
            if let (Some(s), Some(r)) = (so, ro) {
                out.rep.notes.push(format!(
                    "{label}: a_x maximum {:.5} at t = {:.4} (PySPH {:.5} at {:.4}), minimum {:.5} at t = {:.4} (PySPH {:.5} at \
                     {:.4}), equilibrium {:.5} (PySPH {:.5}), log decrement per half period {:.3} (PySPH {:.3}).",
                    s.max.1, s.max.0, r.max.1, r.max.0, s.min.1, s.min.0, r.min.1, r.min.0, s.equilibrium, r.equilibrium,
                    s.log_decrement, r.log_decrement
                ));
            }
        }
        let pts = |k: usize| sim.iter().map(|s| (s.0, s.1[k])).collect::<Vec<_>>();
        out.plot(AX_PLOT).series.push(Series::line(format!("sphlab: {label}"), pts(0)));
        out.plot(BY_PLOT).series.push(Series::line(format!("sphlab: {label}"), pts(1)));
        *out.table(table_file(id)) = table;
        Ok(())
    }

    fn compare(&mut self, _ctx: &Ctx, out: &mut CaseOutput) -> Result<(), ValidateError> {
        let t_max = if self.quick { QUICK_T_END + 1e-9 } else { f64::INFINITY };
        let pts = |k: usize| self.reference.iter().filter(|r| r.t <= t_max).map(|r| (r.t, r.v[k])).collect::<Vec<_>>();
        out.plot(AX_PLOT).series.insert(0, Series::line("PySPH (committed curve)", pts(0)));
        out.plot(BY_PLOT).series.insert(0, Series::line("PySPH (committed curve)", pts(1)));
        Ok(())
    }
}
