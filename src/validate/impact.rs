//! Case `impact` (docs/PHYSICS.md §9(e), thesis §5.2, Figs. 5.3–5.5): 2D water drop impact at
//! Re = 440, We = 6.86 with a constant contact angle θ = 50…175° (Mode B). D/D0 vs
//! τ = 4μt/(ρD0²) until the maximum, and D_max/D0 against the analytic models of
//! `crate::analytic` (axisymmetric Pasandideh-Fard and the thesis's 2D model (c)).
//!
//! The full resolution (100×100, dt ≈ 1e-8 s, 1.65 ms) costs hours per angle on a CPU: unless
//! `--full-impact` is given, the case measures ms/step at full resolution over 100 steps,
//! states the projected time, and runs all nine angles to the full 1.65 ms at `CPU_NX` (the
//! finest resolution whose nine runs fit in one session on the machine the committed report
//! names) and again at
//! `CHECK_NX`, so that the report shows how far the answer moves with the resolution.

use super::data::{col, read_series};
use super::report::{plot, write_csv, Band, CaseReport, Row};
use super::{Ctx, RunSpec, ValidateError};
use crate::analytic::{spread_2d_c, spread_axisym};
use crate::plot::{PlotSpec, Series};
use crate::run::RunOptions;
use std::path::{Path, PathBuf};

/// Thesis angles (degrees).
pub const ANGLES: [f64; 9] = [50.0, 70.0, 90.0, 100.0, 110.0, 130.0, 145.0, 160.0, 175.0];
/// Quick angles.
pub const QUICK_ANGLES: [f64; 2] = [50.0, 160.0];
/// Reynolds and Weber numbers of the case.
pub const RE: f64 = 440.0;
/// Weber number.
pub const WE: f64 = 6.86;
/// Resolution of the CPU case (particles across the 1125 µm half domain; 10.7 drop particles
/// per radius, Δx = 23.4 µm); its cost per angle is in `reports/validation/impact/`.
pub const CPU_NX: u32 = 48;
/// Coarser resolution: the quick case and the CPU case's resolution check (5.3 particles per
/// radius, Δx = 46.9 µm).
pub const CHECK_NX: u32 = 24;
/// End time of the full case (s).
pub const T_END: f64 = 1.65e-3;
/// End time of the quick case (s): 0.225 ms after contact.
pub const QUICK_T_END: f64 = 0.35e-3;

/// τ = 4μt/(ρD0²) of water, D0 = 500 µm.
pub fn tau(t: f64) -> f64 {
    4.0 * 1.136e-3 * t / (1000.0 * 500e-6 * 500e-6)
}

/// The run spec at angle `theta` on `nx` (None: the scene's full resolution) to `t_end`; its id
/// is `theta50` at full resolution, `theta50-nx48` on `nx = 48`.
pub fn spec(theta: f64, nx: Option<u32>, t_end: f64) -> RunSpec<'static> {
    let mut sets = vec![format!("contact.theta_deg={theta}")];
    let mut id = format!("theta{theta:.0}");
    if let Some(nx) = nx {
        sets.push(format!("domain.nx={nx}"));
        sets.push("output.every=200".into());
        id += &format!("-nx{nx}");
    }
    RunSpec::new(id, "impact", &sets, Some(t_end), 0)
}

/// What one impact run gives: D/D0 against τ, its maximum, D/D0 at the end, the largest relative
/// drift of the water mass and whether every row is finite.
struct Spread {
    d: Vec<(f64, f64)>,
    max: f64,
    end: f64,
    drift: f64,
    finite: bool,
}

fn spread_of(rec: &crate::validate::RunRecord) -> Spread {
    let rows = read_series(&PathBuf::from(&rec.dir));
    let d: Vec<(f64, f64)> = col(&rows, |r| r.spread_factor).into_iter().map(|(t, v)| (tau(t), v)).collect();
    let m0 = rows.first().map_or(f64::NAN, |r| r.mass_phase0);
    Spread {
        max: d.iter().map(|p| p.1).fold(f64::NAN, f64::max),
        end: d.last().map_or(f64::NAN, |p| p.1),
        drift: rows.iter().map(|r| (r.mass_phase0 / m0 - 1.0).abs()).fold(0.0, f64::max),
        finite: rows.iter().all(|r| r.kinetic_energy.is_finite() && r.max_speed.is_finite()),
        d,
    }
}

/// Whether a maximum spread lies in the band of Fig. 5.5's check: within [0.9·min, 1.1·max] of
/// the axisymmetric and the 2D model (c).
fn in_band(m: f64, axisym: f64, model_c: f64) -> bool {
    m >= 0.9 * axisym.min(model_c) && m <= 1.1 * axisym.max(model_c)
}

/// The steps between consecutive angles where D_max/D0 rises with θ.
fn rising(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points.windows(2).filter(|w| w[1].1 > w[0].1).map(|w| (w[0].0, w[1].0)).collect()
}

fn rises_count(points: &[(f64, f64)]) -> usize {
    rising(points).len()
}

/// "falls at every step", or where it rises.
fn rises(points: &[(f64, f64)]) -> String {
    let r = rising(points);
    if r.is_empty() {
        return "falls at every step".into();
    }
    let at: Vec<String> = r.iter().map(|(a, b)| format!("{a:.0}°→{b:.0}°")).collect();
    format!("rises at {}", at.join(", "))
}

/// Runs `spec`, or notes it as not run under `--skip-missing` (None).
fn run_or_skip(
    ctx: &Ctx,
    rep: &mut CaseReport,
    spec: &RunSpec,
) -> Result<Option<crate::validate::RunRecord>, ValidateError> {
    match ctx.run(spec, &[]) {
        Ok(r) => Ok(Some(r)),
        Err(ValidateError::Skipped(id)) => {
            rep.notes.push(format!("run {id} was not run (--skip-missing)."));
            Ok(None)
        }
        Err(e) => Err(e),
    }
}

/// The mass row of a run: exact, status ok, no NaN. An invariant, not a pass: particle masses
/// are fixed, so the water mass is exact by construction.
fn mass_row(label: &str, s: &Spread, rec: &crate::validate::RunRecord) -> Row {
    Row::new(label, s.drift, 2, None, Some(0.0))
        .sphlab_text(format!("{:.1e}", s.drift))
        .invariant(s.drift < 1e-12 && rec.status == "ok" && s.finite, "mass exact, status ok, no NaN")
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    let quick = ctx.opts.quick;
    let full = ctx.opts.full_impact && !quick;
    let mut rep = CaseReport::new(
        "impact",
        "Thesis §5.2, Figs. 5.3–5.5 (docs/PHYSICS.md §9(e)): 2D drop impact, Re = 440, We = 6.86",
        quick,
    );
    if !quick && !full {
        probe_full_resolution(ctx, &mut rep)?;
    }
    let (angles, nx, t_end): (Vec<f64>, Option<u32>, f64) = if quick {
        (QUICK_ANGLES.to_vec(), Some(CHECK_NX), QUICK_T_END)
    } else if full {
        (ANGLES.to_vec(), None, T_END)
    } else {
        (ANGLES.to_vec(), Some(CPU_NX), T_END)
    };
    // the CPU case runs each angle again at CHECK_NX
    let check_nx = (!quick && !full).then_some(CHECK_NX);
    let reached = t_end >= T_END;
    let mut spread = PlotSpec::new(
        format!("Drop impact: D/D0 vs τ (Fig. 5.3){}", nx.map_or(String::new(), |n| format!(", nx = {n}"))),
        "τ = 4μt/(ρD0²)",
        "D/D0",
    );
    let mut dmax = PlotSpec::new("Drop impact: D_max/D0 vs θ (Fig. 5.5)", "contact angle θ (degrees)", "D_max/D0");
    let (mut sph, mut sph_check, mut axi, mut mc) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut csv = Vec::new();
    let mut at_end = Vec::new();
    // (angles in the band of Fig. 5.5's check, angles run) at nx and at check_nx
    let (mut band, mut band_check) = ((0usize, 0usize), (0usize, 0usize));
    for &th in &angles {
        let a = spread_axisym(RE, WE, th.to_radians()).unwrap_or(f64::NAN);
        let c = spread_2d_c(RE, WE, th.to_radians()).map_or(f64::NAN, |s| s.xi);
        axi.push((th, a));
        mc.push((th, c));
        let main = run_or_skip(ctx, &mut rep, &spec(th, nx, t_end))?.map(|r| (spread_of(&r), r));
        let check = match check_nx {
            Some(n) => run_or_skip(ctx, &mut rep, &spec(th, Some(n), t_end))?.map(|r| (n, spread_of(&r), r)),
            None => None,
        };
        let max = main.as_ref().map_or(f64::NAN, |m| m.0.max);
        let mut line = vec![th, max, a, c];
        if let Some((s, rec)) = main {
            spread.series.push(Series::line(format!("θ = {th:.0}°"), s.d.clone()));
            sph.push((th, s.max));
            at_end.push((th, s.end));
            let label = match (reached, nx) {
                (false, _) => format!("θ = {th:.0}°: max D/D0 for t ≤ {:.2} ms", t_end * 1e3),
                (true, Some(n)) => format!("θ = {th:.0}°: D_max/D0 (nx = {n})"),
                (true, None) => format!("θ = {th:.0}°: D_max/D0"),
            };
            // the analytic maxima only compare with a run that reaches the maximum; the pass/FAIL
            // band only with the thesis's resolution
            let row = Row::new(&label, s.max, 3, None, if reached { Some(c) } else { None })
                .thesis_text("between axisym and (c) (Fig. 5.5)")
                .analytic_text(&format!("axisym {a:.3}; 2D (c) {c:.3}"));
            band.0 += usize::from(in_band(s.max, a, c));
            band.1 += 1;
            rep.rows.push(if full {
                row.check(in_band(s.max, a, c), "within [0.9·min, 1.1·max] of axisym, (c)")
            } else {
                row
            });
            rep.rows.push(mass_row(&format!("θ = {th:.0}°: max relative drift of the water mass"), &s, &rec));
            rep.runs.push(rec);
        }
        if let Some((n, sc, rc)) = check {
            sph_check.push((th, sc.max));
            line.push(sc.max);
            band_check.0 += usize::from(in_band(sc.max, a, c));
            band_check.1 += 1;
            let text = match (max.is_finite(), nx) {
                (true, Some(m)) => {
                    format!("{:.3} (nx = {m} is {:+.1} % from it)", sc.max, 100.0 * (max / sc.max - 1.0))
                }
                _ => format!("{:.3}", sc.max),
            };
            rep.rows.push(
                Row::new(&format!("θ = {th:.0}°: D_max/D0 at nx = {n} (resolution check)"), sc.max, 3, None, Some(c))
                    .sphlab_text(text)
                    .analytic_text(&format!("2D (c) {c:.3}")),
            );
            rep.rows.push(mass_row(&format!("θ = {th:.0}°: nx = {n}: max relative drift of the water mass"), &sc, &rc));
            rep.runs.push(rc);
        } else if check_nx.is_some() {
            line.push(f64::NAN);
        }
        csv.push(line);
    }
    across_angles(&mut rep, (reached, full), (nx, check_nx), (&sph, &sph_check), (band, band_check), &at_end, t_end);
    let name = nx.map_or("sphlab".to_string(), |n| format!("sphlab nx = {n}"));
    dmax.series = vec![Series::line_points(&name, sph)];
    if let Some(n) = check_nx {
        dmax.series.push(Series::line_points(format!("sphlab nx = {n}"), sph_check));
    }
    dmax.series.push(Series::line("axisymmetric (Pasandideh-Fard)", axi));
    dmax.series.push(Series::line("2D model (c), eq. (93)", mc));
    plot(ctx, &mut rep, "fig5_3_spread_vs_tau.svg", &spread)?;
    plot(ctx, &mut rep, "fig5_5_dmax_vs_theta.svg", &dmax)?;
    let header = match check_nx {
        Some(n) => format!("theta_deg,sphlab_dmax,axisym,model_c,sphlab_dmax_nx{n}"),
        None => "theta_deg,sphlab_dmax,axisym,model_c".to_string(),
    };
    write_csv(ctx, &mut rep, "dmax.csv", &header, &csv)?;
    rep.notes.push(
        "D = 2 × (outermost first-row water particle + Δx/2); τ = 4μ_L t/(ρ_L D0²) (τ = 0.03 at 1.65 ms).".into(),
    );
    if !reached {
        rep.notes.push("Quick: the run stops 0.225 ms after contact, well before the maximum; only the direction (50° spreads more than 160°) and the conservation are checked.".into());
    }
    Ok(rep)
}

/// The cost of the full resolution, measured over 100 steps (or a finished probe reused): the
/// ms/step, dt and projected hours per angle, and why the case runs coarser.
fn probe_full_resolution(ctx: &Ctx, rep: &mut CaseReport) -> Result<(), ValidateError> {
    let dir = ctx.dir.join("runs").join("probe");
    let reuse = crate::validate::RunRecord::load(&dir, "", true)
        .filter(|r| ctx.opts.reuse && r.status == "ok" && r.steps == 100);
    let rec = match reuse {
        Some(r) => r,
        None => {
            let scene = crate::scene::builtin::impact(90.0);
            let opts = RunOptions {
                steps: Some(100),
                every: 0,
                out: dir.clone(),
                backend: ctx.opts.backend,
                ..RunOptions::default()
            };
            crate::run::run(&scene, &opts).map_err(|err| ValidateError::Run { id: "probe".into(), err })?;
            crate::validate::RunRecord::load(&dir, "", false)
                .ok_or_else(|| ValidateError::Io("probe: no summary".into()))?
        }
    };
    let dt = rec.t_final / rec.steps as f64;
    let steps = T_END / dt;
    let hours = steps * rec.ms_per_step / 3.6e6;
    rep.rows.push(Row::new(
        "full resolution: ms/step (100×100, 10,000 fluid particles)",
        rec.ms_per_step,
        1,
        None,
        None,
    ));
    rep.rows.push(
        Row::new("full resolution: dt (s)", dt, 10, Some(1e-8), None)
            .sphlab_text(format!("{dt:.3e}"))
            .thesis_text("≈ 1e-8"),
    );
    rep.rows.push(Row::new("full resolution: projected hours per angle (1.65 ms)", hours, 1, None, None));
    rep.not_full_because(format!(
        "full resolution not run: {:.1} ms/step measured over 100 steps × {:.0} steps (dt = {:.3e} s to 1.65 ms) ≈ {:.1} h per angle, {:.0} h for the 9 angles on this CPU; ran all nine angles to 1.65 ms at nx = {CPU_NX} (Δx = {:.1} µm, the finest whose nine angles fit in one session on 2 cores) instead, and again at nx = {CHECK_NX} (Δx = {:.1} µm) as a resolution check",
        rec.ms_per_step,
        steps,
        dt,
        hours,
        9.0 * hours,
        1125.0 / CPU_NX as f64,
        1125.0 / CHECK_NX as f64
    ));
    let mut probe = rec;
    probe.command = "sphlab run impact --steps 100 --every 0".into();
    rep.runs.push(probe);
    Ok(())
}

/// `(θ, D_max/D0)` of the angles run at one resolution.
type Maxima = [(f64, f64)];

/// The rows across the angles: how many maxima lie in the thesis's band and where D_max/D0
/// rises with θ (a run that reaches the maximum, below full resolution), and the direction
/// check of the spread at the end.
fn across_angles(
    rep: &mut CaseReport,
    (reached, full): (bool, bool),
    (nx, check_nx): (Option<u32>, Option<u32>),
    (sph, sph_check): (&Maxima, &Maxima),
    (band, band_check): ((usize, usize), (usize, usize)),
    at_end: &[(f64, f64)],
    t_end: f64,
) {
    if reached && !full {
        // the thesis's band, counted (its pass/FAIL is for the full resolution only)
        let mut text = format!("{} of {} at nx = {}", band.0, band.1, nx.unwrap_or(0));
        if let Some(n) = check_nx {
            text += &format!("; {} of {} at nx = {n}", band_check.0, band_check.1);
        }
        rep.rows.push(
            Row::new("angles with D_max/D0 within [0.9·min, 1.1·max] of axisym, (c)", band.0 as f64, 0, None, None)
                .sphlab_text(text)
                .thesis_text("all (Fig. 5.5)"),
        );
        let mut text = format!("nx = {}: {}", nx.unwrap_or(0), rises(sph));
        if let Some(n) = check_nx {
            text += &format!("; nx = {n}: {}", rises(sph_check));
        }
        rep.rows.push(
            Row::new("D_max/D0 against θ: steps where it rises", rises_count(sph) as f64, 0, None, None)
                .sphlab_text(text)
                .thesis_text("falls with θ (Fig. 5.5)"),
        );
    }
    // The direction needs two angles (a part of the GPU report runs one).
    if let (Some(a), Some(b), true) = (at_end.first(), at_end.last(), at_end.len() >= 2) {
        rep.rows.push(
            Row::new(
                &format!("D/D0 at t = {:.2} ms: θ = {:.0}° minus θ = {:.0}°", t_end * 1e3, a.0, b.0),
                a.1 - b.1,
                3,
                None,
                None,
            )
            .check(a.1 > b.1, "the hydrophilic drop spreads more (direction)"),
        );
    }
}

/// The sensitivity band of the direction row ("D/D0 at t = … ms: θ = A° minus θ = B°", `quantity`)
/// from the committed runs in `case_dir`: the same difference at the end of the runs at
/// [`CHECK_NX`] and at [`CPU_NX`], with whether the hydrophilic drop spreads more at both.
pub(super) fn direction_band(case_dir: &Path, quantity: &str) -> Option<Band> {
    let mut angles = quantity.split("θ = ").skip(1).map(|p| p.split('°').next().and_then(|a| a.parse::<f64>().ok()));
    let (a, b) = (angles.next()??, angles.next()??);
    let end = |th: f64, nx: u32| {
        let rows = read_series(&case_dir.join("runs").join(spec(th, Some(nx), T_END).id));
        col(&rows, |r| r.spread_factor).last().map(|p| p.1)
    };
    let diff: Vec<f64> =
        [CHECK_NX, CPU_NX].into_iter().map(|nx| Some(end(a, nx)? - end(b, nx)?)).collect::<Option<_>>()?;
    Some(Band {
        varied: format!("nx = {CHECK_NX} / {CPU_NX}"),
        values: diff.iter().map(|d| format!("{d:.3}")).collect(),
        source: format!("runs/theta{a:.0}-nx{{{CHECK_NX},{CPU_NX}}}, runs/theta{b:.0}-nx{{{CHECK_NX},{CPU_NX}}}"),
        holds: Some(diff.iter().all(|d| *d > 0.0)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_direction_rows_band_is_the_same_difference_at_the_check_resolution() {
        let dir = tempfile::tempdir().unwrap();
        let q = "D/D0 at t = 1.65 ms: θ = 50° minus θ = 175°";
        assert!(direction_band(dir.path(), q).is_none(), "no runs, no band");
        for (id, ends) in [
            ("theta50-nx24", [3.0, 4.1]),
            ("theta175-nx24", [1.0, 4.3]),
            ("theta50-nx48", [2.0, 3.7]),
            ("theta175-nx48", [1.0, 0.6]),
        ] {
            let run = dir.path().join("runs").join(id);
            std::fs::create_dir_all(&run).unwrap();
            let mut w = csv::Writer::from_path(run.join("series.csv")).unwrap();
            for (t, d) in [(1e-3, ends[0]), (T_END, ends[1])] {
                w.serialize(crate::run::SeriesRow { t, spread_factor: Some(d), ..Default::default() }).unwrap();
            }
            w.flush().unwrap();
        }
        let band = direction_band(dir.path(), q).unwrap();
        assert_eq!(band.values, ["-0.200", "3.100"], "the last rows, nx = 24 then 48");
        assert_eq!(band.holds, Some(false), "the direction reverses at nx = 24");
        assert_eq!(band.source, "runs/theta50-nx{24,48}, runs/theta175-nx{24,48}");
    }

    #[test]
    fn run_ids_name_the_resolution_except_the_full_one() {
        assert_eq!(spec(50.0, None, T_END).id, "theta50");
        assert_eq!(spec(50.0, Some(CPU_NX), T_END).id, "theta50-nx48");
        assert_eq!(spec(175.0, Some(CHECK_NX), QUICK_T_END).id, "theta175-nx24");
        // the GPU preset runs full-resolution ids
        assert!(crate::study::preset::IMPACT_RUNS.iter().all(|id| !id.contains("-nx")));
    }

    #[test]
    fn band_of_fig_5_5_is_ten_percent_outside_the_two_models() {
        let t = 90f64.to_radians();
        let a = spread_axisym(RE, WE, t).unwrap();
        let c = spread_2d_c(RE, WE, t).unwrap().xi;
        assert!(in_band(2.786, a, c) && in_band(0.91 * a, a, c) && in_band(1.09 * c, a, c));
        assert!(!in_band(4.518, a, c) && !in_band(0.89 * a, a, c) && !in_band(1.11 * c, a, c));
    }

    #[test]
    fn rises_names_the_steps_where_the_spread_grows_with_theta() {
        assert_eq!(rises(&[(50.0, 4.4), (90.0, 2.8), (160.0, 1.9)]), "falls at every step");
        assert_eq!(rises(&[(50.0, 4.40), (70.0, 4.52), (90.0, 4.51), (175.0, 4.6)]), "rises at 50°→70°, 90°→175°");
        assert_eq!(rises_count(&[(50.0, 1.0), (70.0, 1.0)]), 0);
    }
}
