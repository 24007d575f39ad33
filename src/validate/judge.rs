//! Verdicts that read more than the row they judge: results held to theory or to the thesis
//! where a case's measure only reported them (Mode A against Young's angle, the thesis's
//! two-point angle, the Mode A / Mode B shear ratio, the trend with refinement), and for every
//! pass what it depends on with its sensitivity band from the committed background-pressure
//! runs. Applied to a case's report after its measures, and by `validate --rejudge` to a
//! committed `case.json` (whose particle snapshots are not committed), so both give the same
//! verdicts. The bands' numbers are read from the committed files named in each verdict.

use super::band_rows::band_of;
use super::data::{col, read_series, window_stats};
use super::report::{Band, CaseReport, Row};
use super::Ctx;
use std::path::Path;

mod convergence;
mod rule;
mod sensitivity;
#[cfg(test)]
mod sweep_tests;
#[cfg(test)]
mod tests;
mod young_sweep;

use rule::{alpha_band, at_two_resolutions, nx_band, rule_text, KERNELS};
use sensitivity::{
    relax_rule_band, relax_transport_band, relax_unbalanced_band, sessile_rule_band, sessile_shear_ratio_band,
};

/// Young's angle of relax-60 (deg).
pub(super) const YOUNG_DEG: f64 = 60.0;
/// The bound on a relax-60 angle, as the case's Mode B rows (deg).
pub(super) const ANGLE_TOL_DEG: f64 = 3.0;
/// The bound on D/D0 at the wall, as the case's Mode B rows.
const SPREAD_TOL: f64 = 0.03;
/// The thesis's Mode A / Mode B peak wall shear ratio is met within this factor.
const SHEAR_RATIO_FACTOR: f64 = 2.0;

/// Applies the verdicts of case `name` to its report (full runs only: `--quick` checks direction).
pub fn judge(name: &str, ctx: &Ctx, rep: &mut CaseReport) {
    if rep.quick {
        return;
    }
    let root = ctx.opts.out.as_path();
    match name {
        "oscillation" => oscillation(root, rep),
        "sessile-90" => sessile(root, &super::sessile::shear_window(ctx.opts.long_t_end(0.3)).2, rep),
        "relax-60" => relax(root, &super::sessile::shear_window(ctx.opts.long_t_end(0.3)).2, rep),
        "convergence" => convergence::convergence(root, rep),
        "spurious" => spurious(root, rep),
        "cross-code" => cross_code(rep),
        "capillary-wave" => capillary_wave(root, rep),
        "impact" => {
            let dir = root.join(&rep.name);
            for r in rep.rows.iter_mut() {
                let band = if r.quantity.starts_with("D/D0 at t = ") {
                    super::impact::direction_band(&dir, &r.quantity)
                } else {
                    None
                };
                r.qualify(
                    "nx = 48 (not shown converged: nx32-check/README.md), water's c0 and the scene's p_b; the nx = 24 rows above",
                    band.as_ref(),
                );
            }
        }
        _ => {}
    }
    // Every pass and FAIL says whether a sensitivity band stands beside it: a row no rule above
    // qualified says it has none.
    for r in rep.rows.iter_mut().filter(|r| !r.is_qualified()) {
        r.qualify("the case's scene and run parameters (summary.md; not itemised for this row)", None);
    }
}

/// Every row whose quantity starts with `prefix`.
fn rows<'a>(rep: &'a mut CaseReport, prefix: &'a str) -> impl Iterator<Item = &'a mut Row> + 'a {
    rep.rows.iter_mut().filter(move |r| r.quantity.starts_with(prefix))
}

/// What the rule's runs at nx = 30 and 45 depend on.
const AT_EACH_NX: &str =
    "p_b and c0 by the capillary rule at each nx (α = 2, ε = 0.01; docs/PHYSICS.md §3.1), the oscillating drop's scene";

/// The drop's radius (σ/R is the Laplace jump).
const DROP_R: f64 = 0.1875;

fn oscillation(root: &Path, rep: &mut CaseReport) {
    let on = format!("{}, the initial field, μ", rule_text(root, rep, "quintic"));
    let period = alpha_band(root, "quintic", "period", |v| (v / 0.37 - 1.0).abs() <= 0.05);
    for r in rows(rep, "period, field on all particles, quintic") {
        r.qualify(&format!("{on}, the quintic at h = 1.2Δx"), period.as_ref());
    }
    let amp = alpha_band(root, "quintic", "amplitude", |v| (v / 0.012 - 1.0).abs() <= 0.2);
    for r in rows(rep, "first-cycle amplitude, field on all particles, quintic") {
        r.qualify(&format!("{on}, the quintic at h = 1.2Δx"), amp.as_ref());
    }
    // (row prefix, the kernel in the rule's table, the case's run of that kernel)
    let kernels = [
        ("period, cubic spline", "cubic-spline", "cubic"),
        ("period, Wendland C2", "wendland-c2", "wendland"),
        ("period, truncated Gaussian", "gaussian", "gaussian"),
        ("period, Johnson quadratic", "johnson", "johnson"),
    ];
    for (prefix, kernel, run) in kernels {
        // Against the thesis's 0.37 (the bound of check 1 of ../capillary-rule/README.md); the
        // case's own bound is against the quintic's period of the same run.
        let band = nx_band(root, kernel, "period", "against 0.37 ± 5 %", |v| (v / 0.37 - 1.0).abs() <= 0.05);
        let own = format!(
            "{}, the initial field, μ, the kernel's h (the rule at that kernel); against the quintic's period",
            rule_text(root, rep, run)
        );
        for r in rows(rep, prefix) {
            r.qualify(&own, band.as_ref());
        }
    }
    let on = format!("{AT_EACH_NX}, the initial field, μ, the kernel's h");
    at_both_resolutions(root, rep, ("period", "period"), (0.37, 0.05), 4, &on);
}

/// Rows holding every kernel to the thesis at both resolutions of the rule's runs
/// (`capillary-rule/capillary_rule.csv`): the table's `column` (rows named by `what`) within
/// `tol` (relative) of `target` at nx = 30 and at nx = 45, each depending on `on` and carrying
/// that kernel's own α × 0.5 / × 2 band at nx = 30 where the table has it. Replaces the rows an
/// earlier judging added.
fn at_both_resolutions(
    root: &Path,
    rep: &mut CaseReport,
    (what, column): (&str, &str),
    (target, tol): (f64, f64),
    prec: usize,
    on: &str,
) {
    let head = format!("{what} under the rule at nx = 30 / 45, ");
    rep.rows.retain(|r| !r.quantity.starts_with(&head));
    let within = |x: f64| (x / target - 1.0).abs() <= tol;
    for (kernel, label) in KERNELS {
        let Some(v) = at_two_resolutions(root, kernel, column) else {
            continue;
        };
        let mut row = Row::new(&format!("{head}{label}"), v[1], prec, None, Some(target))
            .sphlab_text(format!("{:.prec$} / {:.prec$} (../capillary-rule/capillary_rule.csv)", v[0], v[1]))
            .check(
                v.iter().all(|&x| within(x)),
                &format!("within {:.0} % of {target:.4} at both resolutions", 100.0 * tol),
            );
        row.qualify(on, alpha_band(root, kernel, column, within).as_ref());
        rep.rows.push(row);
    }
}

fn spurious(root: &Path, rep: &mut CaseReport) {
    let on = format!("{}, the quintic at h = 1.2Δx", rule_text(root, rep, "rest"));
    let what = "the drop at rest to t = 1";
    let speed = nx_band(root, "quintic", "spurious_speed", what, |v| v < 0.1);
    let jump = nx_band(root, "quintic", "jump", what, |v| (v * DROP_R - 1.0).abs() <= 0.03);
    for r in rows(rep, "max fluid speed over") {
        r.qualify(&on, speed.as_ref());
    }
    for r in rows(rep, "Laplace jump") {
        r.qualify(&on, jump.as_ref());
    }
    let ke = alpha_band(root, "quintic", "rest_max_ke", |v| v < super::spurious::KE_BOUND).map(|mut b| {
        b.varied.push_str(&format!(" ({what})"));
        b
    });
    for r in rows(rep, "max liquid kinetic energy") {
        r.qualify(&on, ke.as_ref());
    }
    let on = format!("{AT_EACH_NX}, the kernel's h");
    at_both_resolutions(root, rep, ("Laplace jump of the drop at rest", "jump"), (1.0 / DROP_R, 0.03), 3, &on);
}

/// The rod's rows with their band from the case's own runs at p_b × 0.5 and × 2.
fn cross_code(rep: &mut CaseReport) {
    let bands = super::cross_code::pb_bands(rep);
    for r in rep.rows.iter_mut() {
        let band = bands.iter().find(|b| b.0 == r.quantity).map(|b| &b.1);
        r.qualify(
            "PySPH's own parameters as its script sets them (scenes/pysph-rod.toml), none chosen for the match",
            band,
        );
    }
}

/// The capillary wave's rows that are themselves p_b tests (a sweep of p_b, the tangential form at
/// half of it, p_b out of the momentum equation): no α band repeats them.
const P_B_TESTS: [&str; 3] =
    ["period error against p_b", "the tangential form at p_b × 0.5", "→ transport-velocity form"];

/// Every judged row of the capillary wave with its band: the same row built from the runs under
/// the capillary rule's α × 0.5 and × 2 (`wave_band`), where the case has both.
fn capillary_wave(root: &Path, rep: &mut CaseReport) {
    let rule = rule_text(root, rep, "ratio1");
    const HEAD: &str = "rms of a/a0 − Prosperetti, t ≤ ";
    let bands: Vec<Option<Band>> = rep.rows.iter().map(|r| band_of(&rep.rows, r)).collect();
    for (r, band) in rep.rows.iter_mut().zip(bands) {
        let depends = if r.quantity.starts_with(HEAD) && r.quantity.ends_with("(3 periods), density ratio 1") {
            format!("{rule}; the 3-period window chosen after the first run (README.md)")
        } else {
            let each =
                "p_b and c0 by the capillary rule at each run's Δx (docs/PHYSICS.md §3.1), La = 3000, the quintic \
                        at h = 1.2Δx, the lattice start unless the row names another";
            if P_B_TESTS.iter().any(|t| r.quantity.contains(t)) {
                format!("{each}; the row itself tests how large p_b is or where it acts (its runs are named in it), so the α band does not repeat it")
            } else {
                each.to_string()
            }
        };
        r.qualify(&depends, band.as_ref());
    }
}

/// sessile-90's judged rows over the end window `wtext` (the case's, e.g. "t ∈ [4.3, 4.5]").
fn sessile(root: &Path, wtext: &str, rep: &mut CaseReport) {
    let rule = rule_text(root, rep, "mode-b");
    let circle = sessile_rule_band(rep, "max |θ − 90°|, circle fit, whole run (deg)", |v| v < 3.0);
    for r in rows(rep, "Mode B: max |θ − 90°|, circle fit") {
        r.qualify(
            &format!("{rule}, μ = 0.15, a start at θ_Y = 90° (it tests that the drop stays there)"),
            circle.as_ref(),
        );
    }
    // the band rows name the same quantity after their own label (the case's end window)
    let what =
        rep.rows.iter().find_map(|r| r.quantity.strip_prefix("Mode B: max normal deviation, mean").map(str::to_string));
    let normal = what.and_then(|w| sessile_rule_band(rep, &format!("max normal deviation, mean{w}"), |v| v <= 8.0));
    for r in rows(rep, "Mode B: max normal deviation, mean") {
        r.qualify(
            &format!("{rule}; the earlier per-scene p_b: pb-check/README.md; the measure: normal-deviation/README.md"),
            normal.as_ref(),
        );
    }
    let thesis = super::sessile::THESIS_SHEAR_RATIO;
    let within =
        |ratio: f64| ratio.is_finite() && ratio >= thesis / SHEAR_RATIO_FACTOR && ratio <= thesis * SHEAR_RATIO_FACTOR;
    let band = sessile_shear_ratio_band(rep, wtext, within);
    for r in rep.rows.iter_mut().filter(|r| r.quantity == "peak wall shear rate ratio, Mode A / Mode B") {
        *r = r.clone().check(
            within(r.value),
            &format!("within a factor {SHEAR_RATIO_FACTOR} of the thesis's ~{thesis:.0}; Mode B lower than Mode A is only the direction"),
        );
        r.qualify(&format!("{rule} (both modes), μ = 0.15, Mode A's wall tensions (the scene's)"), band.as_ref());
    }
}

/// The variants of relax-60 judged against Young's angle at the wall and in the cap: every run
/// started at 90° (the from-45° runs are judged through the two-start midpoint).
const RELAX_FROM_90: [&str; 7] = [
    "Mode B, no-slip:",
    "Mode B, no-slip, transport velocity:",
    "Mode B, free-slip:",
    "Mode A, no-slip:",
    "Mode A, free-slip:",
    "Mode A, unbalanced Young force, no-slip:",
    "Mode A, unbalanced Young force, free-slip:",
];

/// relax-60's rows over the end window `wtext` (the case's, e.g. "t ∈ [4.3, 4.5]").
fn relax(root: &Path, wtext: &str, rep: &mut CaseReport) {
    let window = format!("mean over {wtext}");
    let rule = rule_text(root, rep, "b-noslip");
    for label in RELAX_FROM_90 {
        let why = if label.starts_with("Mode A, unbalanced") {
            "; the form at θ_Y 41°–120°, nx = 33, 45, 65: mode-a-line/README.md"
        } else if label.starts_with("Mode A") {
            "; Mode A under the rule, both starts and θ_Y 60°–120°: ../capillary-rule/README.md"
        } else {
            ""
        };
        let two_point = rep.row(&format!("{label} θ − 60°, two-point, {window}")).map(|r| r.value + YOUNG_DEG);
        let circle = format!("{label} θ − 60°, circle fit, {window}");
        let spread = format!("{label} D/D0 at the wall, {window}");
        let pb = match label {
            "Mode B, no-slip:" => relax_rule_band(root, "b", ""),
            "Mode A, no-slip:" => relax_rule_band(root, "a", ""),
            "Mode B, free-slip:" => relax_rule_band(root, "b", "-freeslip"),
            "Mode A, free-slip:" => relax_rule_band(root, "a", "-freeslip"),
            "Mode A, unbalanced Young force, no-slip:" => relax_unbalanced_band(root, ""),
            "Mode A, unbalanced Young force, free-slip:" => relax_unbalanced_band(root, "-freeslip"),
            "Mode B, no-slip, transport velocity:" => relax_transport_band(root),
            _ => None,
        };
        let depends = match label {
            "Mode B, no-slip, transport velocity:" => {
                format!("p_b = ρ0c0² in the transport velocity only, c0 of {rule}, μ = 0.05")
            }
            _ => format!("{rule} (p_b in the EOS and momentum equation), μ = 0.05"),
        };
        for r in rows(rep, &circle) {
            let ok = r.value.abs() < ANGLE_TOL_DEG;
            let thesis = two_point.map_or(String::new(), |t| format!("; the thesis's two-point metric: {t:.1}°"));
            *r = r.clone().check(ok, &format!("|θ − 60°| < 3° (Young's angle){thesis}{why}"));
            r.qualify(&depends, pb.as_ref().map(|b| &b[0]));
        }
        for r in rows(rep, &format!("{label} θ − 60°, two-point, {window}")) {
            let ok = r.value.abs() < ANGLE_TOL_DEG;
            *r = r.clone().check(ok, "|θ − 60°| < 3° by the thesis's metric (the first two rows at the wall)");
            r.qualify(&depends, pb.as_ref().map(|b| &b[2]));
        }
        let d_an = super::relax::analytic_spread();
        for r in rows(rep, &spread) {
            let ok = (r.value / d_an - 1.0).abs() < SPREAD_TOL;
            *r = r.clone().check(ok, &format!("within 3 % of the 60° cap's {d_an:.3}{why}"));
            r.qualify(&depends, pb.as_ref().map(|b| &b[1]));
        }
    }
    for (head, why) in [
        ("Mode A, no-slip", "../capillary-rule/README.md"),
        ("Mode A, unbalanced Young force, no-slip", "mode-a-line/README.md"),
    ] {
        for r in rows(rep, &format!("{head}: end angle approached from both sides")) {
            let mid = r.value;
            *r = r.clone().check(
                mid.abs() < ANGLE_TOL_DEG,
                &format!("|midpoint − 60°| < 3°: Young's angle, from either side; {why}"),
            );
        }
    }
    for (mode, head) in
        [("a", "Mode A, no-slip"), ("b", "Mode B, no-slip"), ("unbalanced", "Mode A, unbalanced Young force, no-slip")]
    {
        let band = young_sweep::both_sides_band(root, mode);
        for r in rows(rep, &format!("{head}: end angle approached from both sides")) {
            r.qualify(&rule, band.as_ref());
        }
    }
    young_sweep::young_sweep_rows(root, rep);
}

/// Whether `errors` (by resolution, coarse to fine) fall at every refinement.
pub(super) fn falls(errors: &[f64]) -> bool {
    errors.len() >= 2 && errors.windows(2).all(|w| w[1] < w[0])
}

/// Where the committed relax-60 study runs are, relative to the report root, with the suffix of
/// their folder names: the capillary rule's (made with the cubic spline) and the quintic's.
pub(super) const RELAX_RUN_SOURCES: [(&str, &str); 2] =
    [("capillary-rule/relax-60", ""), ("form-and-kernel/relax-60", "-quintic")];

/// Whether the run in `dir` is of relax-60 at the particle spacing of `nx` across the scene's
/// box (a wider box at that spacing, as the Young sweep's 41° point takes, counts) with the
/// kernel and h the scene takes now.
pub(super) fn of_the_scene(dir: &Path, nx: u32) -> bool {
    let scene = crate::scene::builtin::builtin("relax-60");
    let (Some(now), Some(v), Some(scene)) =
        (super::report::kernel_now("relax-60"), super::report::summary_at(dir), scene)
    else {
        return false;
    };
    let want = (scene.domain.x[1] - scene.domain.x[0]) / f64::from(nx);
    v["scene"] == "relax-60"
        && v["parameters"]["kernel"] == now
        && run_spacing(&v).is_some_and(|s| (s - want).abs() <= 1e-9 * want)
}

/// The particle spacing across x of a run, from its summary.json's domain.
pub(super) fn run_spacing(summary: &serde_json::Value) -> Option<f64> {
    let d = &summary["parameters"]["domain"];
    Some((d["x"][1].as_f64()? - d["x"][0].as_f64()?) / d["nx"].as_f64()?)
}

/// The circle-fit angle of the committed run in `dir`, mean over relax-60's end window
/// t ∈ [4.3, 4.5] (None without its series or rows there).
fn end_angle(dir: &Path) -> Option<f64> {
    window_stats(&col(&read_series(dir), |r| r.theta_circle_fit), 4.3, 4.5).map(|s| s.0)
}
