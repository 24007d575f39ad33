//! The `relax-60` case as a spec for the executor: the variants' runs (modes, walls, starts)
//! and per run the spread, angle, motion and wall-shear rows; across the runs the two-start
//! rows and the dt comparison.

use super::compare::{dt_comparison, two_starts, EndAngle};
use super::{analytic_spread, analytic_spread_at, start_cap, variants, wall_spread, Variant, R0, THESIS_SPREAD_MAX};
use crate::plot::{Marker, PlotSpec, RefLine, Series};
use crate::validate::case::{Case, CaseOutput, CasePlot, CaseRun, CaseSpec, CaseTable};
use crate::validate::committed::{vouched, Committed};
use crate::validate::data::{col, mean_shear_profile_in, read_series, snapshot_files, window_stats, Row as SRow};
use crate::validate::report::{Row, RunRecord};
use crate::validate::sessile::{geometry, quick_sets, shear_window};
use crate::validate::{Ctx, RunSpec, ValidateError};
use std::path::PathBuf;

const ANGLE_PLOT: &str = "contact_angle_deviation.svg";
const SPREAD_PLOT: &str = "fig4_13_spread_factor.svg";
/// The wall shear along the wall while the drop relaxes and at its end, one plot per window.
const SHEAR_PLOTS: [&str; 2] = ["wall_shear_profiles_early.svg", "wall_shear_profiles_end.svg"];
const SHEAR_TABLE: &str = "wall_shear_profiles.csv";

/// The case: resolution, windows, the analytic spreads, its variants, and what the comparison
/// across runs needs (Mode B no-slip's angle, each variant's end angle).
pub(super) struct Relax {
    quick: bool,
    t_end: f64,
    nx: u32,
    /// Δx, wall height, wall extent.
    geometry: (f64, f64, f64),
    /// Analytic D/D0 at the wall and at the first row's height.
    spread: (f64, f64),
    /// The end window and its text.
    window: (f64, f64, String),
    /// The early window of the shear profile.
    early: (f64, f64),
    variants: Vec<Variant>,
    b_circle: Vec<(f64, f64)>,
    end_angle: Vec<EndAngle>,
}

/// The series of one run, read back (D/D0 rescaled to the half-disc's R0) with its angles.
struct RunSeries {
    rows: Vec<SRow>,
    circle: Vec<(f64, f64)>,
    two: Vec<(f64, f64)>,
    area: Vec<(f64, f64)>,
    spread: Vec<(f64, f64)>,
    wall: Vec<(f64, f64)>,
}

impl Relax {
    /// The case under the options of `ctx`.
    pub(super) fn new(ctx: &Ctx) -> Self {
        let quick = ctx.opts.quick;
        let t_end = ctx.opts.long_t_end(0.3);
        let nx = if quick { 26 } else { ctx.opts.long_nx() };
        let geometry = geometry(nx);
        Relax {
            quick,
            t_end,
            nx,
            geometry,
            spread: (analytic_spread(), analytic_spread_at(0.5 * geometry.0)),
            window: shear_window(t_end),
            early: (0.2f64.min(0.5 * t_end), 0.3f64.min(t_end)),
            variants: if quick { variants().into_iter().take(1).collect() } else { variants() },
            b_circle: Vec::new(),
            end_angle: Vec::new(),
        }
    }

    /// The run of a variant. The long runs take the convergence case's sets at this nx
    /// (relax-60's p_b rule, dt scaled from the thesis's 7e-5 at nx = 65, a row every ~0.035), so
    /// Mode B no-slip is the convergence run at the same nx and either case reuses the other's.
    fn run_of(&self, ctx: &Ctx, v: &Variant) -> CaseRun {
        let (quick, nx) = (self.quick, self.nx);
        let mut sets =
            if quick { quick_sets() } else { crate::validate::convergence::spec(nx, false, self.t_end).sets };
        sets.extend(v.sets.iter().cloned());
        let mut run = CaseRun::new(RunSpec::new(v.id, "relax-60", &sets, Some(self.t_end), 2), v.label);
        if v.id == "b-noslip" && !quick {
            run.also = vec![ctx.opts.out.join("convergence").join("runs").join(format!("nx{nx}"))];
        }
        run
    }

    /// Why the case is not at the thesis's resolution and end time.
    fn not_full(&self) -> Vec<String> {
        let (quick, nx, t_end) = (self.quick, self.nx, self.t_end);
        let mut why = Vec::new();
        if !quick && nx != 65 {
            why.push(format!(
                "nx = {nx} instead of the thesis's 65 (CPU time), p_b = {:.2} (the capillary rule), dt = {:.4e} (relax-60's dt at nx = 65 scaled with the tightest limit, as in the convergence case)",
                crate::validate::convergence::pb_for(nx),
                crate::validate::convergence::dt_for(nx, false)
            ));
        }
        if !quick && t_end < 5.0 {
            why.push(format!("t_end = {t_end} instead of the thesis's 5 (CPU time); end profile over the last 10 %"));
        }
        why
    }

    /// The plots, their series filled per run.
    fn plots(&self) -> Vec<CasePlot> {
        let (d_an, d_row) = self.spread;
        let mut angle = PlotSpec::new(
            "Relaxation 90° → 60°: contact-angle deviation from 60° (§4.2.3)",
            "t (nondimensional)",
            "θ − 60° (degrees)",
        );
        angle.refs = vec![RefLine::horizontal("target 60°", 0.0)];
        angle.y_range = Some((-20.0, 50.0));
        let mut spread = PlotSpec::new(
            "Relaxation 90° → 60°: spread factor D/D0 at the first row (Fig. 4.13)",
            "t (nondimensional)",
            "D/D0 = x_tp / R",
        );
        spread.refs = vec![
            RefLine::horizontal(format!("analytic equilibrium cap {d_an:.3} (at the wall)"), d_an),
            RefLine::horizontal(format!("analytic cap at the first row's height {d_row:.3}"), d_row),
            RefLine::horizontal("thesis Fig. 4.13 upper bound 1.4", THESIS_SPREAD_MAX),
        ];
        let phases = ["relaxing", "end window"];
        let shear = self.shear_windows().into_iter().zip(phases).map(|(window, phase)| {
            let mut shear = PlotSpec::new(
                format!("Relaxation 90° → 60°: wall shear, {window} ({phase})"),
                "fraction of the wall (0 = drop centre, 1 = right wall)",
                "average |∂u/∂y| (1/time)",
            );
            shear.log_y = true;
            shear
        });
        [(ANGLE_PLOT, angle), (SPREAD_PLOT, spread)]
            .into_iter()
            .chain(SHEAR_PLOTS.into_iter().zip(shear))
            .map(|(file, plot)| CasePlot { file, plot })
            .collect()
    }

    /// Notes on the method: the analytic cap, the wall shear, the two D/D0 measures, and for
    /// the long runs the transport-velocity variant and where the equilibrium's causes are tested.
    fn method_notes(&self) -> Vec<String> {
        let (d_an, d_row) = self.spread;
        let dx = self.geometry.0;
        let mut notes = vec![
            format!("Analytic equilibrium: circular cap of the half-drop's area πR²/2 at 60°: R_c = 0.3998, x_tp = 0.3462, D/D0 = {d_an:.4}."),
            "Wall shear = |u/(y − y_w)| of first-row particles (diagnostics::wall_shear_profile): a shear rate for the no-slip wall only; on the free-slip wall it measures the slip velocity over the first-row height.".into(),
            format!("D/D0 at the first row = x_tp/R with x_tp the outermost first-row liquid particle + Δx/2 (series.csv spread_factor, the plot): the interface at the first row's height Δx/2, compared with the analytic cap's width at that height ({d_row:.4} at nx = {}). D/D0 at the wall (the issue's criterion, against {d_an:.4}) carries each row's value down to the wall along its own circle-fit angle: + (Δx/2)·cot θ / R (+{:.4} at 60° here). The two comparisons differ only in where the cap is cut.", self.nx, 0.5 * dx / (R0 * 60f64.to_radians().tan())),
        ];
        if !self.quick {
            let ph = &crate::scene::builtin::relax_60().phases[0];
            let p_b = crate::scene::builtin::transport_background_pressure(ph.rho0, ph.c0);
            notes.push(format!("Transport velocity (`b-noslip-tvf`: `time.background = \"transport\"`, p_b = ρ0c0² = {p_b:.0} at the rule's c0 = {:.1}; Adami, Hu & Adams 2013; CPU only): p_b leaves the EOS and the momentum equation and only moves the particles, through ṽ = v + (dt/2)a_b, and the momentum equation carries their artificial stress A = ρv⊗(ṽ − v) (docs/PHYSICS.md §7.5). Its price in motion is in the rows 'max fluid speed' and 'liquid kinetic energy'; the [0.7t_end, t_end] rows against the 0.2-wide window show any sloshing about the cap. In the thesis's form p_b acts in the momentum equation; relax-60's p_b is fixed in units of σ/R (../convergence/summary.md, ../convergence/pb-check/README.md); the transport form at other p_b: ../pb-sweep/summary.md.", ph.c0));
            notes.push("Mode B's equilibrium against the interpolation line's anchor, the Algorithm 1 band and its κh restriction (docs/PHYSICS.md §8 ambiguities 2–4) and the background pressure: anchor-check/README.md.".into());
        }
        notes
    }

    /// The series of a run, the spread rescaled to R0 (the series' spread factor is x_tp over the
    /// initial shape's radius), so that every variant's D/D0 has the same D0.
    fn read(&self, dir: &std::path::Path, start_deg: f64) -> RunSeries {
        let mut rows = read_series(dir);
        let to_r0 = if start_deg == 90.0 { 1.0 } else { start_cap(start_deg).radius / R0 };
        for r in &mut rows {
            r.spread_factor = r.spread_factor.map(|d| d * to_r0);
        }
        let dev = |f: fn(&SRow) -> Option<f64>| col(&rows, move |r| f(r).map(|v| v - 60.0));
        let (circle, two, area) = (dev(|r| r.theta_circle_fit), dev(|r| r.theta_two_point), dev(|r| r.theta_area));
        let spread = col(&rows, |r| r.spread_factor);
        let wall = wall_spread(&rows, self.geometry.0);
        RunSeries { rows, circle, two, area, spread, wall }
    }
}

impl Relax {
    /// The plotted series of a run and its wall-shear profiles in the early and the end window
    /// (also as rows of the table, `variant_index` = `k`).
    fn series(
        &self,
        (k, label): (usize, &str),
        s: &RunSeries,
        [early, late]: &[Vec<(f64, f64)>; 2],
        out: &mut CaseOutput,
    ) {
        let angle = out.plot(ANGLE_PLOT);
        angle.series.push(Series::line(format!("{label}: circle fit"), s.circle.clone()));
        if k == 0 {
            angle.series.push(Series::points(format!("{label}: two-point (per row)"), s.two.clone()));
            angle.series.push(Series::line(format!("{label}: area inversion"), s.area.clone()));
        }
        out.plot(SPREAD_PLOT).series.push(Series::line(label.to_string(), s.spread.clone()));
        let (colour, marker) = shear_look(&self.variants, k);
        for (file, profile) in SHEAR_PLOTS.into_iter().zip([early, late]) {
            let line = Series::line_points(label, profile.clone()).with_palette_colour(colour).with_marker(marker);
            out.plot(file).series.push(line);
        }
        let table = out.table(SHEAR_TABLE);
        for (window, profile) in [(0.0, early), (1.0, late)] {
            table.extend(profile.iter().map(|(x, g)| vec![k as f64, window, *x, *g]));
        }
    }

    /// D/D0 at the first row against the analytic cap there (quick: that it grows), and at the
    /// wall against 1.385 (the full runs' verdicts: validate::judge).
    fn spread_rows(&self, label: &str, s: &RunSeries, out: &mut CaseOutput) {
        let ((d_an, d_row), (wa, wb, wtext)) = (self.spread, &self.window);
        let d_end = window_stats(&s.spread, *wa, *wb).map_or(f64::NAN, |s| s.0);
        let row =
            Row::new(&format!("{label}: D/D0 at the first row (Δx/2), mean over {wtext}"), d_end, 3, None, Some(d_row))
                .thesis_text("within 1–1.4 (Fig. 4.13)");
        let rows = &mut out.rep.rows;
        rows.push(if self.quick {
            let d0 = s.spread.first().map_or(f64::NAN, |p| p.1);
            row.check(d_end > d0, &format!("D/D0 grows from {d0:.3} (direction)"))
        } else {
            row
        });
        if !self.quick {
            let dw = window_stats(&s.wall, *wa, *wb).map_or(f64::NAN, |s| s.0);
            let row = Row::new(&format!("{label}: D/D0 at the wall, mean over {wtext}"), dw, 3, None, Some(d_an));
            // Judged against the 60° cap by validate::judge.
            rows.push(row);
        }
    }

    /// θ − 60° by the three methods over the end window (quick: that the circle fit falls; the
    /// full runs' verdicts: validate::judge).
    fn angle_rows(&self, label: &str, s: &RunSeries, out: &mut CaseOutput) {
        let (quick, (wa, wb, wtext)) = (self.quick, &self.window);
        for (name, pts) in [("circle fit", &s.circle), ("two-point", &s.two), ("area inversion", &s.area)] {
            if let Some((mean, std, n)) = window_stats(pts, *wa, *wb) {
                let r =
                    Row::new(&format!("{label}: θ − 60°, {name}, mean over {wtext} (deg)"), mean, 2, None, Some(0.0))
                        .sphlab_text(format!("{mean:.2} ± {std:.2} (n = {n})"));
                // The full runs' angles are judged against Young's angle by validate::judge.
                out.rep.rows.push(if quick && name == "circle fit" {
                    let th0 = s.circle.first().map_or(f64::NAN, |p| p.1);
                    r.check(mean < th0, &format!("θ decreases from {:.1}° (direction)", th0 + 60.0))
                } else {
                    r
                });
            }
        }
    }

    /// The price of each form in motion that is not the relaxation: the largest fluid speed and
    /// density error once the drop is near its cap (t ≥ 1), and the equilibrium over the whole
    /// second part of the run (a 0.2-wide window samples any sloshing about it).
    fn motion_rows(&self, label: &str, s: &RunSeries, out: &mut CaseOutput) {
        let (t_end, d_an) = (self.t_end, self.spread.0);
        let rows = &mut out.rep.rows;
        let speed = col(&s.rows, |r| Some(r.max_speed));
        let dens = col(&s.rows, |r| Some(r.max_density_error));
        if let Some((m, sd, _)) = window_stats(&speed, 1.0, t_end) {
            rows.push(
                Row::new(&format!("{label}: max fluid speed, mean over t ∈ [1, {t_end}]"), m, 3, None, Some(0.0))
                    .sphlab_text(format!("{m:.3} ± {sd:.3}")),
            );
        }
        let mut ke: Vec<f64> = s.rows.iter().filter(|r| r.t >= 1.0).map(|r| r.kinetic_energy).collect();
        ke.sort_by(f64::total_cmp);
        if let Some(&med) = ke.get(ke.len() / 2) {
            rows.push(
                Row::new(&format!("{label}: liquid kinetic energy, median over t ∈ [1, {t_end}]"), med, 3, None, None)
                    .sphlab_text(format!("{med:.2e}")),
            );
        }
        let peak = dens.iter().filter(|p| p.0 >= 1.0).map(|p| p.1).fold(f64::NAN, f64::max);
        if peak.is_finite() {
            rows.push(Row::new(&format!("{label}: max |ρ/ρ0 − 1|, t ≥ 1"), peak, 3, None, Some(0.0)));
        }
        let half = 0.7 * t_end;
        if let (Some(dm), Some(cm)) = (window_stats(&s.wall, half, t_end), window_stats(&s.circle, half, t_end)) {
            let over = format!("t ∈ [{half:.1}, {t_end}]");
            rows.push(
                Row::new(&format!("{label}: D/D0 at the wall, mean over {over}"), dm.0, 3, None, Some(d_an))
                    .sphlab_text(format!("{:.3} ± {:.3} (n = {})", dm.0, dm.1, dm.2)),
            );
            rows.push(
                Row::new(&format!("{label}: θ − 60°, circle fit, mean over {over} (deg)"), cm.0, 2, None, Some(0.0))
                    .sphlab_text(format!("{:.2} ± {:.2} (n = {})", cm.0, cm.1, cm.2)),
            );
        }
    }
}

impl Relax {
    /// dθ/dt over the end window; for the long runs, whether the angle has reached a plateau
    /// (the area-inversion angle over the two halves of the second part of the run, within
    /// 0.5°) and where the angle at the wall leads the cap's.
    fn rate_rows(&self, label: &str, s: &RunSeries, out: &mut CaseOutput) {
        let (quick, t_end, (wa, wb, wtext)) = (self.quick, self.t_end, &self.window);
        let rep = &mut out.rep;
        let win: Vec<&(f64, f64)> = s.circle.iter().filter(|p| p.0 >= *wa && p.0 <= *wb).collect();
        if let (Some(a), Some(b)) = (win.first(), win.last()) {
            if b.0 > a.0 {
                let rate = (b.1 - a.1) / (b.0 - a.0);
                let name = format!("{label}: dθ/dt (circle fit) over {wtext} (deg/time)");
                rep.rows.push(Row::new(&name, rate, 2, None, Some(0.0)));
            }
        }
        let (h1, h2) = (window_stats(&s.area, 0.3 * t_end, 0.6 * t_end), window_stats(&s.area, 0.7 * t_end, t_end));
        if let (Some(h1), Some(h2), false) = (h1, h2, quick) {
            let steady = (h1.0 - h2.0).abs() < 0.5;
            rep.notes.push(format!(
                "{label}: θ (area inversion) {:.2}° ± {:.2} over t ∈ [{:.1}, {:.1}] and {:.2}° ± {:.2} over [{:.1}, {t_end:.1}]: {}",
                h1.0 + 60.0,
                h1.1,
                0.3 * t_end,
                0.6 * t_end,
                h2.0 + 60.0,
                h2.1,
                0.7 * t_end,
                if steady {
                    "a plateau (the two means within 0.5°): the contact line has stopped; the two-start rows say whether it is pinned or at the model's own equilibrium"
                } else {
                    "still moving"
                }
            ));
        }
        if let (Some(c), Some(t2)) = (window_stats(&s.circle, *wa, *wb), window_stats(&s.two, *wa, *wb)) {
            if t2.0 < c.0 - 5.0 && !quick {
                rep.notes.push(format!(
                    "{label}: at the wall (two-point, rows 1–2) θ = {:.1}° while the circle fit of the cap gives {:.1}° over {wtext}.",
                    t2.0 + 60.0,
                    c.0 + 60.0
                ));
            }
        }
    }

    /// The wall-shear profiles of a run in the early and the end window, from its particle
    /// snapshots; for a reused run with none in this checkout, the committed report's (its table
    /// rows of variant `k`, each vouched for by its committed peak row), with a note.
    fn shear_profiles(
        &self,
        ctx: &Ctx,
        (k, label): (usize, &str),
        dir: &std::path::Path,
        s: &RunSeries,
        out: &mut CaseOutput,
    ) -> [Vec<(f64, f64)>; 2] {
        let ((dx, y_w, x_max), (ea, eb), (wa, wb, _)) = (self.geometry, self.early, &self.window);
        if !snapshot_files(dir).is_empty() {
            return [(ea, eb), (*wa, *wb)].map(|w| mean_shear_profile_in(dir, &s.rows, w, dx, y_w, x_max, 20, false));
        }
        let Some(c) = Committed::load(ctx) else { return [Vec::new(), Vec::new()] };
        let windows = self.shear_windows();
        let profiles = [0.0, 1.0].map(|w| {
            let rows = c.table(SHEAR_TABLE, |r| r.len() == 4 && r[0] == k as f64 && r[1] == w);
            let profile = rows.iter().map(|r| (r[2], r[3])).collect();
            vouched(profile, c.value(&peak_name(label, &windows[w as usize])))
        });
        if profiles.iter().any(|p| !p.is_empty()) {
            out.rep.notes.push(format!(
                "{label}: wall shear as the committed report measured it ({SHEAR_TABLE} and its peak rows): this checkout holds none of the run's particle snapshots."
            ));
        }
        profiles
    }

    /// The texts of the early and the end window of the wall shear.
    fn shear_windows(&self) -> [String; 2] {
        let (ea, eb) = self.early;
        [format!("t ∈ [{ea:.2}, {eb:.2}]"), self.window.2.clone()]
    }

    /// The peak wall shear in the early and the end window (a reused run written with sparser
    /// snapshots, the convergence case's, may have none in a window: a note then, as a NaN
    /// would not survive case.json).
    fn shear_rows(&self, label: &str, [early, late]: &[Vec<(f64, f64)>; 2], out: &mut CaseOutput) {
        let pk = |p: &[(f64, f64)]| p.iter().map(|q| q.1).fold(f64::NAN, f64::max);
        for (window, profile) in self.shear_windows().into_iter().zip([early, late]) {
            if profile.is_empty() {
                out.rep
                    .notes
                    .push(format!("{label}: no particle snapshot in {window}, so no wall shear profile there."));
            } else {
                out.rep.rows.push(Row::new(&peak_name(label, &window), pk(profile), 4, None, None));
            }
        }
    }
}

impl Case for Relax {
    fn spec(&self, ctx: &Ctx) -> CaseSpec {
        CaseSpec {
            name: "relax-60",
            reference: "Thesis §4.2.3, Figs. 4.10–4.15 (docs/PHYSICS.md §9(c)): 90° → 60° relaxation",
            runs: self.variants.iter().map(|v| self.run_of(ctx, v)).collect(),
            not_full: self.not_full(),
            plots: self.plots(),
            tables: vec![CaseTable {
                file: SHEAR_TABLE,
                header: "variant_index,late_window,wall_fraction,mean_abs_shear_rate".into(),
                rows: Vec::new(),
            }],
            method_notes: self.method_notes(),
        }
    }

    fn measure(
        &mut self,
        ctx: &Ctx,
        run: &CaseRun,
        rec: &RunRecord,
        out: &mut CaseOutput,
    ) -> Result<(), ValidateError> {
        let k = self.variants.iter().position(|v| v.id == run.spec.id).expect("a run of the case's variants");
        let (id, label, start_deg, from_90) = {
            let v = &self.variants[k];
            (v.id, v.label, v.start_deg, v.from_90)
        };
        let dir = PathBuf::from(&rec.dir);
        let s = self.read(&dir, start_deg);
        if id == "b-noslip" {
            self.b_circle = s.circle.clone();
        }
        let profiles = self.shear_profiles(ctx, (k, label), &dir, &s, out);
        self.series((k, label), &s, &profiles, out);
        self.spread_rows(label, &s, out);
        self.angle_rows(label, &s, out);
        if let Some((m, _, _)) = window_stats(&s.circle, self.window.0, self.window.1) {
            self.end_angle.push((id, label, start_deg, from_90, m + 60.0));
        }
        if !self.quick {
            self.motion_rows(label, &s, out);
        }
        self.rate_rows(label, &s, out);
        self.shear_rows(label, &profiles, out);
        Ok(())
    }

    fn compare(&mut self, ctx: &Ctx, out: &mut CaseOutput) -> Result<(), ValidateError> {
        let (wa, wb, wtext) = (self.window.0, self.window.1, self.window.2.as_str());
        two_starts(&self.end_angle, wtext, &mut out.rep);
        if !self.quick && self.nx != 65 {
            let angle = &mut out.plots.iter_mut().find(|p| p.file == ANGLE_PLOT).expect("the angle plot").plot;
            dt_comparison(ctx, self.nx, self.t_end, (wa, wb, wtext), &self.b_circle, &mut out.rep, angle);
        }
        shared_y_range(out, &SHEAR_PLOTS);
        Ok(())
    }
}

/// The look of variant `k` in the wall-shear plots: its palette colour, one per mode, wall and
/// form (a run from below 60° in its from-90° sibling's colour), and a circle from 90°, a
/// triangle from below.
pub(super) fn shear_look(variants: &[Variant], k: usize) -> (usize, Marker) {
    let v = &variants[k];
    let family = v.from_90.unwrap_or(v.id);
    let colour = variants.iter().filter(|w| w.from_90.is_none()).position(|w| w.id == family);
    (colour.unwrap_or(k), if v.from_90.is_some() { Marker::Triangle } else { Marker::Circle })
}

/// The row of a run's peak wall shear in a window (also how the committed profile is vouched for).
fn peak_name(label: &str, window: &str) -> String {
    format!("{label}: peak wall shear, {window} (1/time)")
}

/// One y range for the plots `files` (log axes: their positive values), so that the windows'
/// profiles read against each other.
fn shared_y_range(out: &mut CaseOutput, files: &[&str]) {
    let plots = || out.plots.iter().filter(|p| files.contains(&p.file));
    let ys = plots().flat_map(|p| p.plot.series.iter().flat_map(|s| s.points.iter().map(|q| q.1)));
    let (lo, hi) = ys.filter(|y| *y > 0.0).fold((f64::INFINITY, 0.0f64), |(lo, hi), y| (lo.min(y), hi.max(y)));
    if lo < hi {
        for p in out.plots.iter_mut().filter(|p| files.contains(&p.file)) {
            p.plot.y_range = Some((lo / 1.5, hi * 1.5));
        }
    }
}
