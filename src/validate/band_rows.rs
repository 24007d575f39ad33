//! Rows of a sensitivity band: a case's judged rows built again from its runs under the
//! capillary rule's α × 0.5 and × 2 (docs/PHYSICS.md §3.1: p_b × 0.5 and × 2, c0 unchanged),
//! shown beside the row they repeat as information (not counted), and read back by the judge as
//! that row's band.

use super::report::{Band, Row};
use super::RunSpec;

/// The band's two ends: the id suffix of their runs, α, and the label their rows carry.
pub const BAND: [(&str, f64, &str); 2] =
    [("-alpha1", 1.0, "at p_b × 0.5 (α = 1)"), ("-alpha4", 4.0, "at p_b × 2 (α = 4)")];

/// `spec` at the band end `k`: its id suffixed, the capillary rule's α set, and any p_b or c0
/// the spec names dropped (an explicit value would override the rule, and α would change nothing).
pub fn at_end<'a>(spec: &RunSpec<'a>, k: usize) -> RunSpec<'a> {
    let (suffix, alpha, _) = BAND[k];
    let mut s = spec.clone();
    s.id = format!("{}{suffix}", s.id);
    s.sets.retain(|v| !(v.starts_with("phases.") && (v.contains(".p_b=") || v.contains(".c0="))));
    s.sets.push(format!("capillary_rule.alpha={alpha:.1}"));
    s
}

/// A judged row built from the band end `k`'s runs, as the band of the row it repeats: its
/// quantity prefixed with the end's label, its verdict the criterion's outcome as information
/// (not counted). Rows without a verdict are dropped (nothing to band).
pub fn as_band(k: usize, row: Row) -> Option<Row> {
    let met = if row.verdict.starts_with("pass (") {
        "met"
    } else if row.verdict.starts_with("FAIL (") {
        "not met"
    } else {
        return None;
    };
    let mut r = row;
    r.quantity = format!("{}: {}", BAND[k].2, r.quantity);
    r.verdict = format!("info (band of the row without this prefix: its criterion {met})");
    Some(r)
}

/// The band ends' rows for `quantity`: per end, (sphlab's text, whether the criterion was met).
pub fn rows_of<'a>(rows: &'a [Row], quantity: &str) -> Option<[(&'a str, bool); 2]> {
    let end = |k: usize| {
        let q = format!("{}: {quantity}", BAND[k].2);
        let r = rows.iter().find(|r| r.quantity == q)?;
        Some((r.sphlab.as_str(), r.verdict.contains("criterion met")))
    };
    Some([end(0)?, end(1)?])
}

/// `row`'s band from the band rows among `rows` (none unless both ends have one): the three
/// results, α × 0.5's first, and whether the row's criterion holds at all three.
pub fn band_of(rows: &[Row], row: &Row) -> Option<Band> {
    let [(half, half_met), (double, double_met)] = rows_of(rows, &row.quantity)?;
    let values = [half, row.sphlab.as_str(), double];
    // A value with parts of its own is bracketed, so the band's " / " stays readable.
    let parts = values.iter().any(|v| v.contains(" / ") || v.contains("; "));
    Some(Band {
        varied: "the capillary rule's α × 0.5 / × 1 / × 2 (p_b × 0.5 / × 2, c0 unchanged)".into(),
        values: values.map(|v| if parts { format!("[{v}]") } else { v.to_string() }).to_vec(),
        source: format!(
            "the rows \"{}: …\" and \"{}: …\" (summary.md), from the runs named in the case's notes",
            BAND[0].2, BAND[1].2
        ),
        holds: Some(half_met && row.is_pass() && double_met),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_band_row_is_information_that_keeps_its_criterions_outcome() {
        let pass = Row::new("q", 0.01, 3, None, Some(0.0)).check(true, "≤ 0.05");
        let fail = Row::new("q", 0.1, 3, None, Some(0.0)).check(false, "≤ 0.05");
        let (p, f) = (as_band(0, pass).unwrap(), as_band(1, fail).unwrap());
        assert!(p.verdict.starts_with("info") && f.verdict.starts_with("info"));
        assert!(as_band(0, Row::new("q", 1.0, 3, None, None)).is_none());
        let rows = [p, f];
        assert_eq!(rows_of(&rows, "q"), Some([("0.010", true), ("0.100", false)]));
        assert_eq!(rows_of(&rows, "other"), None);
    }
}
