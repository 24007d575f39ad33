//! Mode A's Young sweep as verdict rows of relax-60: at each Young angle, the end angle approached
//! from above and from below (the two starts' midpoint) at nx = 33, 45 and 65, read from the
//! committed runs of `capillary-rule/relax-60/` and `form-and-kernel/relax-60/` (the wall bands)
//! and `relax-60/mode-a-line/runs/` (the wall's tensions at the contact line, docs/PHYSICS.md
//! §8.2.3, and the unbalanced Young force, §8.2.5), all started by `examples/analysis/relax_start_angle.sh` (each folder's README says how
//! each was run), and, at 60°, the case's own two Mode A runs. Only runs of relax-60's kernel and h as the scene takes
//! them now count (each run's `summary.json`), so the rows describe the case's kernel. The
//! acceptance is the issue's: within 3° of θ_Y at nx = 65, and cos θ / cos θ_Y closer to 1 at
//! every refinement. Each row's sensitivity band is its midpoint at nx = 33 under the capillary
//! rule's α × 0.5 / × 1 / × 2, where those runs are committed.

use super::super::data::{col, read_series, window_stats};
use super::super::report::summary_at;
use super::super::report::{Band, CaseReport, Row};
use super::super::scatter::{mean_of_means_se, pooled_sd, stats, suffix as scatter_suffix, JITTER, SEEDS};
use super::sensitivity::ALPHA_SUFFIXES;
use super::{end_angle, falls, of_the_scene, run_spacing, ANGLE_TOL_DEG, RELAX_RUN_SOURCES as SOURCES};
use std::path::{Path, PathBuf};

/// The resolutions of the sweep, coarse to fine.
const NXS: [u32; 3] = [33, 45, 65];

/// One point of the sweep: its Young angle, the wall tensions (and where they act), the run
/// folder of each start (`{nx}` stands for the resolution), the starts' angles, the folders its
/// runs are in (with the suffix of their names) and the case's own runs of the two starts where
/// the case has them (at its resolution).
struct Point {
    theta_y: f64,
    tensions: &'static str,
    run: &'static str,
    starts: [&'static str; 2],
    sources: &'static [(&'static str, &'static str)],
    wall_tension: &'static str,
    case_runs: Option<[&'static str; 2]>,
}

/// Where a run's wall tensions act, as its `summary.json` records them (`bands` when the record
/// predates the option).
pub(super) fn wall_tension_of(dir: &Path) -> Option<String> {
    let v = summary_at(dir)?;
    Some(v["parameters"]["contact"]["wall_tension"].as_str().unwrap_or("bands").to_string())
}

/// Whether the run in `dir` is one of point `p` at `nx`: the scene's kernel and spacing, and the
/// point's wall tensions.
fn of_the_point(dir: &Path, p: &Point, nx: u32) -> bool {
    of_the_scene(dir, nx) && wall_tension_of(dir).as_deref() == Some(p.wall_tension)
}

/// Where the runs of the wall's tensions at the contact line are.
const LINE_RUNS: [(&str, &str); 1] = [("relax-60/mode-a-line/runs", "-line")];

/// Where the runs of the unbalanced Young force are.
const UNBALANCED_RUNS: [(&str, &str); 1] = [("relax-60/mode-a-line/runs", "-unbalanced")];

/// How the line points name their form.
macro_rules! at_the_line {
    ($t:literal) => {
        concat!($t, "; the wall's tensions at the contact line, liquid–gas free at the wall (docs/PHYSICS.md §8.2.3)")
    };
}

/// How the unbalanced Young force's points name their form.
macro_rules! unbalanced {
    ($t:literal) => {
        concat!($t, "; the unbalanced Young force at the measured angle, the wall typed there (docs/PHYSICS.md §8.2.5)")
    };
}

const POINTS: [Point; 10] = [
    Point {
        theta_y: 41.0,
        tensions: "σ_LS = 0.245, σ_GS = 1; a box 1.5 times as wide",
        run: "nx{nx}w-a-sls0.245-from",
        starts: ["90", "30"],
        sources: &SOURCES,
        wall_tension: "bands",
        case_runs: None,
    },
    Point {
        theta_y: 60.0,
        tensions: "σ_LS = 0.5, σ_GS = 1 (built-in)",
        run: "nx{nx}-a-from",
        starts: ["90", "45"],
        sources: &SOURCES,
        wall_tension: "bands",
        case_runs: Some(["a-noslip", "a-noslip-from45"]),
    },
    Point {
        theta_y: 120.0,
        tensions: "σ_LS = 1.5, σ_GS = 1",
        run: "nx{nx}-a-sls1.5-from",
        starts: ["90", "135"],
        sources: &SOURCES,
        wall_tension: "bands",
        case_runs: None,
    },
    Point {
        theta_y: 120.0,
        tensions: "σ_LS = 0.5, σ_GS = 0",
        run: "nx{nx}-a-sls0.5-sgs0-from",
        starts: ["90", "135"],
        sources: &SOURCES,
        wall_tension: "bands",
        case_runs: None,
    },
    Point {
        theta_y: 41.0,
        tensions: at_the_line!("σ_LS = 0.245, σ_GS = 1; a box 1.5 times as wide"),
        run: "nx{nx}w-sls0.245-from",
        starts: ["90", "30"],
        sources: &LINE_RUNS,
        wall_tension: "line",
        case_runs: None,
    },
    Point {
        theta_y: 60.0,
        tensions: at_the_line!("σ_LS = 0.5, σ_GS = 1 (built-in)"),
        run: "nx{nx}-from",
        starts: ["90", "45"],
        sources: &LINE_RUNS,
        wall_tension: "line",
        case_runs: None,
    },
    Point {
        theta_y: 120.0,
        tensions: at_the_line!("σ_LS = 1.5, σ_GS = 1"),
        run: "nx{nx}-sls1.5-from",
        starts: ["90", "135"],
        sources: &LINE_RUNS,
        wall_tension: "line",
        case_runs: None,
    },
    Point {
        theta_y: 41.0,
        tensions: unbalanced!("σ_LS = 0.245, σ_GS = 1; a box 1.5 times as wide"),
        run: "nx{nx}w-sls0.245-from",
        starts: ["90", "30"],
        sources: &UNBALANCED_RUNS,
        wall_tension: "unbalanced",
        case_runs: None,
    },
    Point {
        theta_y: 60.0,
        tensions: unbalanced!("σ_LS = 0.5, σ_GS = 1 (built-in)"),
        run: "nx{nx}-from",
        starts: ["90", "45"],
        sources: &UNBALANCED_RUNS,
        wall_tension: "unbalanced",
        case_runs: None,
    },
    Point {
        theta_y: 120.0,
        tensions: unbalanced!("σ_LS = 1.5, σ_GS = 1"),
        run: "nx{nx}-sls1.5-from",
        starts: ["90", "135"],
        sources: &UNBALANCED_RUNS,
        wall_tension: "unbalanced",
        case_runs: None,
    },
];

/// How far a start's contact point moved over t ∈ [3, 5], in particle spacings: the mean x_tp
/// over [4.8, 5.0] less that over [2.9, 3.1]. More than [`MOVING_DX`] and the end angle is
/// not an equilibrium (a line still spreading, e.g. as a film along the wall).
fn drift_dx(dir: &Path) -> Option<f64> {
    let spacing = run_spacing(&summary_at(dir)?)?;
    let x = col(&read_series(dir), |r| r.x_tp);
    Some((window_stats(&x, 4.8, 5.0)?.0 - window_stats(&x, 2.9, 3.1)?.0).abs() / spacing)
}

/// The contact point's largest drift over t ∈ [3, 5] (in Δx) that still counts as stopped.
const MOVING_DX: f64 = 2.0;

/// The two starts' run folders of point `p` at `nx` in the source `(src, suffix)`, with `tag` (one
/// of [`ALPHA_SUFFIXES`]) after the suffix, and how a row cites them (relative to the case's
/// folder).
fn pair(root: &Path, p: &Point, nx: u32, (src, suffix): (&str, &str), tag: &str) -> ([PathBuf; 2], String) {
    let dir = p.run.replace("{nx}", &nx.to_string());
    let at = |start: &str| root.join(src).join(format!("{dir}{start}{suffix}{tag}"));
    let cite = format!("../{src}/{dir}{{{}}}{suffix}{tag}", p.starts.join(","));
    ([at(p.starts[0]), at(p.starts[1])], cite)
}

/// The midpoint of a pair of starts and the larger of their contact-point drifts over t ∈ [3, 5]
/// (in Δx, zero when the series has no x_tp there), when both are runs of point `p` at `nx`.
fn pair_midpoint(p: &Point, nx: u32, dirs: &[PathBuf; 2]) -> Option<(f64, f64)> {
    if !dirs.iter().all(|d| of_the_point(d, p, nx)) {
        return None;
    }
    let drift = dirs.iter().filter_map(|d| drift_dx(d)).fold(0.0, f64::max);
    Some((0.5 * (end_angle(&dirs[0])? + end_angle(&dirs[1])?), drift))
}

/// The two starts' midpoint at `nx`, where its runs are (relative to the case's folder) and the
/// larger of the starts' contact-point drifts, from the first source with both runs of the
/// scene's kernel (None when none has them).
fn midpoint(root: &Path, p: &Point, nx: u32) -> Option<(f64, String, f64)> {
    let mut sources: Vec<([PathBuf; 2], String)> = p.sources.iter().map(|&src| pair(root, p, nx, src, "")).collect();
    if let Some(ids) = p.case_runs {
        let runs = root.join("relax-60/runs");
        sources.push(([runs.join(ids[0]), runs.join(ids[1])], format!("runs/{}, runs/{}", ids[0], ids[1])));
    }
    sources.into_iter().find_map(|(dirs, cite)| pair_midpoint(p, nx, &dirs).map(|(mid, drift)| (mid, cite, drift)))
}

/// Point `p`'s midpoint at nx = 33 under the capillary rule's α × 0.5 / × 1 / × 2 (the pairs of
/// runs named with [`ALPHA_SUFFIXES`]), from the first source with all three pairs, each against
/// the 3° bound.
fn alpha_band(root: &Path, p: &Point) -> Option<Band> {
    p.sources.iter().find_map(|&src| {
        let (mids, cites): (Vec<f64>, Vec<String>) = ALPHA_SUFFIXES
            .iter()
            .map(|tag| {
                let (dirs, cite) = pair(root, p, NXS[0], src, tag);
                pair_midpoint(p, NXS[0], &dirs).map(|(mid, _)| (mid, cite))
            })
            .collect::<Option<Vec<_>>>()?
            .into_iter()
            .unzip();
        Some(Band {
            varied: format!(
                "the capillary rule's α × 0.5 / × 1 / × 2 at nx = {} (the starts' midpoint, against 3° of θ_Y)",
                NXS[0]
            ),
            values: mids.iter().map(|m| format!("{m:.2}")).collect(),
            source: cites.join(", "),
            holds: Some(mids.iter().all(|m| (m - p.theta_y).abs() < ANGLE_TOL_DEG)),
        })
    })
}

/// The α band of relax-60's row "Mode <mode>, no-slip: end angle approached from both sides": the
/// midpoint of the starts from 90° and 45° at nx = 33 under the capillary rule's α × 0.5 / × 1 /
/// × 2: with the wall bands (`mode` "a" or "b"), or Mode A with the unbalanced Young force
/// (`mode` "unbalanced").
pub(super) fn both_sides_band(root: &Path, mode: &str) -> Option<Band> {
    let (run, sources, wall_tension): (_, &'static [(&'static str, &'static str)], _) = match mode {
        "a" => ("nx{nx}-a-from", &SOURCES, "bands"),
        "unbalanced" => ("nx{nx}-from", &UNBALANCED_RUNS, "unbalanced"),
        _ => ("nx{nx}-b-from", &SOURCES, "bands"),
    };
    let p = Point {
        theta_y: 60.0,
        tensions: "σ_LS = 0.5, σ_GS = 1 (built-in)",
        run,
        starts: ["90", "45"],
        sources,
        wall_tension,
        case_runs: None,
    };
    alpha_band(root, &p)
}

/// A point's realisations at one resolution: the midpoint of the starts' means, the pooled sample
/// sd between realisations, the fewest per start and the midpoint's standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Realised {
    mid: f64,
    sd: f64,
    n: usize,
    se: f64,
}

/// The realisations of a point at `nx`, from the first source with two or more per start.
fn realisations(root: &Path, p: &Point, nx: u32) -> Option<Realised> {
    let dir = p.run.replace("{nx}", &nx.to_string());
    p.sources.iter().find_map(|(src, suffix)| {
        let per_start: Vec<Vec<f64>> = p
            .starts
            .iter()
            .map(|start| {
                SEEDS
                    .iter()
                    .map(|&k| root.join(src).join(format!("{dir}{start}{suffix}{}", scatter_suffix(k))))
                    .filter(|d| of_the_point(d, p, nx))
                    .filter_map(|d| end_angle(&d))
                    .collect()
            })
            .collect();
        let n = per_start.iter().map(Vec::len).min()?;
        if n < 2 {
            return None;
        }
        let mid = per_start.iter().map(|v| stats(v).0).sum::<f64>() / per_start.len() as f64;
        let sd = pooled_sd(per_start.iter().map(Vec::as_slice))?;
        let counts: Vec<usize> = per_start.iter().map(Vec::len).collect();
        Some(Realised { mid, sd, n, se: mean_of_means_se(sd, &counts) })
    })
}

/// The sweep's trend judged with its scatter, from the realisations at each resolution (coarse to
/// fine): at every refinement the midpoint is closer to θ_Y, or at both resolutions it lies within
/// two standard errors of θ_Y (the form at Young's angle to within its scatter, where no approach
/// can be resolved).
fn approaches_within_scatter(theta_y: f64, reals: &[Realised]) -> bool {
    let off = |r: &Realised| (r.mid - theta_y).abs();
    reals.len() >= 2 && reals.windows(2).all(|w| off(&w[1]) < off(&w[0]) || w.iter().all(|r| off(r) <= 2.0 * r.se))
}

/// What every verdict of the sweep depends on.
const DEPENDS: &str = "p_b and c0 by the capillary rule at each nx (α = 2, ε = 0.01; docs/PHYSICS.md §3.1), μ = 0.05, \
                       no-slip, T-wall, the starts";

/// Replaces the sweep's rows of `rep` with one row per point that has all three resolutions; a
/// point with fewer is an info row that names the resolutions it has.
pub(super) fn young_sweep_rows(root: &Path, rep: &mut CaseReport) {
    const HEAD: &str = "Mode A Young sweep, θ_Y = ";
    rep.rows.retain(|r| !r.quantity.starts_with(HEAD));
    for p in &POINTS {
        let found: Vec<(u32, f64, String, f64)> =
            NXS.iter().filter_map(|&nx| midpoint(root, p, nx).map(|(m, cite, drift)| (nx, m, cite, drift))).collect();
        let Some((nx_fine, fine, _, _)) = found.last().cloned() else {
            continue;
        };
        let cos_y = p.theta_y.to_radians().cos();
        let ratio: Vec<f64> = found.iter().map(|f| f.1.to_radians().cos() / cos_y).collect();
        let nxs: Vec<String> = found.iter().map(|f| f.0.to_string()).collect();
        let quantity = format!(
            "{HEAD}{:.0}° ({}): midpoint of the starts from {}° and {}°, nx = {} (deg)",
            p.theta_y,
            p.tensions,
            p.starts[0],
            p.starts[1],
            nxs.join(", ")
        );
        let angles: Vec<String> = found.iter().map(|f| format!("{:.2}", f.1)).collect();
        let ratios: Vec<String> = ratio.iter().map(|r| format!("{r:.3}")).collect();
        let cites: Vec<String> = found.iter().map(|f| format!("nx = {}: {}", f.0, f.2)).collect();
        let reals: Vec<Option<Realised>> = NXS.iter().map(|&nx| realisations(root, p, nx)).collect();
        let real: Vec<String> = NXS
            .iter()
            .zip(&reals)
            .filter_map(|(nx, r)| {
                let Realised { mid, sd, n, se } = (*r)?;
                Some(format!("at nx = {nx} {mid:.2}° (pooled sd {sd:.2}°, {n} per start, standard error {se:.2}°)"))
            })
            .collect();
        let real = if real.is_empty() {
            String::new()
        } else {
            format!(
                "; realisations from the lattice jittered by {JITTER}Δx (seeds 1–3, `-jitter{JITTER}-seed<k>` beside each run), \
                 midpoint {}",
                real.join(", ")
            )
        };
        let moving: Vec<String> = found
            .iter()
            .filter(|f| f.3 > MOVING_DX)
            .map(|f| format!("at nx = {} the contact point moved {:.1}Δx over t ∈ [3, 5]", f.0, f.3))
            .collect();
        let moving_text = if moving.is_empty() {
            String::new()
        } else {
            format!("; not an equilibrium: {} (a line still spreading)", moving.join(", "))
        };
        let text = format!(
            "{} (cos θ / cos θ_Y {}; {}{real}{moving_text})",
            angles.join(" → "),
            ratios.join(" → "),
            cites.join("; ")
        );
        let row = Row::new(&quantity, fine, 2, None, Some(p.theta_y)).sphlab_text(text);
        let mut row = if found.len() == NXS.len() && nx_fine == NXS[NXS.len() - 1] {
            let within = (fine - p.theta_y).abs() < ANGLE_TOL_DEG && moving.is_empty();
            match reals.iter().copied().collect::<Option<Vec<Realised>>>() {
                Some(reals) => row.check(
                    within && approaches_within_scatter(p.theta_y, &reals),
                    "within 3° of Young's angle at nx = 65, and at every refinement the realisations' midpoint \
                     closer to θ_Y or within two standard errors of it at both resolutions (realisations at every \
                     resolution), every start's contact point stopped (moved at most 2Δx over t ∈ [3, 5])",
                ),
                None => {
                    let off: Vec<f64> = ratio.iter().map(|r| (1.0 - r).abs()).collect();
                    row.check(
                        within && falls(&off),
                        "within 3° of Young's angle at nx = 65, and cos θ / cos θ_Y closer to 1 at every \
                         refinement, every start's contact point stopped (moved at most 2Δx over t ∈ [3, 5]); one \
                         realisation per start where no realisations are named (the runs' folders' README.md)",
                    )
                }
            }
        } else {
            row
        };
        row.qualify(DEPENDS, alpha_band(root, p).as_ref());
        rep.rows.push(row);
    }
}
