//! What a capillary case's verdicts depend on under the one background-pressure and sound-speed
//! rule (docs/PHYSICS.md §3.1), and the rule's own sensitivity bands: the oscillating drop and the
//! drop at rest at α × 0.5 / × 1 / × 2 and at nx = 30 / 45, read from
//! `capillary-rule/capillary_rule.csv` (the runs of `examples/analysis/capillary_rule.sh`).

use crate::validate::report::{run_summary, Band, CaseReport};
use std::path::Path;

/// The committed table of the rule's runs, relative to the report root.
const RULE_CSV: &str = "capillary-rule/capillary_rule.csv";

/// "p_b = α·σ|∇C|_max/2 = … and c0 = … by the capillary rule (α, ε), nx = …" as run `run` of
/// the case recorded them (its `summary.json`: the densest phase's p_b and c0, the rule's
/// constants, its resolution), so a verdict names the values its numbers were measured at even
/// after the scene's defaults change. Without a record it names the rule without values.
pub(super) fn rule_text(root: &Path, rep: &CaseReport, run: &str) -> String {
    let record = rep.runs.iter().find(|r| r.id == run).and_then(|r| run_summary(&root.join(&rep.name), r));
    let Some(v) = record else {
        return format!("p_b and c0 by the capillary rule (docs/PHYSICS.md §3.1; run `{run}` has no record)");
    };
    let p = &v["parameters"];
    let dense = p["phases"]
        .as_array()
        .into_iter()
        .flatten()
        .max_by(|a, b| a["rho0"].as_f64().unwrap_or(0.0).total_cmp(&b["rho0"].as_f64().unwrap_or(0.0)));
    let num = |x: Option<&serde_json::Value>, key: &str| x.and_then(|x| x[key].as_f64()).unwrap_or(f64::NAN);
    let (p_b, c0) = (num(dense, "p_b"), num(dense, "c0"));
    let nx = p["domain"]["nx"].as_u64().map_or("?".into(), |n| n.to_string());
    let rule = &p["capillary_rule"];
    if rule.is_object() {
        format!(
            "p_b = α·σ|∇C|_max/2 = {p_b:.1} and c0 = {c0:.1} by the capillary rule (α = {}, ε = {}; docs/PHYSICS.md §3.1), nx = {nx}",
            num(Some(rule), "alpha"),
            num(Some(rule), "epsilon")
        )
    } else {
        format!("p_b = {p_b:.1} and c0 = {c0:.1} set by the scene (before the capillary rule), nx = {nx}")
    }
}

/// Column `column` of the rule's table for `kernel`, at each `(alpha, nx)` of `points` that has
/// a finite value.
fn table(root: &Path, kernel: &str, column: &str, points: &[(f64, u32)]) -> Vec<(f64, u32, f64)> {
    let Ok(mut reader) = csv::Reader::from_path(root.join(RULE_CSV)) else {
        return Vec::new();
    };
    let Ok(header) = reader.headers().cloned() else {
        return Vec::new();
    };
    let idx = |name: &str| header.iter().position(|h| h == name);
    let (Some(a), Some(n), Some(k), Some(c)) = (idx("alpha"), idx("nx"), idx("kernel"), idx(column)) else {
        return Vec::new();
    };
    let num = |rec: &csv::StringRecord, i: usize| rec.get(i).and_then(|x| x.parse::<f64>().ok());
    let mut found = Vec::new();
    for rec in reader.records().map_while(Result::ok) {
        let (Some(alpha), Some(nx), Some(v)) = (num(&rec, a), num(&rec, n), num(&rec, c)) else {
            continue;
        };
        let here = points.iter().any(|p| (p.0 - alpha).abs() < 1e-9 && f64::from(p.1) == nx);
        if rec.get(k) == Some(kernel) && here && v.is_finite() {
            found.push((alpha, nx as u32, v));
        }
    }
    found.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    found
}

/// A band's value with `prec` decimals, or in scientific notation when that would show no
/// significant digit (a kinetic energy of 1e-5).
fn shown(v: f64, prec: usize) -> String {
    if v != 0.0 && v.abs() < 1e-3 {
        format!("{v:.2e}")
    } else {
        format!("{v:.prec$}")
    }
}

fn band(varied: String, found: &[(f64, u32, f64)], prec: usize, ok: impl Fn(f64) -> bool) -> Option<Band> {
    (found.len() >= 2).then(|| Band {
        varied,
        values: found.iter().map(|f| shown(f.2, prec)).collect(),
        source: format!("../{RULE_CSV}"),
        holds: Some(found.iter().all(|f| ok(f.2))),
    })
}

/// The oscillating drop's or the drop at rest's `column` (period, amplitude, jump) with `kernel`
/// at α × 0.5 / × 1 / × 2 of the rule (nx = 30), with whether `ok` holds at each.
pub(super) fn alpha_band(root: &Path, kernel: &str, column: &str, ok: impl Fn(f64) -> bool) -> Option<Band> {
    let found = table(root, kernel, column, &[(1.0, 30), (2.0, 30), (4.0, 30)]);
    let steps: Vec<&str> = found
        .iter()
        .map(|f| match f.0 {
            a if a < 1.5 => "× 0.5",
            a if a < 3.0 => "× 1",
            _ => "× 2",
        })
        .collect();
    band(format!("α {} of the rule at nx = 30", steps.join(" / ")), &found, 4, ok)
}

/// `column` with `kernel` under the rule (α = 2) at nx = 30 and 45 (the rule moves p_b and c0
/// with Δx), with whether `ok` holds at both.
pub(super) fn nx_band(root: &Path, kernel: &str, column: &str, what: &str, ok: impl Fn(f64) -> bool) -> Option<Band> {
    let found = table(root, kernel, column, &[(2.0, 30), (2.0, 45)]);
    band(format!("nx = 30 / 45 under the rule ({what})"), &found, 4, ok)
}

/// The kernels of the rule's runs, with the labels of their rows.
pub(super) const KERNELS: [(&str, &str); 5] = [
    ("quintic", "quintic h = 1.2Δx"),
    ("cubic-spline", "cubic spline h = 1.2Δx"),
    ("wendland-c2", "Wendland C2 h = 1.5Δx"),
    ("johnson", "Johnson quadratic h = 2Δx"),
    ("gaussian", "truncated Gaussian h = 1.2Δx"),
];

/// Column `column` of the rule's runs with `kernel` at nx = 30 and 45 (α of the rule), when both
/// are in the table.
pub(super) fn at_two_resolutions(root: &Path, kernel: &str, column: &str) -> Option<[f64; 2]> {
    let found = table(root, kernel, column, &[(2.0, 30), (2.0, 45)]);
    (found.len() == 2).then(|| [found[0].2, found[1].2])
}
