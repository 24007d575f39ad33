//! The convergence case's realisations and extrapolations: relax-60 Mode B started from a
//! jittered lattice (0.05Δx, seeds 1–3) at the coarser resolutions, so that the change of θ with
//! Δx is read against the scatter between starts; the realisations' trend verdict; and the
//! observed order and Richardson estimate of the lattice runs and of the realisations' means
//! (docs/PHYSICS.md §9(d)).

use super::super::data::{col, read_series, window_stats};
use super::super::judge::{ANGLE_TOL_DEG, YOUNG_DEG};
use super::super::relax::wall_spread;
use super::super::report::{plot, write_csv, CaseReport, Row};
use super::super::richardson::{extrapolate, Extrapolation};
use super::super::scatter::{self, stats, JITTER, SEEDS};
use super::super::{Ctx, RunSpec, ValidateError};
use super::band_density::{relax_last_state, BandDensity};
use crate::plot::{PlotSpec, RefLine, Series};
use std::path::{Path, PathBuf};

/// Resolutions with realisations: those where one run costs at most about an hour of a core.
pub const REALISATION_NX: [u32; 3] = [33, 45, 65];

/// A run's end state: means over the window, and the density error over t ≥ 1.
#[derive(Clone, Copy, Debug)]
pub struct End {
    /// θ, circle fit (deg).
    pub theta: f64,
    /// θ by the thesis's two-point metric, the first two rows at the wall (deg).
    pub two_point: f64,
    /// D/D0 at the wall.
    pub spread: f64,
    /// max |ρ/ρ0 − 1| for t ≥ 1.
    pub density: f64,
    /// The last state's density error in the interface band and outside it (None without a
    /// snapshot).
    pub band: Option<BandDensity>,
}

/// The end state of the run in `dir` at `nx`, window `[a, b]`.
pub fn end_values(dir: &Path, nx: u32, a: f64, b: f64) -> End {
    let rows = read_series(dir);
    let mean = |pts: &[(f64, f64)]| window_stats(pts, a, b).map_or(f64::NAN, |s| s.0);
    End {
        theta: mean(&col(&rows, |r| r.theta_circle_fit)),
        two_point: mean(&col(&rows, |r| r.theta_two_point)),
        spread: mean(&wall_spread(&rows, 0.5 / nx as f64)),
        density: rows.iter().filter(|r| r.t >= 1.0).map(|r| r.max_density_error).fold(f64::NAN, f64::max),
        band: relax_last_state(dir, nx),
    }
}

/// The realisation `seed` at `nx`: the lattice run's spec with the jitter.
fn spec(nx: u32, seed: u64, t_end: f64) -> RunSpec<'static> {
    let mut s = super::spec(nx, false, t_end);
    s.sets.extend(scatter::sets(seed));
    s.id = format!("nx{nx}{}", scatter::suffix(seed));
    s
}

/// Where else a run of the capillary rule's relax-60 study may already be (same scene):
/// `capillary-rule/relax-60/nx<nx>-b-from90[-jitter0.05-seed<k>]`.
pub fn capillary_rule_dir(root: &Path, nx: u32, seed: Option<u64>) -> PathBuf {
    let tail = seed.map_or(String::new(), scatter::suffix);
    root.join("capillary-rule").join("relax-60").join(format!("nx{nx}-b-from90{tail}"))
}

/// One resolution's realisations.
struct Group {
    nx: u32,
    ends: Vec<End>,
}

/// Runs (or reuses) the realisations, adds their rows, the realisations' trend verdict and the
/// Richardson rows, a plot of the end angle against resolution and `realisations.csv`.
/// `lattice` holds the lattice runs' end states by resolution, coarse to fine.
pub fn add(ctx: &Ctx, rep: &mut CaseReport, lattice: &[(u32, End)], t_end: f64) -> Result<(), ValidateError> {
    let (wa, wb, wtext) = super::super::sessile::shear_window(t_end);
    let mut groups = Vec::new();
    let mut csv = Vec::new();
    for nx in REALISATION_NX {
        let mut ends = Vec::new();
        for seed in SEEDS {
            let also = [capillary_rule_dir(&ctx.opts.out, nx, Some(seed))];
            let Some(rec) = super::run_or_skip(ctx, rep, &spec(nx, seed, t_end), &also)? else { continue };
            let e = end_values(Path::new(&rec.dir), nx, wa, wb);
            csv.push(vec![nx as f64, seed as f64, e.theta, e.spread, e.density]);
            ends.push(e);
            rep.runs.push(rec);
        }
        if !ends.is_empty() {
            groups.push(Group { nx, ends });
        }
    }
    for g in &groups {
        let th: Vec<f64> = g.ends.iter().map(|e| e.theta).collect();
        let (m, s, n) = stats(&th);
        let list: Vec<String> = th.iter().map(|v| format!("{v:.2}")).collect();
        rep.rows.push(
            Row::new(
                &format!("realisations at Δx = 0.5/{}: θ circle fit, mean over {wtext} (deg)", g.nx),
                m,
                2,
                None,
                Some(YOUNG_DEG),
            )
            .sphlab_text(format!("{m:.2}{} (n = {n}: {})", spread(s, 2), list.join(", "))),
        );
        let d: Vec<f64> = g.ends.iter().map(|e| e.spread).collect();
        let (m, s, n) = stats(&d);
        rep.rows.push(
            Row::new(
                &format!("realisations at Δx = 0.5/{}: D/D0 at the wall, mean over {wtext}", g.nx),
                m,
                3,
                None,
                Some(super::super::relax::analytic_spread()),
            )
            .sphlab_text(format!("{m:.3}{} (n = {n})", spread(s, 3))),
        );
        let bands: Vec<BandDensity> = g.ends.iter().filter_map(|e| e.band).collect();
        if !bands.is_empty() {
            let what = format!("realisations at Δx = 0.5/{}", g.nx);
            rep.rows.push(band_density_row(&what, &bands));
        }
    }
    rep.notes.push(format!(
        "Realisations: the lattice start jittered by {JITTER}Δx (`domain.jitter`, seeds {}) at nx = {}; a run of \
         the capillary rule's relax-60 study with the same scene (../capillary-rule/relax-60/nx<nx>-b-from90[-jitter{JITTER}-seed<k>]) \
         is reused for a lattice run or a realisation. Their trend verdict, stated before the runs: |θ̄ − 60°| < 3° \
         at every resolution, and no refinement raises it by more than twice the standard error of the difference \
         (pooled sample sd over the resolutions with two or more realisations). Richardson: f = f* + C·Δx^p \
         through three resolutions (unequal ratios; p by bisection in (0, 20]), on the three finest lattice runs and on \
         the realisations' means, the latter with the range of f* over the means ± one standard error.",
        SEEDS.map(|k| k.to_string()).join(", "),
        REALISATION_NX.map(|k| k.to_string()).join(", "),
    ));
    trend_row(rep, &groups);
    richardson_rows(rep, lattice, &groups);
    end_angle_plot(ctx, rep, lattice, &groups)?;
    write_csv(ctx, rep, "realisations.csv", "nx,seed,theta_circle_end,spread_end,max_density_error_t_ge_1", &csv)
}

/// The info row of the last states' density error in the interface band and outside it, as
/// means over `bands` (one per run).
pub fn band_density_row(what: &str, bands: &[BandDensity]) -> Row {
    let n = bands.len() as f64;
    let mean = |f: fn(&BandDensity) -> f64| bands.iter().map(f).sum::<f64>() / n;
    let (b, o, m) = (mean(|b| b.band_max), mean(|b| b.outside_max), mean(|b| b.outside_mean));
    Row::new(
        &format!(
            "{what}: |ρ/ρ0 − 1| of the last state, max in the interface band (|∇C|Δx ≥ {}) / max outside / mean outside",
            super::band_density::BAND_GRADIENT
        ),
        b,
        4,
        None,
        None,
    )
    .sphlab_text(format!("{b:.4} / {o:.4} / {m:.5} (mean over {} run(s))", bands.len()))
}

/// " ± sd" (sample standard deviation), or nothing for a single realisation.
fn spread(sd: f64, prec: usize) -> String {
    if sd.is_finite() {
        format!(" ± {sd:.prec$}")
    } else {
        String::new()
    }
}

/// The pooled sample standard deviation of θ over the groups with two or more realisations.
fn pooled_sd(groups: &[Group]) -> Option<f64> {
    let th: Vec<Vec<f64>> = groups.iter().map(|g| g.ends.iter().map(|e| e.theta).collect()).collect();
    scatter::pooled_sd(th.iter().map(Vec::as_slice))
}

/// The realisations' trend verdict, stated before their runs: |θ̄ − 60°| < 3° at every
/// resolution with realisations, and no refinement raises |θ̄ − 60°| by more than twice the
/// standard error of the difference (pooled scatter).
fn trend_row(rep: &mut CaseReport, groups: &[Group]) {
    let Some(sd) = pooled_sd(groups) else { return };
    if groups.len() < 2 {
        return;
    }
    let mean = |g: &Group| g.ends.iter().map(|e| e.theta).sum::<f64>() / g.ends.len() as f64;
    let err: Vec<f64> = groups.iter().map(|g| (mean(g) - YOUNG_DEG).abs()).collect();
    let se: Vec<f64> = groups.iter().map(|g| sd / (g.ends.len() as f64).sqrt()).collect();
    let within = err.iter().all(|e| *e < ANGLE_TOL_DEG);
    let no_rise = (1..err.len()).all(|i| err[i] - err[i - 1] <= 2.0 * (se[i].powi(2) + se[i - 1].powi(2)).sqrt());
    let nxs: Vec<String> = groups.iter().map(|g| g.nx.to_string()).collect();
    let text: Vec<String> = err.iter().zip(&se).map(|(e, s)| format!("{e:.2} ± {s:.2}")).collect();
    rep.rows.push(
        Row::new(
            &format!("realisations' trend with refinement: |θ̄ − 60°| at nx = {} (deg)", nxs.join(", ")),
            *err.last().unwrap_or(&f64::NAN),
            2,
            None,
            Some(0.0),
        )
        .sphlab_text(format!("{} (± one standard error; pooled sd {sd:.2}°)", text.join(" → ")))
        .check(
            within && no_rise,
            "|θ̄ − 60°| < 3° at every resolution and no rise with refinement beyond two standard errors of the difference",
        ),
    );
}

/// Info rows: observed order and Richardson estimate over the three finest lattice runs (θ and
/// D/D0) and over the realisations' means (θ, with its range over the ± one-standard-error
/// corners).
fn richardson_rows(rep: &mut CaseReport, lattice: &[(u32, End)], groups: &[Group]) {
    let h = |nx: u32| 0.5 / nx as f64;
    if lattice.len() >= 3 {
        let l = &lattice[lattice.len() - 3..];
        let hs = [h(l[0].0), h(l[1].0), h(l[2].0)];
        let nxs = format!("{}, {}, {}", l[0].0, l[1].0, l[2].0);
        for (what, f, prec) in [
            ("θ circle fit (deg)", [l[0].1.theta, l[1].1.theta, l[2].1.theta], 2),
            ("D/D0 at the wall", [l[0].1.spread, l[1].1.spread, l[2].1.spread], 3),
        ] {
            let x = extrapolate(hs, f);
            rep.rows.push(richardson_row(&format!("Richardson over the lattice runs at nx = {nxs}: {what}"), x, prec));
        }
    }
    let (Some(sd), true) = (pooled_sd(groups), groups.len() >= 3) else { return };
    let g = &groups[groups.len() - 3..];
    let hs = [h(g[0].nx), h(g[1].nx), h(g[2].nx)];
    let means: Vec<f64> = g.iter().map(|g| g.ends.iter().map(|e| e.theta).sum::<f64>() / g.ends.len() as f64).collect();
    let se: Vec<f64> = g.iter().map(|g| sd / (g.ends.len() as f64).sqrt()).collect();
    let x = extrapolate(hs, [means[0], means[1], means[2]]);
    let mut limits = Vec::new();
    for corner in 0..8u32 {
        let f = |i: usize| means[i] + if corner >> i & 1 == 1 { se[i] } else { -se[i] };
        if let Extrapolation::Order { limit, .. } = extrapolate(hs, [f(0), f(1), f(2)]) {
            limits.push(limit);
        }
    }
    let range = if limits.is_empty() {
        "; none of the 8 ± one-standard-error corners gives an order".to_string()
    } else {
        let (lo, hi) = limits.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
        format!("; over the ± one-standard-error corners {lo:.2}–{hi:.2} ({} of 8 give an order)", limits.len())
    };
    let nxs = format!("{}, {}, {}", g[0].nx, g[1].nx, g[2].nx);
    let mut row =
        richardson_row(&format!("Richardson over the realisations' means at nx = {nxs}: θ circle fit (deg)"), x, 2);
    row.sphlab = format!("{}{range}", row.sphlab);
    rep.rows.push(row);
}

/// An info row of an extrapolation; an order above 2 (the most an SPH discretisation gives)
/// says the three resolutions are not in the asymptotic range.
fn richardson_row(quantity: &str, x: Extrapolation, prec: usize) -> Row {
    let (value, note) = match x {
        Extrapolation::Order { limit, p } if p > 2.0 => (limit, " (above 2: not in the asymptotic range)"),
        Extrapolation::Order { limit, .. } => (limit, ""),
        _ => (f64::NAN, ""),
    };
    Row::new(quantity, value, prec, None, None).sphlab_text(format!("{x}{note}"))
}

/// θ at the end against the resolution: the lattice runs, each realisation and their means.
fn end_angle_plot(
    ctx: &Ctx,
    rep: &mut CaseReport,
    lattice: &[(u32, End)],
    groups: &[Group],
) -> Result<(), ValidateError> {
    let mut spec = PlotSpec::new(
        "Convergence: end angle vs resolution (relax-60, Mode B)",
        "particles across 0.5 (nx)",
        "θ circle fit, mean over the end window (degrees)",
    );
    spec.series
        .push(Series::line_points("lattice start", lattice.iter().map(|(nx, e)| (*nx as f64, e.theta)).collect()));
    let each = groups.iter().flat_map(|g| g.ends.iter().map(move |e| (g.nx as f64, e.theta))).collect();
    spec.series.push(Series::points(format!("jittered starts ({JITTER}Δx)"), each));
    let means = groups
        .iter()
        .map(|g| (g.nx as f64, g.ends.iter().map(|e| e.theta).sum::<f64>() / g.ends.len() as f64))
        .collect();
    spec.series.push(Series::line_points("mean of the jittered starts", means));
    spec.refs = vec![RefLine::horizontal("Young's angle 60°", YOUNG_DEG)];
    plot(ctx, rep, "end_angle_vs_resolution.svg", &spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn groups(thetas: &[(u32, &[f64])]) -> Vec<Group> {
        thetas
            .iter()
            .map(|(nx, th)| Group {
                nx: *nx,
                ends: th
                    .iter()
                    .map(|&theta| End { theta, two_point: f64::NAN, spread: 1.385, density: 0.01, band: None })
                    .collect(),
            })
            .collect()
    }

    fn verdict(thetas: &[(u32, &[f64])]) -> String {
        let mut rep = CaseReport::new("convergence", "", false);
        trend_row(&mut rep, &groups(thetas));
        rep.rows.last().map(|r| r.verdict.clone()).unwrap_or_default()
    }

    #[test]
    fn the_realisations_trend_passes_only_near_young_without_a_rise_beyond_the_scatter() {
        // within 3° and a change smaller than the scatter
        assert!(verdict(&[(33, &[60.0, 60.5, 59.5]), (45, &[60.2, 60.8, 59.6])]).starts_with("pass"));
        // a rise far beyond two standard errors, though within 3°
        assert!(verdict(&[(33, &[60.0, 60.1, 59.9]), (45, &[62.5, 62.6, 62.4])]).starts_with("FAIL"));
        // the finest resolution outside 3°
        assert!(verdict(&[(33, &[63.5, 63.0, 64.0]), (45, &[63.2, 63.8, 63.3])]).starts_with("FAIL"));
        // one realisation per resolution gives no scatter: no row
        assert_eq!(verdict(&[(33, &[60.0]), (45, &[60.1])]), "");
    }
}
