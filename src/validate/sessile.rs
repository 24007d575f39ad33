//! Case `sessile-90` (PHYSICS.md §9(b), thesis §4.2.2, Figs. 4.3–4.9): the 90° drop at rest on
//! a no-slip wall, Mode B (thesis method) and Mode A (three coefficients). Contact-angle
//! deviation from 90° by the three §10 methods, liquid kinetic energy, the wall shear-rate
//! profile averaged near t ≈ 4.4 (the last 10 % of a shortened run) and the maximum normal
//! deviation (Fig. 4.9). Thesis: Mode B < 3°, Mode A ±10°, Mode A's peak shear ≈ 160× Mode B's.

use super::data::{
    col, for_each_snapshot_in, normal_deviation_quantiles, normal_deviation_series, read_series, window_stats,
    Row as SRow, ShearMean,
};
use super::report::{plot, write_csv, CaseReport, Row};
use super::{Ctx, RunSpec, ValidateError};
use crate::plot::{PlotSpec, RefLine, Series};
use std::path::PathBuf;

/// Thesis: Mode B contact-angle deviation bound (degrees).
pub const THESIS_MODE_B_DEV: f64 = 3.0;
/// Thesis: Mode A deviation (degrees).
pub const THESIS_MODE_A_DEV: f64 = 10.0;
/// Thesis: ratio of Mode A's to Mode B's peak wall shear rate.
pub const THESIS_SHEAR_RATIO: f64 = 160.0;
/// Thesis Fig. 4.7 (Mode A): the average shear rate peaks at ≈ 2.5 near the triple point (its
/// axis runs to 2.5).
pub const THESIS_MODE_A_SHEAR_PEAK: f64 = 2.5;
/// Thesis Fig. 4.8 (Mode B): the average shear rate stays below 0.016 (its axis's top).
pub const THESIS_MODE_B_SHEAR_MAX: f64 = 0.016;
/// Half-width of the band around the contact line (fraction of the wall; the drop's edge is at
/// 0.5) over which the mean-flow wall shear near the contact line is taken: two bins each side.
const CONTACT_BAND: f64 = 0.1;

/// Quick-mode overrides of the sessile / relax scenes: 26×26 (13 particles per radius),
/// dt = 1.4e-4 (half the CFL limit there), a series row every 100 steps.
pub fn quick_sets() -> Vec<String> {
    vec!["domain.nx=26".into(), "time.dt=1.4e-4".into(), "output.every=100".into()]
}

/// The averaging window of the "equilibrium" shear profile: around t = 4.4 when the run
/// reaches 4.6, else its last 10 %.
pub fn shear_window(t_end: f64) -> (f64, f64, String) {
    if t_end >= 4.6 {
        (4.3, 4.5, "t ∈ [4.3, 4.5]".into())
    } else {
        (0.9 * t_end, t_end, format!("last 10 %: t ∈ [{:.3}, {:.3}]", 0.9 * t_end, t_end))
    }
}

/// Δx, y_w and the wall x extent of a sessile-type run.
pub fn geometry(nx: u32) -> (f64, f64, f64) {
    (0.5 / nx as f64, 0.0, 0.5)
}

/// Measured quantities of one sessile-type run.
pub struct Measured {
    /// Series rows.
    pub rows: Vec<SRow>,
    /// Averaged shear profile in the window (mean |γ̇|).
    pub shear: Vec<(f64, f64)>,
    /// The mean flow's shear profile over [`mean_flow_window`]: |time mean of signed γ̇| per bin.
    pub mean_flow: Vec<(f64, f64)>,
    /// Max normal deviation vs t.
    pub normal: Vec<(f64, f64)>,
    /// Averaged shear profile (mean |γ̇|) over [`startup_window`].
    pub startup: Vec<(f64, f64)>,
}

/// The start-up window: every snapshot after t = 0 up to t = 1 (or the run's end), where the
/// modes differ most (the thesis's kinetic energies, Figs. 4.5–4.6). The thesis does not say
/// over which time Figs. 4.7–4.8 average.
pub fn startup_window(t_end: f64) -> (f64, f64) {
    (1e-12, t_end.min(1.0))
}

/// The window of the mean-flow shear profile: after the start-up (t ≥ 1) to the end of the run
/// (its second half when it ends before t = 2). The thesis's "average shear rate" (Figs. 4.7, 4.8);
/// over ~60 snapshots the particle noise, which dominates |γ̇| in any one snapshot, cancels.
pub fn mean_flow_window(t_end: f64) -> (f64, f64) {
    (if t_end >= 2.0 { 1.0 } else { 0.5 * t_end }, t_end)
}

/// Reads a run back and measures the shear profile in `[a, b]`, the mean-flow shear profile over
/// [`mean_flow_window`], the start-up shear profile ([`startup_window`]) and the normal deviation.
pub fn measure(dir: &std::path::Path, nx: u32, a: f64, b: f64, t_end: f64) -> Measured {
    let (dx, y_w, x_max) = geometry(nx);
    let rows = read_series(dir);
    // Every snapshot read once, in step (so time) order, into each window it lies in.
    let windows = [(a, b), mean_flow_window(t_end), startup_window(t_end)];
    let mut means = [false, true, false].map(|signed| ShearMean::new(dx, y_w, x_max, 20, signed));
    for_each_snapshot_in(dir, &rows, f64::NEG_INFINITY, f64::INFINITY, |s| {
        for ((lo, hi), m) in windows.iter().zip(&mut means) {
            if s.t >= *lo && s.t <= *hi {
                m.add(&s);
            }
        }
    });
    let shear = means[0].profile();
    let mean_flow = means[1].profile().into_iter().map(|(x, g)| (x, g.abs())).collect();
    let normal = normal_deviation_series(dir, &rows, dx, y_w, [0.0, 0.0], 0.25, 3.0 * dx);
    let startup = means[2].profile();
    Measured { rows, shear, mean_flow, normal, startup }
}

pub(super) fn run(ctx: &Ctx) -> Result<CaseReport, ValidateError> {
    let quick = ctx.opts.quick;
    let mut rep =
        CaseReport::new("sessile-90", "Thesis §4.2.2, Figs. 4.3–4.9 (PHYSICS.md §9(b)): 90° drop at rest", quick);
    let t_end = ctx.opts.long_t_end(0.3);
    let nx = if quick { 26 } else { ctx.opts.long_nx() };
    let (wa, wb, wtext) = shear_window(t_end);
    let mut angle = PlotSpec::new(
        "Sessile 90°: contact-angle deviation from 90° (§4.2.2)",
        "t (nondimensional)",
        "θ − 90° (degrees)",
    );
    let mut ke = PlotSpec::new(
        "Sessile 90°: liquid kinetic energy (§4.2.2)",
        "t (nondimensional)",
        "kinetic energy of the liquid (nondimensional)",
    );
    ke.log_y = true;
    let mut shear = PlotSpec::new(
        format!("Sessile 90°: wall shear rate |∂u/∂y| along the wall, {wtext}"),
        "fraction of the wall (0 = drop centre, 1 = right wall)",
        "average shear rate (1/time)",
    );
    shear.log_y = true;
    let mut normal = PlotSpec::new(
        "Sessile 90°: maximum normal deviation (Fig. 4.9)",
        "t (nondimensional)",
        "max angle between n̂ and the radial direction (degrees)",
    );
    let (fa, fb) = mean_flow_window(t_end);
    let ftext = format!("t ∈ [{fa:.2}, {fb:.2}]");
    let mut mean_flow = PlotSpec::new(
        format!("Sessile 90°: mean-flow wall shear rate |⟨u/(y − y_w)⟩| along the wall, {ftext}"),
        "fraction of the wall (0 = drop centre, 1 = right wall)",
        "|time mean of the signed shear rate| (1/time)",
    );
    mean_flow.log_y = true;
    let mut peaks = Vec::new();
    let mut flow_peaks = Vec::new();
    // where along the wall each mode's mean flow peaks (fraction of the wall)
    let mut flow_xs = Vec::new();
    let mut cl_flows = Vec::new();
    let mut startup_peaks = Vec::new();
    let stext = format!("start-up t ∈ (0, {:.2}]", startup_window(t_end).1);
    let mut shear_csv: Vec<Vec<f64>> = Vec::new();
    for (id, mode, thesis_dev) in [("mode-b", "b", THESIS_MODE_B_DEV), ("mode-a", "a", THESIS_MODE_A_DEV)] {
        let mut sets =
            if quick { quick_sets() } else { ctx.opts.long_sets(crate::scene::builtin::at_rest_background_pressure) };
        sets.push(format!("contact.mode={mode}"));
        let rec = match ctx.run(&RunSpec::new(id, "sessile-90", &sets, Some(t_end), 2), &[]) {
            Ok(r) => r,
            Err(ValidateError::Skipped(s)) => {
                rep.not_full_because(format!("{s} not run (time)"));
                // every per-mode list keeps its slot (index 0: Mode B, 1: Mode A)
                peaks.push(f64::NAN);
                flow_peaks.push(f64::NAN);
                flow_xs.push(f64::NAN);
                cl_flows.push(f64::NAN);
                startup_peaks.push(f64::NAN);
                continue;
            }
            Err(e) => return Err(e),
        };
        let dir = PathBuf::from(&rec.dir);
        let m = measure(&dir, nx, wa, wb, t_end);
        let label = format!("Mode {}", mode.to_uppercase());
        let dev = |f: fn(&SRow) -> Option<f64>| col(&m.rows, move |r| f(r).map(|v| v - 90.0));
        let circle = dev(|r| r.theta_circle_fit);
        let two = dev(|r| r.theta_two_point);
        let area = dev(|r| r.theta_area);
        angle.series.push(Series::line(format!("{label}: circle fit"), circle.clone()));
        angle.series.push(Series::points(format!("{label}: two-point (per row)"), two.clone()));
        angle.series.push(Series::line(format!("{label}: area inversion"), area.clone()));
        ke.series.push(Series::line(
            label.clone(),
            col(&m.rows, |r| Some(r.kinetic_energy)).into_iter().filter(|p| p.0 > 0.0).collect(),
        ));
        shear.series.push(Series::line_points(label.clone(), m.shear.clone()));
        normal.series.push(Series::line_points(label.clone(), m.normal.clone()));
        let max_circle = circle.iter().map(|p| p.1.abs()).fold(f64::NAN, f64::max);
        let crit = if mode == "b" { Some(thesis_dev) } else { None };
        let r = Row::new(
            &format!("{label}: max |θ − 90°|, circle fit, whole run (deg)"),
            max_circle,
            2,
            Some(thesis_dev),
            None,
        )
        .thesis_text(if mode == "b" { "< 3" } else { "±10" });
        rep.rows.push(match crit {
            Some(c) => r.check(max_circle < c, "< 3° (thesis)"),
            None => r,
        });
        for (name, pts) in [("circle fit", &circle), ("two-point", &two), ("area inversion", &area)] {
            if let Some((mean, std, n)) = window_stats(pts, wa, wb) {
                rep.rows.push(
                    Row::new(&format!("{label}: θ − 90°, {name}, mean over {wtext} (deg)"), mean, 2, None, Some(0.0))
                        .sphlab_text(format!("{mean:.2} ± {std:.2} (n = {n})")),
                );
            }
        }
        let ke_end = m.rows.last().map_or(f64::NAN, |r| r.kinetic_energy);
        rep.rows.push(
            Row::new(&format!("{label}: liquid kinetic energy at t = {t_end}"), ke_end, 3, None, Some(0.0))
                .sphlab_text(format!("{ke_end:.3e}")),
        );
        // The peak and where it sits (fraction of the wall; the drop's contact line is at 0.5).
        let peak_at = |prof: &[(f64, f64)]| {
            prof.iter().copied().fold((f64::NAN, f64::NAN), |a, p| if !(a.1 >= p.1) { p } else { a })
        };
        let (peak_x, peak) = peak_at(&m.shear);
        rep.rows.push(
            Row::new(&format!("{label}: peak wall shear rate, {wtext} (1/time)"), peak, 4, None, None)
                .sphlab_text(format!("{peak:.4} (at {peak_x:.3} of the wall)")),
        );
        let (flow_x, flow_peak) = peak_at(&m.mean_flow);
        rep.rows.push(
            Row::new(
                &format!("{label}: peak mean-flow wall shear rate |⟨γ̇⟩|, {ftext} (1/time)"),
                flow_peak,
                4,
                None,
                None,
            )
            .sphlab_text(format!("{flow_peak:.4} (at {flow_x:.3} of the wall)")),
        );
        mean_flow.series.push(Series::line_points(label.clone(), m.mean_flow.clone()));
        flow_peaks.push(flow_peak);
        flow_xs.push(flow_x);
        // the mean flow near the contact line: the largest bin within CONTACT_BAND of the wall's 0.5
        let near =
            m.mean_flow.iter().filter(|p| (p.0 - 0.5).abs() <= CONTACT_BAND).map(|p| p.1).fold(f64::NAN, f64::max);
        rep.rows.push(Row::new(
            &format!(
                "{label}: mean-flow wall shear rate near the contact line ({:.1}–{:.1} of the wall), {ftext} (1/time)",
                0.5 - CONTACT_BAND,
                0.5 + CONTACT_BAND
            ),
            near,
            4,
            None,
            None,
        ));
        cl_flows.push(near);
        let (su_x, su_peak) = peak_at(&m.startup);
        rep.rows.push(
            Row::new(
                &format!("{label}: peak wall shear rate, {stext} (1/time)"),
                su_peak,
                4,
                Some(if mode == "b" { THESIS_MODE_B_SHEAR_MAX } else { THESIS_MODE_A_SHEAR_PEAK }),
                None,
            )
            .sphlab_text(format!("{su_peak:.4} (at {su_x:.3} of the wall)"))
            .thesis_text(if mode == "b" {
                "≤ 0.016 (Fig. 4.8)"
            } else {
                "≈ 2.5 near the triple point (Fig. 4.7)"
            }),
        );
        startup_peaks.push(su_peak);
        let nd = window_stats(&m.normal, wa, wb).map_or(f64::NAN, |s| s.0);
        let nd_row =
            Row::new(&format!("{label}: max normal deviation, mean over {wtext} (deg)"), nd, 2, None, Some(0.0))
                .thesis_text("0–8 (Fig. 4.9)");
        rep.rows.push(if mode == "b" && !quick {
            nd_row.check(nd <= 8.0, "within the thesis's 0–8° band")
        } else {
            nd_row
        });
        // The window mean averages three to six snapshots of a quantity that swings by ±4° from
        // snapshot to snapshot: the whole run after the start-up (t ≥ 1) says more.
        let late: Vec<f64> = m.normal.iter().filter(|p| p.0 >= 1.0).map(|p| p.1).collect();
        if !quick && !late.is_empty() {
            let mut v = late.clone();
            v.sort_by(f64::total_cmp);
            let med = v[v.len() / 2];
            let within = v.iter().filter(|&&x| x <= 8.0).count();
            rep.rows.push(
                Row::new(
                    &format!("{label}: max normal deviation, median of the snapshots with t ≥ 1 (deg)"),
                    med,
                    2,
                    None,
                    Some(0.0),
                )
                .sphlab_text(format!(
                    "{med:.2} ({:.1}–{:.1}; {within} of {} snapshots ≤ 8°)",
                    v[0],
                    v[v.len() - 1],
                    v.len()
                ))
                .thesis_text("0–8 (Fig. 4.9)"),
            );
        }
        if mode == "b" && !quick && nd > 8.0 {
            let (dxn, band) = (0.5 / nx as f64, 1.5 / nx as f64);
            let q: Vec<[f64; 3]> = normal_deviation_quantiles(&dir, &m.rows, dxn, 0.0, [0.0, 0.0], 0.25, band)
                .into_iter()
                .filter(|(t, _)| *t >= wa && *t <= wb)
                .filter_map(|(_, q)| q)
                .collect();
            let mean = |k: usize| q.iter().map(|v| v[k]).sum::<f64>() / q.len().max(1) as f64;
            let (lo, hi) = q.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v[2]), b.max(v[2])));
            rep.notes.push(format!(
                "{label}: the max normal deviation {nd:.1}° over {wtext} (per snapshot {lo:.1}°–{hi:.1}°) is set by one or two \
                 particles: per snapshot the median is {:.1}° and the 90th percentile {:.1}° of the counted interface \
                 particles (|∇C| ≥ 0.3·max), inside the thesis's 0–8°. The largest angles sit in the interface core \
                 (|∇C| ≥ 0.7·max), 20–35° above the wall where the contact-line circulation of Mode B moves the particles: \
                 on the committed nx = 45 run, raising the |∇C| threshold to 0.5 or 0.7·max, narrowing the band to |r − R| ≤ Δx or \
                 excluding y ≤ 6Δx leaves the per-snapshot maximum unchanged, and a circle fitted to the interface \
                 (centre within 0.004 of the origin) instead of the radial direction does not lower it. The band is not \
                 reached by the max of per-particle ∇C directions on a disordered arrangement; it is by their median and \
                 90th percentile. The whole run and the thesis's nx = 65: normal-deviation/README.md.",
                mean(0),
                mean(1)
            ));
        }
        peaks.push(peak);
        for (x, g) in &m.shear {
            let at = |prof: &[(f64, f64)]| prof.iter().find(|p| (p.0 - x).abs() < 1e-9).map_or(f64::NAN, |p| p.1);
            shear_csv.push(vec![if mode == "b" { 1.0 } else { 0.0 }, *x, *g, at(&m.mean_flow), at(&m.startup)]);
        }
        rep.runs.push(rec);
    }
    if !quick && nx != 65 {
        rep.not_full_because(format!(
            "nx = {nx} instead of the thesis's 65 (CPU time on a shared 2-core machine), p_b = σ/Δx = {} (a drop at rest: pb-check/README.md)",
            crate::scene::builtin::at_rest_background_pressure(1.0, 0.5 / nx as f64)
        ));
    }
    if !quick && t_end < 5.0 {
        let ms: Vec<f64> = rep.runs.iter().map(|r| r.ms_per_step).filter(|m| m.is_finite()).collect();
        let mean = ms.iter().sum::<f64>() / ms.len().max(1) as f64;
        rep.not_full_because(format!(
            "t_end = {t_end} instead of the thesis's 5 (CPU time: 71,429 steps to t = 5 at the {mean:.1} ms/step measured here on a shared 2-core machine ≈ {:.0} min per run); the shear profile is averaged over the last 10 % instead of near t = 4.4",
            mean * 5.0 / 7e-5 / 6e4
        ));
    }
    let ratio = peaks[1] / peaks[0];
    rep.rows.push(
        Row::new("peak wall shear rate ratio, Mode A / Mode B", ratio, 1, Some(THESIS_SHEAR_RATIO), None)
            .check(ratio > 1.0, "Mode B lower than Mode A (direction)"),
    );
    // Mode A over Mode B of one shear measure, against the thesis's ~160×.
    let ratio_row = |name: String, v: f64| Row::new(&name, v, 1, Some(THESIS_SHEAR_RATIO), None);
    let flow_ratio = flow_peaks[1] / flow_peaks[0];
    rep.rows.push(ratio_row(format!("peak mean-flow wall shear rate ratio, Mode A / Mode B, {ftext}"), flow_ratio));
    let cl_ratio = cl_flows[1] / cl_flows[0];
    rep.rows.push(ratio_row(
        format!("mean-flow wall shear rate near the contact line, Mode A / Mode B, {ftext}"),
        cl_ratio,
    ));
    let su_ratio = startup_peaks[1] / startup_peaks[0];
    rep.rows.push(ratio_row(format!("peak wall shear rate ratio, Mode A / Mode B, {stext}"), su_ratio));
    if su_ratio.is_finite() {
        let (a_scale, b_scale) =
            (startup_peaks[1] / THESIS_MODE_A_SHEAR_PEAK, startup_peaks[0] / THESIS_MODE_B_SHEAR_MAX);
        rep.notes.push(format!(
            "Which mode is off the thesis's scale: over the {stext} Mode A's mean |γ̇| peaks at {:.2} ({:.2}× the ≈ 2.5 of Fig. 4.7), \
             Mode B's at {:.3} ({:.0}× the ≤ 0.016 of Fig. 4.8).{}",
            startup_peaks[1],
            a_scale,
            startup_peaks[0],
            b_scale,
            if (0.5..=2.0).contains(&a_scale) && b_scale > 3.0 {
                " Mode A is on the thesis's scale and Mode B is not: the distance from the thesis's ~160× is Mode B's wall flow, not Mode A's."
            } else {
                ""
            }
        ));
    }
    if ratio.is_finite() && ratio < 10.0 {
        rep.notes.push(format!(
            "The thesis's ~160× higher peak wall shear for Mode A is not reproduced: peak |γ̇| Mode A {:.3} vs Mode B {:.3} (ratio {ratio:.2}) in the same window, and over {ftext} the mean flow's {:.3} vs {:.3} (ratio {flow_ratio:.1}). In a window of a few snapshots Mode A's peak can sit anywhere its particle noise is largest (where, in the rows); the mean flow peaks at {:.3} of the wall in Mode A and {:.3} in Mode B (the drop's edge is at 0.5, the right wall at 1; the profile per bin is in wall_shear_profile.csv). Both modes hold the bulk 90° by the circle fit; Mode A's deviation shows in the two-point angle near the wall (rows 1–2) instead.",
            peaks[1], peaks[0], flow_peaks[1], flow_peaks[0], flow_xs[1], flow_xs[0]
        ));
    }
    angle.refs = vec![
        RefLine::horizontal("thesis Mode B bound +3°", 3.0),
        RefLine::horizontal("thesis Mode B bound −3°", -3.0),
        RefLine::horizontal("thesis Mode A +10°", 10.0),
        RefLine::horizontal("thesis Mode A −10°", -10.0),
    ];
    angle.y_range = Some((-45.0, 45.0));
    plot(ctx, &mut rep, "contact_angle_deviation.svg", &angle)?;
    plot(ctx, &mut rep, "kinetic_energy.svg", &ke)?;
    plot(ctx, &mut rep, "wall_shear_profile.svg", &shear)?;
    plot(ctx, &mut rep, "wall_shear_mean_flow.svg", &mean_flow)?;
    plot(ctx, &mut rep, "fig4_9_max_normal_deviation.svg", &normal)?;
    write_csv(
        ctx,
        &mut rep,
        "wall_shear_profile.csv",
        "mode_b,wall_fraction,mean_abs_shear_rate,abs_mean_shear_rate,startup_mean_abs_shear_rate",
        &shear_csv,
    )?;
    rep.notes.push("Two-point angles (§10.1) are noisy per snapshot on disordered particles (±40°): the table gives the window mean ± std; the circle fit (§10.2) is the robust estimate.".into());
    rep.notes.push("Wall shear rate: |u/(y − y_w)| of first-row fluid particles (§9(b) quick check, diagnostics::wall_shear_profile), 20 bins over [0, 0.5], count-weighted over the snapshots in the window.".into());
    rep.notes.push(format!("Mean-flow wall shear rate: the same first-row particles, u/(y − y_w) signed (positive towards the right wall), count-weighted over every snapshot with {ftext} per bin, then its magnitude (`abs_mean_shear_rate` in wall_shear_profile.csv). The thesis's \"average shear rate\" of Figs. 4.7–4.8 does not say whether the particle noise is averaged out: the window's mean |γ̇| counts it, the mean flow does not and keeps the steady flow, which is where the correction method differs from Mode A."));
    rep.notes.push("Max normal deviation: particles with |grad C| ≥ 0.3 × its largest value (diagnostics::flow::NORMAL_GRAD_FRACTION), y > 3Δx and |r − 0.25| ≤ 3Δx (the drop's interface band; Mode A's walls are a third colour, so particles at the right and top walls also carry grad C), angle between the outward normal and the radial direction from (0, 0).".into());
    Ok(rep)
}
