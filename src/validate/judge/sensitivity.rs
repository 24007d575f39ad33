//! Sensitivity bands read from committed runs: relax-60 at nx = 33 with the capillary
//! rule's α × 0.5 / × 1 / × 2 (docs/PHYSICS.md §3.1; `capillary-rule/relax-60` for the cubic
//! spline, `form-and-kernel/relax-60` for the quintic), and sessile-90's modes at nx = 33 the same
//! way (the case's own band runs, read from its rows); the transport velocity's own p_b × 0.5 /
//! × 1 / × 2 as relax-60's. The drop's bands of the rule are in `rule.rs`.

use super::young_sweep::wall_tension_of;
use super::{of_the_scene, RELAX_RUN_SOURCES};
use crate::validate::data::{col, read_series, window_stats};
use crate::validate::report::{Band, CaseReport};
use crate::validate::sessile::{band_label, peak_shear, BAND_NX, BAND_RUNS};
use std::path::Path;

/// The capillary rule's α × 0.5 / × 1 / × 2 as the suffixes of a run's name: the runs of a
/// sensitivity band are named `<run>-alpha1`, `<run>`, `<run>-alpha4`.
pub(super) const ALPHA_SUFFIXES: [&str; 3] = ["-alpha1", "", "-alpha4"];

/// relax-60 from 90° at nx = 33 in `mode` ("a" or "b") with the bottom wall `wall` ("" for
/// no-slip, "-freeslip") at the capillary rule's α × 0.5 / × 1 / × 2 (`nx33-<mode>-from90<wall>`,
/// the source's suffix, then one of [`ALPHA_SUFFIXES`]: the runs of
/// `examples/analysis/relax_start_angle.sh`, from the first of [`RELAX_RUN_SOURCES`] whose three
/// runs have the scene's kernel and h), over t ∈ [4.3, 4.5]: `[θ − 60° by the circle fit, D/D0
/// at the wall, θ − 60° by the thesis's two-point measure]`, each with the case's bound. At
/// nx = 33, not the headline's 65: an nx = 65 run costs about 17 CPU minutes, one at 33 about 2.
pub(super) fn relax_rule_band(root: &Path, mode: &str, wall: &str) -> Option<[Band; 3]> {
    let slip = if wall.is_empty() { "no-slip" } else { "free-slip" };
    let varied =
        format!("the capillary rule's α × 0.5 / × 1 / × 2 at nx = 33 (Mode {} from 90°, {slip})", mode.to_uppercase());
    relax_band(root, &format!("nx33-{mode}-from90{wall}"), ALPHA_SUFFIXES, &varied)
}

/// The transport-velocity form's own p_b (ρ0c0²) × 0.5 / × 1 / × 2 at nx = 33, Mode B from 90°,
/// no-slip (`nx33-b-from90-tvf<source suffix>{-pb0.5,,-pb2}`), as [`relax_rule_band`] reads its runs.
pub(super) fn relax_transport_band(root: &Path) -> Option<[Band; 3]> {
    let varied = "the transport velocity's p_b = ρ0c0² × 0.5 / × 1 / × 2 at nx = 33 (Mode B from 90°, no-slip)";
    relax_band(root, "nx33-b-from90-tvf", ["-pb0.5", "", "-pb2"], varied)
}

/// Mode A with the unbalanced Young force from 90° at nx = 33 with the bottom wall `wall` ("" for
/// no-slip, "-freeslip") at the capillary rule's α × 0.5 / × 1 / × 2 (the runs of
/// `relax-60/mode-a-line/runs/nx33-from90-unbalanced<wall>`, then one of [`ALPHA_SUFFIXES`]), read
/// as [`relax_rule_band`] reads the wall bands'.
pub(super) fn relax_unbalanced_band(root: &Path, wall: &str) -> Option<[Band; 3]> {
    let slip = if wall.is_empty() { "no-slip" } else { "free-slip" };
    let varied = format!(
        "the capillary rule's α × 0.5 / × 1 / × 2 at nx = 33 (Mode A with the unbalanced Young force from 90°, {slip})"
    );
    let runs = ALPHA_SUFFIXES.map(|s| format!("relax-60/mode-a-line/runs/nx33-from90-unbalanced{wall}{s}"));
    let of_the_form =
        |d: &String| of_the_scene(&root.join(d), 33) && wall_tension_of(&root.join(d)).as_deref() == Some("unbalanced");
    if !runs.iter().all(of_the_form) {
        return None;
    }
    relax_band_of(root, &runs, &varied)
}

/// The band of relax-60's three end-state rows from the runs `<base><source suffix><s>` for each
/// of `suffixes` (what `varied` names), found under the first of [`RELAX_RUN_SOURCES`] that holds
/// all three at nx = 33 with the scene's kernel and h.
fn relax_band(root: &Path, base: &str, suffixes: [&str; 3], varied: &str) -> Option<[Band; 3]> {
    let runs = RELAX_RUN_SOURCES.into_iter().find_map(|(src, suffix)| {
        let all = suffixes.map(|s| format!("{src}/{base}{suffix}{s}"));
        all.iter().all(|d| of_the_scene(&root.join(d), 33)).then_some(all)
    })?;
    relax_band_of(root, &runs, varied)
}

/// The band of relax-60's three end-state rows from `runs` (relative to the report root; runs of
/// the scene's kernel and h at nx = 33, as the callers checked); none when one has no end window.
fn relax_band_of(root: &Path, runs: &[String; 3], varied: &str) -> Option<[Band; 3]> {
    let dx = 0.5 / 33.0;
    let d_an = crate::validate::relax::analytic_spread();
    let (mut theta, mut spread, mut two_point) = (Vec::new(), Vec::new(), Vec::new());
    for d in runs {
        let rows = read_series(&root.join(d));
        theta.push(window_stats(&col(&rows, |r| r.theta_circle_fit.map(|v| v - 60.0)), 4.3, 4.5)?.0);
        spread.push(window_stats(&crate::validate::relax::wall_spread(&rows, dx), 4.3, 4.5)?.0);
        two_point.push(window_stats(&col(&rows, |r| r.theta_two_point.map(|v| v - 60.0)), 4.3, 4.5)?.0);
    }
    let source = runs.iter().map(|r| format!("../{r}")).collect::<Vec<_>>().join(", ");
    let band = |values: &[f64], holds: bool, prec: usize| Band {
        varied: varied.to_string(),
        values: values.iter().map(|v| format!("{v:.prec$}")).collect(),
        source: source.clone(),
        holds: Some(holds),
    };
    Some([
        band(&theta, theta.iter().all(|t| t.abs() < 3.0), 2),
        band(&spread, spread.iter().all(|d| (d / d_an - 1.0).abs() < 0.03), 3),
        band(&two_point, two_point.iter().all(|t| t.abs() < 3.0), 2),
    ])
}

/// sessile-90 Mode B at nx = 33 under the capillary rule's α × 0.5 / × 1 / × 2: the case's own
/// band rows (`sessile::BAND_RUNS`) whose quantity is `what` after the run's label, each judged
/// by `bound` (Mode B's row's own bound); none when the report lacks any of the three.
pub(super) fn sessile_rule_band(rep: &CaseReport, what: &str, bound: impl Fn(f64) -> bool) -> Option<Band> {
    let (values, source) = sessile_band_values(rep, true, what)?;
    Some(Band {
        varied: format!("the capillary rule's α × 0.5 / × 1 / × 2 at nx = {BAND_NX} (Mode B)"),
        values: values.iter().map(|v| format!("{v:.2}")).collect(),
        source,
        holds: Some(values.iter().all(|&v| bound(v))),
    })
}

/// The Mode A / Mode B peak wall shear rate ratio at each α of the band (both modes at nx = 33,
/// the peak in the end window `window`, `sessile::peak_shear`), each judged by `bound` (the ratio
/// row's own); none when any of the six band rows is missing.
pub(super) fn sessile_shear_ratio_band(rep: &CaseReport, window: &str, bound: impl Fn(f64) -> bool) -> Option<Band> {
    let what = peak_shear(window);
    let (b, b_src) = sessile_band_values(rep, true, &what)?;
    let (a, a_src) = sessile_band_values(rep, false, &what)?;
    let ratios: Vec<f64> = a.iter().zip(&b).map(|(a, b)| a / b).collect();
    Some(Band {
        varied: format!("the capillary rule's α × 0.5 / × 1 / × 2 at nx = {BAND_NX} (both modes)"),
        values: ratios.iter().map(|v| format!("{v:.1}")).collect(),
        source: format!("{a_src} over {b_src}"),
        holds: Some(ratios.iter().all(|&v| bound(v))),
    })
}

/// The values of the band rows of one mode whose quantity is `what` after the run's label, in
/// α order, and their runs; none when any is missing or not finite.
fn sessile_band_values(rep: &CaseReport, mode_b: bool, what: &str) -> Option<(Vec<f64>, String)> {
    let runs: Vec<_> = BAND_RUNS.iter().filter(|b| b.2 == mode_b).collect();
    let values = runs
        .iter()
        .map(|&&(_, alpha, _)| {
            let q = format!("{}: {what}", band_label(mode_b, alpha));
            rep.rows.iter().find(|r| r.quantity == q).map(|r| r.value).filter(|v| v.is_finite())
        })
        .collect::<Option<Vec<f64>>>()?;
    Some((values, runs.iter().map(|(id, ..)| format!("runs/{id}")).collect::<Vec<_>>().join(", ")))
}

/// The convergence case's lattice trend under the capillary rule's α × 0.5 and × 2 (runs
/// `convergence/runs/nx<nx>-alpha1` and `-alpha4`, relax-60 as the case runs it), beside the
/// row's own at α (`at_alpha`, coarse to fine over `nxs`): per α the end angle's |θ − 60°|
/// (circle fit, mean over t ∈ [4.3, 4.5]) or, with `density`, the max |ρ/ρ0 − 1| for t ≥ 1,
/// judged as the trend rows are (falls at every refinement); none while a run is missing.
pub(super) fn convergence_alpha_band(root: &Path, nxs: &[u32], at_alpha: &[f64], density: bool) -> Option<Band> {
    lattice_alpha_band(root, "", nxs, at_alpha, density, super::falls)
}

/// [`convergence_alpha_band`] of the lattice runs in the form whose run ids carry `form`
/// (`""` or `"-tangential"`: `nx<nx><form>-alpha1`, `-alpha4`), each trend judged by `holds`.
pub(super) fn lattice_alpha_band(
    root: &Path,
    form: &str,
    nxs: &[u32],
    at_alpha: &[f64],
    density: bool,
    holds: fn(&[f64]) -> bool,
) -> Option<Band> {
    let at = |alpha: &str| -> Option<Vec<f64>> {
        nxs.iter()
            .map(|&nx| {
                let dir = root.join(format!("convergence/runs/nx{nx}{form}-alpha{alpha}"));
                if !of_the_scene(&dir, nx) {
                    return None;
                }
                let rows = read_series(&dir);
                if density {
                    let late = rows.iter().filter(|r| r.t >= 1.0).map(|r| r.max_density_error);
                    Some(late.fold(f64::NAN, f64::max)).filter(|v| v.is_finite())
                } else {
                    window_stats(&col(&rows, |r| r.theta_circle_fit), 4.3, 4.5).map(|s| (s.0 - 60.0).abs())
                }
            })
            .collect()
    };
    let trends = [at("1")?, at_alpha.to_vec(), at("4")?];
    // The tangential rows print their density errors to 4 decimals, the traceless trend row to 3.
    let prec = if !density {
        2
    } else if form.is_empty() {
        3
    } else {
        4
    };
    let text = |t: &Vec<f64>| t.iter().map(|v| format!("{v:.prec$}")).collect::<Vec<_>>().join(" → ");
    let nx_text = nxs.iter().map(u32::to_string).collect::<Vec<_>>().join(",");
    Some(Band {
        varied: format!(
            "the capillary rule's α × 0.5 / × 1 / × 2, the lattice runs at nx = {}",
            nx_text.replace(',', ", ")
        ),
        values: trends.iter().map(text).collect(),
        source: format!("runs/nx{{{nx_text}}}{form}-alpha1, the rows above, runs/nx{{{nx_text}}}{form}-alpha4"),
        holds: Some(trends.iter().all(|t| holds(t))),
    })
}

/// The tangential form's last-state band maximum over the traceless form's under the capillary
/// rule's α × 0.5 and × 2 (the last snapshots of `convergence/runs/nx<nx>-tangential-alpha{1,4}`
/// and `nx<nx>-alpha{1,4}`), at the row's own resolutions `nxs`: per α the worst ratio, beside
/// the row's own (`at_alpha`), each judged below one half as the row is; none while any of the
/// runs or their last snapshots is missing.
pub(super) fn band_max_alpha_band(root: &Path, nxs: &[u32], at_alpha: f64) -> Option<Band> {
    let worst = |alpha: &str| -> Option<f64> {
        let ratios = nxs.iter().map(|&nx| {
            let last = |form: &str| {
                let dir = root.join(format!("convergence/runs/nx{nx}{form}-alpha{alpha}"));
                of_the_scene(&dir, nx).then(|| crate::validate::convergence::relax_last_state(&dir, nx)).flatten()
            };
            Some(last("-tangential")?.band_max / last("")?.band_max)
        });
        ratios.collect::<Option<Vec<f64>>>().map(|r| r.into_iter().fold(f64::NAN, f64::max))
    };
    let worsts = [worst("1")?, at_alpha, worst("4")?];
    let nx_text = nxs.iter().map(u32::to_string).collect::<Vec<_>>().join(",");
    Some(Band {
        varied: format!(
            "the capillary rule's α × 0.5 / × 1 / × 2, the lattice runs' last states at nx = {} (worst ratio)",
            nx_text.replace(',', ", ")
        ),
        values: worsts.iter().map(|v| format!("{v:.3}")).collect(),
        source: format!(
            "runs/nx{{{nx_text}}}{{-tangential,}}-alpha1, the row above, runs/nx{{{nx_text}}}{{-tangential,}}-alpha4"
        ),
        holds: Some(worsts.iter().all(|&w| w < 0.5)),
    })
}
