//! Sensitivity bands read from committed runs: relax-60 at nx = 33 with the capillary
//! rule's α × 0.5 / × 1 / × 2 (docs/PHYSICS.md §3.1; `capillary-rule/relax-60` for the cubic
//! spline, `form-and-kernel/relax-60` for the quintic), and sessile-90 Mode B at nx = 45 with p_b
//! 45 / 90 (`sessile-90/pb-check/runs`, made before the rule and the quintic). The drop's bands
//! of the rule are in `rule.rs`.

use super::{of_the_scene, RELAX_RUN_SOURCES};
use crate::validate::data::{col, read_series, window_stats};
use crate::validate::report::Band;
use std::path::Path;

/// relax-60 from 90° at nx = 33 in `mode` ("a" or "b") with the bottom wall `wall` ("" for
/// no-slip, "-freeslip") at the capillary rule's α × 0.5 / × 1 / × 2 (`nx33-<mode>-from90<wall>`
/// with `-alpha1` or `-alpha4` before or after the source's suffix, the runs of
/// `examples/analysis/relax_start_angle.sh`, from the first of [`RELAX_RUN_SOURCES`] whose three
/// runs have the scene's kernel and h), over t ∈ [4.3, 4.5]: `[θ − 60° by the circle fit, D/D0
/// at the wall]`, each with the case's bound. At nx = 33, not the headline's 65: an nx = 65 run
/// costs about 17 CPU minutes, one at 33 about 2.
pub(super) fn relax_rule_band(root: &Path, mode: &str, wall: &str) -> Option<[Band; 2]> {
    let base = format!("nx33-{mode}-from90{wall}");
    let run = |src: &str, suffix: &str, alpha: &str| {
        [format!("{src}/{base}{alpha}{suffix}"), format!("{src}/{base}{suffix}{alpha}")]
            .into_iter()
            .find(|d| of_the_scene(&root.join(d), 33))
    };
    let runs = RELAX_RUN_SOURCES.into_iter().find_map(|(src, suffix)| {
        Some([run(src, suffix, "-alpha1")?, run(src, suffix, "")?, run(src, suffix, "-alpha4")?])
    })?;
    let dx = 0.5 / 33.0;
    let d_an = crate::validate::relax::analytic_spread();
    let mut theta = Vec::new();
    let mut spread = Vec::new();
    for d in &runs {
        let rows = read_series(&root.join(d));
        theta.push(window_stats(&col(&rows, |r| r.theta_circle_fit.map(|v| v - 60.0)), 4.3, 4.5)?.0);
        spread.push(window_stats(&crate::validate::relax::wall_spread(&rows, dx), 4.3, 4.5)?.0);
    }
    let source = runs.iter().map(|r| format!("../{r}")).collect::<Vec<_>>().join(", ");
    let slip = if wall.is_empty() { "no-slip" } else { "free-slip" };
    let band = |values: &[f64], holds: bool, prec: usize| Band {
        varied: format!(
            "the capillary rule's α × 0.5 / × 1 / × 2 at nx = 33 (Mode {} from 90°, {slip})",
            mode.to_uppercase()
        ),
        values: values.iter().map(|v| format!("{v:.prec$}")).collect(),
        source: source.clone(),
        holds: Some(holds),
    };
    Some([
        band(&theta, theta.iter().all(|t| t.abs() < 3.0), 2),
        band(&spread, spread.iter().all(|d| (d / d_an - 1.0).abs() < 0.03), 3),
    ])
}

/// sessile-90 Mode B at nx = 45 with p_b 45 and 90 (× 0.5 and × 1 of σ/Δx): max |θ − 90°| by the
/// circle fit over the whole run, with the case's bound (< 3°).
pub(super) fn sessile_pb_band(root: &Path) -> Option<Band> {
    let mut values = Vec::new();
    for d in ["sessile-90/pb-check/runs/mode-b-pb45", "sessile-90/pb-check/runs/mode-b-pb90"] {
        let rows = read_series(&root.join(d));
        let dev = col(&rows, |r| r.theta_circle_fit.map(|v| (v - 90.0).abs()));
        if dev.is_empty() {
            return None;
        }
        values.push(dev.iter().map(|p| p.1).fold(f64::NAN, f64::max));
    }
    Some(Band {
        varied: "p_b 45 / 90 at nx = 45, c0 = 20, the cubic spline h = 1.2Δx (runs before the capillary rule; × 0.5 / × 1 of its σ/Δx then)".into(),
        values: values.iter().map(|v| format!("{v:.2}")).collect(),
        source: "pb-check/runs/mode-b-pb45, pb-check/runs/mode-b-pb90".into(),
        holds: Some(values.iter().all(|v| *v < 3.0)),
    })
}
