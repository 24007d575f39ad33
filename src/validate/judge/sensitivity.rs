//! Sensitivity bands read from the committed background-pressure runs: the oscillating-drop
//! sweep (`pb-sweep/pb_sweep.csv`, nx = 24), relax-60 Mode B at nx = 65 with p_b 30 / 45 / 65
//! (`convergence/pb-check/runs`, `convergence/runs/nx65`) and sessile-90 Mode B at nx = 45 with
//! p_b 45 / 90 (`sessile-90/pb-check/runs`).

use crate::validate::data::{col, read_series, window_stats};
use crate::validate::report::Band;
use std::path::Path;

/// The sweep's p_b Δx/σ at × 0.5, × 1 (the rule σ/(2Δx)) and × 2.
const SWEEP_STEPS: [(f64, &str); 3] = [(0.25, "× 0.5"), (0.5, "× 1"), (1.0, "× 2")];

/// Column `column` of the momentum-form rows of `kernel` in `pb-sweep/pb_sweep.csv` at p_b × 0.5,
/// × 1 and × 2 of the rule (those present); `ok` is the verdict's bound.
pub(super) fn pb_sweep_band(root: &Path, kernel: &str, column: &str, ok: impl Fn(f64) -> bool) -> Option<Band> {
    let path = root.join("pb-sweep/pb_sweep.csv");
    let mut reader = csv::Reader::from_path(&path).ok()?;
    let header = reader.headers().ok()?.clone();
    let idx = |name: &str| header.iter().position(|h| h == name);
    let (bg, k, scaled, c) = (idx("background")?, idx("kernel")?, idx("p_b_dx_over_sigma")?, idx(column)?);
    let mut found: Vec<(f64, &str, f64)> = Vec::new();
    for rec in reader.records().map_while(Result::ok) {
        if rec.get(bg) != Some("momentum") || rec.get(k) != Some(kernel) {
            continue;
        }
        let (Some(s), Some(v)) =
            (rec.get(scaled).and_then(|x| x.parse::<f64>().ok()), rec.get(c).and_then(|x| x.parse().ok()))
        else {
            continue;
        };
        if let Some(step) = SWEEP_STEPS.iter().find(|p| (p.0 - s).abs() < 1e-9) {
            found.push((step.0, step.1, v));
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The sweep's own h for this kernel (its rule-p_b run), which need not be the case's.
    let h = std::fs::read_to_string(root.join(format!("pb-sweep/runs/{kernel}-pb24-osc/summary.json")))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["parameters"]["kernel"]["h_ratio"].as_f64())
        .map_or(String::new(), |h| format!(", the sweep's h = {h:.1}Δx"));
    (found.len() >= 2).then(|| Band {
        varied: format!("p_b {} of σ/(2Δx) at nx = 24{h}", found.iter().map(|f| f.1).collect::<Vec<_>>().join(" / ")),
        values: found.iter().map(|f| format!("{:.4}", f.2)).collect(),
        source: "../pb-sweep/pb_sweep.csv".into(),
        holds: Some(found.iter().all(|f| ok(f.2))),
    })
}

/// relax-60 Mode B no-slip at nx = 65 with p_b 30, 45 (the rule) and 65, over t ∈ [4.3, 4.5]:
/// `[θ − 60° by the circle fit, D/D0 at the wall]`, each with the case's bound.
pub(super) fn relax_pb_band(root: &Path) -> Option<[Band; 2]> {
    let dirs = ["convergence/pb-check/runs/nx65-pb30", "convergence/runs/nx65", "convergence/pb-check/runs/nx65-pb65"];
    let dx = 0.5 / 65.0;
    let d_an = crate::validate::relax::analytic_spread();
    let mut theta = Vec::new();
    let mut spread = Vec::new();
    for d in dirs {
        let rows = read_series(&root.join(d));
        theta.push(window_stats(&col(&rows, |r| r.theta_circle_fit.map(|v| v - 60.0)), 4.3, 4.5)?.0);
        spread.push(window_stats(&crate::validate::relax::wall_spread(&rows, dx), 4.3, 4.5)?.0);
    }
    let band = |values: &[f64], holds: bool, prec: usize| Band {
        varied: "p_b 30 / 45 (the rule) / 65 (× 0.67 / × 1 / × 1.44) at nx = 65".into(),
        values: values.iter().map(|v| format!("{v:.prec$}")).collect(),
        source:
            "../convergence/pb-check/runs/nx65-pb30, ../convergence/runs/nx65, ../convergence/pb-check/runs/nx65-pb65"
                .into(),
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
        varied: "p_b × 0.5 / × 1 of σ/Δx at nx = 45".into(),
        values: values.iter().map(|v| format!("{v:.2}")).collect(),
        source: "pb-check/runs/mode-b-pb45, pb-check/runs/mode-b-pb90".into(),
        holds: Some(values.iter().all(|v| *v < 3.0)),
    })
}
