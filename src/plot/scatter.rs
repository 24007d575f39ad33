//! The labelled scatter plot ([`scatter_labeled_svg`]), e.g. speed against error with the
//! Pareto front.

use std::path::Path;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::axes::{auto_range, axis_label, drawable, log_axis, snap_span};
use super::{msg, palette, svg_area, Area};
use crate::output::{OutputError, Result};

/// Draws labelled points `(x, y, label)` on `root` in the coordinates `xc`, `yc`.
#[allow(
    clippy::too_many_arguments,
    reason = "the drawing area, both coordinate systems and the style are named at every call"
)]
fn draw_scatter<X, Y>(
    root: &Area<'_>,
    title: &str,
    x_label: &str,
    y_label: &str,
    pts: &[(f64, f64, String)],
    xc: X,
    yc: Y,
    (log_x, log_y): (bool, bool),
) -> std::result::Result<(), String>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let (xspan, yspan) = {
        let (rx, ry) = (xc.range(), yc.range());
        (snap_span(rx.start, rx.end), snap_span(ry.start, ry.end))
    };
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 26))
        .margin(20)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d(xc, yc)
        .map_err(msg)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 14))
        .x_label_formatter(&|v| axis_label(*v, xspan, log_x))
        .y_label_formatter(&|v| axis_label(*v, yspan, log_y))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(msg)?;
    chart
        .draw_series(pts.iter().enumerate().map(|(k, (x, y, label))| {
            let color = palette(k);
            EmptyElement::at((*x, *y))
                + Circle::new((0, 0), 5, color.filled())
                + Text::new(label.clone(), (8, -14), ("sans-serif", 14).into_font())
        }))
        .map_err(msg)?;
    Ok(())
}

/// A scatter plot with a text label at each point, e.g. speed against error of the solver
/// variants (a Pareto plot). Points that cannot be drawn (non-finite, non-positive on a log
/// axis) are skipped. Parent directory created if missing.
pub fn scatter_labeled_svg(
    path: impl AsRef<Path>,
    title: &str,
    x_label: &str,
    y_label: &str,
    points: &[(f64, f64, String)],
    log_x: bool,
    log_y: bool,
) -> Result<()> {
    let path = path.as_ref();
    let pts: Vec<(f64, f64, String)> =
        points.iter().filter(|(x, y, _)| drawable(*x, log_x) && drawable(*y, log_y)).cloned().collect();
    // A wider margin than for lines leaves room for the labels.
    let xr = auto_range(pts.iter().map(|p| p.0), log_x, 0.12);
    let yr = auto_range(pts.iter().map(|p| p.1), log_y, 0.12);
    let root = svg_area(path)?;
    let lin = |r: (f64, f64)| RangedCoordf64::from(r.0..r.1);
    let log = log_axis;
    let (t, xl, yl) = (title, x_label, y_label);
    let drawn = match (log_x, log_y) {
        (false, false) => draw_scatter(&root, t, xl, yl, &pts, lin(xr), lin(yr), (log_x, log_y)),
        (true, false) => draw_scatter(&root, t, xl, yl, &pts, log(xr), lin(yr), (log_x, log_y)),
        (false, true) => draw_scatter(&root, t, xl, yl, &pts, lin(xr), log(yr), (log_x, log_y)),
        (true, true) => draw_scatter(&root, t, xl, yl, &pts, log(xr), log(yr), (log_x, log_y)),
    };
    drawn.map_err(|m| OutputError::plot(path, m))?;
    root.present().map_err(|e| OutputError::plot(path, msg(e)))
}
