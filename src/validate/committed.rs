//! What a case's committed report measured, read back: the rows of its `case.json` and the rows
//! of a table it wrote. Particle snapshots are not committed, so a case that reuses a finished
//! run whose snapshots this checkout lacks keeps what the report measured on them from here
//! rather than dropping it.

use super::report::{CaseReport, Row};
use super::Ctx;
use std::path::PathBuf;

/// The committed report of one case: its rows, and the directory its tables lie in.
pub struct Committed {
    rows: Vec<Row>,
    dir: PathBuf,
}

impl Committed {
    /// The report in the case directory of `ctx` (`case.json`), if there is one that reads.
    pub fn load(ctx: &Ctx) -> Option<Committed> {
        let path = ctx.path("case.json");
        let rep: CaseReport = serde_json::from_str(&std::fs::read_to_string(&path).ok()?).ok()?;
        Some(Committed { rows: rep.rows, dir: path.parent()?.to_path_buf() })
    }

    /// The value of the row named exactly `quantity`.
    pub fn value(&self, quantity: &str) -> Option<f64> {
        self.rows.iter().find(|r| r.quantity == quantity).map(|r| r.value).filter(|v| v.is_finite())
    }

    /// The rows of the table `file` (a header line, then numbers; an empty cell is NaN) for which
    /// `keep` holds; none when the table is missing or a cell does not read as a number.
    pub fn table(&self, file: &str, keep: impl Fn(&[f64]) -> bool) -> Vec<Vec<f64>> {
        let Ok(text) = std::fs::read_to_string(self.dir.join(file)) else { return Vec::new() };
        let cell = |c: &str| if c.trim().is_empty() { Some(f64::NAN) } else { c.trim().parse().ok() };
        let rows: Option<Vec<Vec<f64>>> =
            text.lines().skip(1).filter(|l| !l.trim().is_empty()).map(|l| l.split(',').map(cell).collect()).collect();
        rows.unwrap_or_default().into_iter().filter(|r| keep(r)).collect()
    }
}

/// A committed profile that its committed peak row vouches for: `profile` when its largest
/// value equals `peak` (to the 1e-9 relative the table's full-precision numbers keep), else none
/// (a table and rows written by different runs or orders of runs).
pub fn vouched(profile: Vec<(f64, f64)>, peak: Option<f64>) -> Vec<(f64, f64)> {
    let max = profile.iter().map(|p| p.1).fold(f64::NAN, f64::max);
    match peak {
        Some(p) if !profile.is_empty() && (max - p).abs() <= 1e-9 * p.abs().max(1e-300) => profile,
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_profile_is_kept_only_when_its_peak_row_matches() {
        let p = vec![(0.025, 1.5), (0.075, 4.8945), (0.125, 2.0)];
        assert_eq!(vouched(p.clone(), Some(4.8945)).len(), 3);
        assert!(vouched(p.clone(), Some(4.9)).is_empty(), "another run's peak");
        assert!(vouched(p, None).is_empty(), "no committed row");
        assert!(vouched(Vec::new(), Some(4.8945)).is_empty());
    }
}
