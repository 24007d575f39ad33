//! Plot axes: the range of an axis (automatic with a margin, or a given one checked), tick labels
//! without float noise, and a series split into its drawable runs.

use std::path::Path;

use plotters::coord::combinators::WithKeyPoints;
use plotters::prelude::{BindKeyPoints, IntoLogRange, LogCoord};

use crate::output::{OutputError, Result};

/// Can `v` be drawn on an axis (finite, and positive on a log axis)?
pub(crate) fn drawable(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v > 0.0)
}

/// Range of the drawable `values` with a 5 % margin (in log space on a log axis); a default
/// when there is none, a widened one when all are equal.
pub(crate) fn auto_range(values: impl Iterator<Item = f64>, log: bool, margin: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| drawable(*v, log)) {
        let v = if log { v.log10() } else { v };
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if hi - lo <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let pad = if log {
            0.5
        } else if lo == 0.0 {
            1.0
        } else {
            0.1 * lo.abs()
        };
        lo -= pad;
        hi += pad;
    } else {
        let m = margin * (hi - lo);
        lo -= m;
        hi += m;
    }
    if log {
        // plotters labels only powers of ten on a log axis: make sure at least two show.
        if hi.floor() - lo.ceil() < 1.0 {
            lo = lo.floor();
            hi = hi.ceil();
            if hi - lo < 1.0 {
                hi = lo + 1.0;
            }
            // a hair beyond the decades, so rounding in `powf` keeps both inside
            lo -= 1e-9;
            hi += 1e-9;
        }
        (10f64.powf(lo), 10f64.powf(hi))
    } else {
        (lo, hi)
    }
}

/// The axis range: the given one checked, or an automatic one.
pub(crate) fn axis_range(
    given: Option<(f64, f64)>,
    values: impl Iterator<Item = f64>,
    log: bool,
    margin: f64,
    axis: &str,
    path: &Path,
) -> Result<(f64, f64)> {
    match given {
        None => Ok(auto_range(values, log, margin)),
        Some((lo, hi)) => {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                Err(OutputError::plot(path, format!("{axis} range ({lo}, {hi}) is not an increasing finite interval")))
            } else if log && lo <= 0.0 {
                Err(OutputError::plot(path, format!("{axis} range ({lo}, {hi}) is not positive on a log axis")))
            } else {
                Ok((lo, hi))
            }
        }
    }
}

/// Tick label: short, no float noise (`0.30000000000000004` → `0.3`), scientific when large
/// or small.
pub fn fmt_tick(v: f64) -> String {
    if v == 0.0 {
        return "0".to_string();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.3e}");
        match s.split_once('e') {
            Some((mant, exp)) => {
                let mant = if mant.contains('.') { mant.trim_end_matches('0').trim_end_matches('.') } else { mant };
                format!("{mant}e{exp}")
            }
            None => s,
        }
    } else {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// The span within which [`tick_label`] snaps ticks to `0`: the axis length when the axis
/// contains zero, else 0 (an axis that excludes zero, such as every log axis, has no float noise
/// around zero: `1e-15` on a `1e-15..1e-3` log axis is `1e-15`, not `0`).
pub(crate) fn snap_span(lo: f64, hi: f64) -> f64 {
    if lo <= 0.0 && hi >= 0.0 {
        hi - lo
    } else {
        0.0
    }
}

/// Tick label on an axis spanning `span`: like [`fmt_tick`], with float noise around zero
/// (e.g. `-2.2e-16` on a `-1..1` axis) shown as `0`.
pub(crate) fn tick_label(v: f64, span: f64) -> String {
    if v.abs() <= 1e-9 * span {
        "0".to_string()
    } else {
        fmt_tick(v)
    }
}

/// Tick label on an axis: on a log axis the grid's bold points of [`log_grid`] (a power of ten
/// read without rounding noise, so labels never read `31622.776602`), else [`tick_label`].
pub(crate) fn axis_label(v: f64, span: f64, log: bool) -> String {
    if !log {
        return tick_label(v, span);
    }
    let e = v.log10();
    if v > 0.0 && (e - e.round()).abs() < 1e-9 {
        fmt_tick(10f64.powi(e.round() as i32))
    } else {
        fmt_tick(v)
    }
}

/// `m`·10^`k`, rounded once (`3 / 100`, not `3 · 0.01`).
fn decade_multiple(m: u32, k: i32) -> f64 {
    if k >= 0 {
        f64::from(m) * 10f64.powi(k)
    } else {
        f64::from(m) / 10f64.powi(-k)
    }
}

/// Grid of a log axis over `lo..hi` (both positive): the bold, labelled lines at the powers of
/// ten, or at 1, 2 and 5 times them where fewer than two powers of ten fall inside, or at the
/// ends where fewer than two of those do; the light lines at every 1–9 multiple of a power of
/// ten inside. (The drawing library's own log grid puts light lines at linear steps, a dense
/// band below each power of ten, and can label one power of ten twice.)
pub(crate) fn log_grid(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let inside = |v: f64| v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9);
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let multiples = |ms: &[u32]| -> Vec<f64> {
        (k0..=k1).flat_map(|k| ms.iter().map(move |&m| decade_multiple(m, k))).filter(|v| inside(*v)).collect()
    };
    let light = multiples(&[1, 2, 3, 4, 5, 6, 7, 8, 9]);
    let mut bold = multiples(&[1]);
    if bold.len() < 2 {
        bold = multiples(&[1, 2, 5]);
    }
    if bold.len() < 2 {
        bold = vec![lo, hi];
    }
    (bold, light)
}

/// A log axis over `r` drawn with the grid of [`log_grid`].
pub(crate) fn log_axis(r: (f64, f64)) -> WithKeyPoints<LogCoord<f64>> {
    let (bold, light) = log_grid(r.0, r.1);
    LogCoord::<f64>::from((r.0..r.1).log_scale()).with_key_points(bold).with_light_points(light)
}

/// A polyline or point set in data coordinates.
pub(crate) type Points = Vec<(f64, f64)>;

/// Points of a series split into drawable runs (a line is broken at every skipped point).
pub(crate) fn segments(points: &[(f64, f64)], ok: impl Fn(f64, f64) -> bool) -> (Vec<Points>, Points) {
    let mut segs = Vec::new();
    let mut cur = Vec::new();
    let mut all = Vec::new();
    for &(x, y) in points {
        if ok(x, y) {
            cur.push((x, y));
            all.push((x, y));
        } else if !cur.is_empty() {
            segs.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        segs.push(cur);
    }
    (segs, all)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(vs: &[f64]) -> Vec<String> {
        vs.iter().map(|v| axis_label(*v, 0.0, true)).collect()
    }

    #[test]
    fn a_log_grid_labels_each_power_of_ten_once_and_lines_every_multiple() {
        // The speed-vs-error plot's period-error axis: neither end on a power of ten.
        let (bold, light) = log_grid(0.0075, 0.18);
        assert_eq!(labels(&bold), ["0.01", "0.1"]);
        let want = [0.008, 0.009, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09, 0.1];
        assert_eq!(light.len(), want.len(), "{light:?}");
        for (got, want) in light.iter().zip(want) {
            assert!((got - want).abs() < 1e-15, "{light:?}");
        }
        // Several decades, ends on powers of ten.
        let (bold, light) = log_grid(1.0, 1000.0);
        assert_eq!(labels(&bold), ["1", "10", "100", "1000"]);
        assert_eq!(light.len(), 28);
        assert!(light.windows(2).all(|w| w[0] < w[1]), "increasing, no repeats: {light:?}");
    }

    #[test]
    fn a_log_grid_within_one_decade_falls_back_to_one_two_five_then_the_ends() {
        let (bold, _) = log_grid(2.0, 40.0);
        assert_eq!(labels(&bold), ["2", "5", "10", "20"]);
        let (bold, light) = log_grid(3.1, 3.9);
        assert_eq!(labels(&bold), ["3.1", "3.9"]);
        assert!(light.is_empty());
    }
}
