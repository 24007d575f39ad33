//! Report plots as SVG files, drawn with `plotters` (SVG backend only: text is emitted as SVG
//! `<text>`, so no font files are needed).
//!
//! * [`line_plot_svg`]: curves (lines, points or both) with axis labels, a legend, distinct
//!   colours, optional reference lines (e.g. a value reported in the thesis, dashed), linear or
//!   log axes, automatic ranges with a small margin;
//! * [`scatter_labeled_svg`]: labelled points, e.g. a speed-against-error Pareto plot.
//!
//! Non-finite points (and non-positive ones on a log axis) are skipped, and a line is broken
//! there; empty series still get a legend entry. Nothing here panics on bad data: an unusable
//! range is an [`OutputError::Plot`].

use std::path::Path;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::output::{ensure_parent, OutputError, Result};

/// Picture size of every plot (pixels).
pub const PLOT_SIZE: (u32, u32) = (1024, 720);
/// Width (px) of the legend column of a plot with [`PlotSpec::legend_outside`].
const LEGEND_WIDTH: i32 = 300;

/// Colours of the series, in order (Tableau 10), then reused.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// Connected line.
    #[default]
    Line,
    /// Markers only.
    Points,
    /// Connected line with markers.
    LinePoints,
}

/// One curve of a plot.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `(x, y)` points, drawn in order.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
}

impl Series {
    /// A series with the given style.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Series { label: label.into(), points, style }
    }
    /// A connected line.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Line)
    }
    /// Markers only.
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Points)
    }
    /// A line with markers.
    pub fn line_points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::LinePoints)
    }
}

/// A dashed reference line across the whole plot, e.g. a value reported in the thesis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RefLine {
    /// Legend text.
    pub label: String,
    /// The y value (horizontal line) or x value (vertical line).
    pub value: f64,
    /// True: the line `y = value`; false: the line `x = value`.
    pub horizontal: bool,
}

impl RefLine {
    /// The horizontal line `y = value`.
    pub fn horizontal(label: impl Into<String>, value: f64) -> Self {
        RefLine { label: label.into(), value, horizontal: true }
    }
    /// The vertical line `x = value`.
    pub fn vertical(label: impl Into<String>, value: f64) -> Self {
        RefLine { label: label.into(), value, horizontal: false }
    }
}

/// Everything [`line_plot_svg`] draws.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlotSpec {
    /// Caption above the plot.
    pub title: String,
    /// x-axis label, with units, e.g. `"t (s)"`.
    pub x_label: String,
    /// y-axis label, with units.
    pub y_label: String,
    /// Curves, coloured in order.
    pub series: Vec<Series>,
    /// Dashed reference lines.
    pub refs: Vec<RefLine>,
    /// Logarithmic x axis (base 10).
    pub log_x: bool,
    /// Logarithmic y axis (base 10).
    pub log_y: bool,
    /// Fixed x range; `None`: from the data and reference lines, with a margin.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None`: from the data and reference lines, with a margin.
    pub y_range: Option<(f64, f64)>,
    /// Legend in a column right of the plot (many series) instead of over its upper right.
    pub legend_outside: bool,
}

impl PlotSpec {
    /// A plot with a title and axis labels, no series, linear automatic axes.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        PlotSpec { title: title.into(), x_label: x_label.into(), y_label: y_label.into(), ..Default::default() }
    }
}

/// Can `v` be drawn on an axis (finite, and positive on a log axis)?
fn drawable(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v > 0.0)
}

/// Range of the drawable `values` with a 5 % margin (in log space on a log axis); a default
/// when there is none, a widened one when all are equal.
fn auto_range(values: impl Iterator<Item = f64>, log: bool, margin: f64) -> (f64, f64) {
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
fn axis_range(
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
fn snap_span(lo: f64, hi: f64) -> f64 {
    if lo <= 0.0 && hi >= 0.0 {
        hi - lo
    } else {
        0.0
    }
}

/// Tick label on an axis spanning `span`: like [`fmt_tick`], with float noise around zero
/// (e.g. `-2.2e-16` on a `-1..1` axis) shown as `0`.
fn tick_label(v: f64, span: f64) -> String {
    if v.abs() <= 1e-9 * span {
        "0".to_string()
    } else {
        fmt_tick(v)
    }
}

/// A polyline or point set in data coordinates.
type Points = Vec<(f64, f64)>;

/// Points of a series split into drawable runs (a line is broken at every skipped point).
fn segments(points: &[(f64, f64)], ok: impl Fn(f64, f64) -> bool) -> (Vec<Points>, Points) {
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

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Maps any plotters error to a message.
fn msg<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Draws `spec` on `root` in the coordinates `xc`, `yc` (linear or log).
#[allow(clippy::too_many_arguments)]
fn draw_lines<X, Y>(
    root: &Area<'_>,
    legend: Option<&Area<'_>>,
    spec: &PlotSpec,
    xc: X,
    yc: Y,
    xr: (f64, f64),
    yr: (f64, f64),
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
        .caption(&spec.title, ("sans-serif", 26))
        .margin(20)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d(xc, yc)
        .map_err(msg)?;
    chart
        .configure_mesh()
        .x_desc(spec.x_label.as_str())
        .y_desc(spec.y_label.as_str())
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 14))
        .x_label_formatter(&|v| tick_label(*v, xspan))
        .y_label_formatter(&|v| tick_label(*v, yspan))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(msg)?;

    let inside = |x: f64, y: f64| {
        drawable(x, spec.log_x) && drawable(y, spec.log_y) && (xr.0..=xr.1).contains(&x) && (yr.0..=yr.1).contains(&y)
    };
    let mut labelled = false;
    for (k, s) in spec.series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let line_style = color.stroke_width(2);
        let (segs, pts) = segments(&s.points, inside);
        labelled |= !s.label.is_empty();
        match s.style {
            Style::Line => {
                chart
                    .draw_series(segs.into_iter().map(|seg| PathElement::new(seg, line_style)))
                    .map_err(msg)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x - 12, y), (x + 12, y)], line_style));
            }
            Style::Points => {
                chart
                    .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, color.filled())))
                    .map_err(msg)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
            }
            Style::LinePoints => {
                chart
                    .draw_series(segs.into_iter().map(|seg| PathElement::new(seg, line_style)))
                    .map_err(msg)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(-12, 0), (12, 0)], line_style)
                            + Circle::new((0, 0), 4, color.filled())
                    });
                chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 4, color.filled()))).map_err(msg)?;
            }
        }
    }
    for (j, r) in spec.refs.iter().enumerate() {
        let color = PALETTE[(spec.series.len() + j) % PALETTE.len()];
        let style = color.stroke_width(2);
        let line = if r.horizontal && drawable(r.value, spec.log_y) {
            Some(vec![(xr.0, r.value), (xr.1, r.value)])
        } else if !r.horizontal && drawable(r.value, spec.log_x) {
            Some(vec![(r.value, yr.0), (r.value, yr.1)])
        } else {
            None
        };
        labelled |= !r.label.is_empty();
        chart
            .draw_series(line.into_iter().map(|l| DashedPathElement::new(l, 10, 6, style)))
            .map_err(msg)?
            .label(r.label.as_str())
            .legend(move |(x, y)| DashedPathElement::new(vec![(x - 12, y), (x + 12, y)], 5, 3, style));
    }
    if let Some(area) = legend {
        draw_legend_column(area, spec)?;
    } else if labelled {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 15))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(msg)?;
    }
    Ok(())
}

/// The legend of `spec` as a column in `area` (right of the plot): one row per labelled series
/// and reference line, in the colours and styles [`draw_lines`] gives them.
fn draw_legend_column(area: &Area<'_>, spec: &PlotSpec) -> std::result::Result<(), String> {
    let font = ("sans-serif", 15).into_font();
    let mut y = 80;
    let mut row = |label: &str, color: RGBColor, dashed: bool, dot: bool| -> std::result::Result<(), String> {
        if label.is_empty() {
            return Ok(());
        }
        let style = color.stroke_width(2);
        if dashed {
            area.draw(&DashedPathElement::new(vec![(10, y), (40, y)], 5, 3, style)).map_err(|e| e.to_string())?;
        } else {
            area.draw(&PathElement::new(vec![(10, y), (40, y)], style)).map_err(|e| e.to_string())?;
        }
        if dot {
            area.draw(&Circle::new((25, y), 4, color.filled())).map_err(|e| e.to_string())?;
        }
        area.draw(&Text::new(label.to_string(), (48, y - 8), font.clone())).map_err(|e| e.to_string())?;
        y += 24;
        Ok(())
    };
    for (k, s) in spec.series.iter().enumerate() {
        row(&s.label, PALETTE[k % PALETTE.len()], false, s.style != Style::Line)?;
    }
    for (j, r) in spec.refs.iter().enumerate() {
        row(&r.label, PALETTE[(spec.series.len() + j) % PALETTE.len()], true, false)?;
    }
    Ok(())
}

/// Opens an SVG drawing area at `path` (creating its directory) with a white background.
fn svg_area<'a>(path: &'a Path) -> Result<Area<'a>> {
    ensure_parent(path)?;
    let root = SVGBackend::new(path, PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| OutputError::plot(path, msg(e)))?;
    Ok(root)
}

/// Draws `spec` into the SVG file `path` (parent directory created if missing).
pub fn line_plot_svg(path: impl AsRef<Path>, spec: &PlotSpec) -> Result<()> {
    let path = path.as_ref();
    let xs = spec
        .series
        .iter()
        .flat_map(|s| s.points.iter().filter(|p| drawable(p.1, spec.log_y)).map(|p| p.0))
        .chain(spec.refs.iter().filter(|r| !r.horizontal).map(|r| r.value));
    let xr = axis_range(spec.x_range, xs, spec.log_x, 0.05, "x", path)?;
    let ys = spec
        .series
        .iter()
        .flat_map(|s| {
            s.points.iter().filter(|p| drawable(p.0, spec.log_x) && (xr.0..=xr.1).contains(&p.0)).map(|p| p.1)
        })
        .chain(spec.refs.iter().filter(|r| r.horizontal).map(|r| r.value));
    let yr = axis_range(spec.y_range, ys, spec.log_y, 0.05, "y", path)?;

    let root = svg_area(path)?;
    let (plot, legend) = if spec.legend_outside {
        let (p, l) = root.split_horizontally(PLOT_SIZE.0 as i32 - LEGEND_WIDTH);
        (p, Some(l))
    } else {
        (root.clone(), None)
    };
    let lin = |r: (f64, f64)| RangedCoordf64::from(r.0..r.1);
    let log = |r: (f64, f64)| LogCoord::<f64>::from((r.0..r.1).log_scale());
    let l = legend.as_ref();
    let drawn = match (spec.log_x, spec.log_y) {
        (false, false) => draw_lines(&plot, l, spec, lin(xr), lin(yr), xr, yr),
        (true, false) => draw_lines(&plot, l, spec, log(xr), lin(yr), xr, yr),
        (false, true) => draw_lines(&plot, l, spec, lin(xr), log(yr), xr, yr),
        (true, true) => draw_lines(&plot, l, spec, log(xr), log(yr), xr, yr),
    };
    drawn.map_err(|m| OutputError::plot(path, m))?;
    root.present().map_err(|e| OutputError::plot(path, msg(e)))
}

/// Draws labelled points `(x, y, label)` on `root` in the coordinates `xc`, `yc`.
#[allow(clippy::too_many_arguments)]
fn draw_scatter<X, Y>(
    root: &Area<'_>,
    title: &str,
    x_label: &str,
    y_label: &str,
    pts: &[(f64, f64, String)],
    xc: X,
    yc: Y,
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
        .x_label_formatter(&|v| tick_label(*v, xspan))
        .y_label_formatter(&|v| tick_label(*v, yspan))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(msg)?;
    chart
        .draw_series(pts.iter().enumerate().map(|(k, (x, y, label))| {
            let color = PALETTE[k % PALETTE.len()];
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
    let log = |r: (f64, f64)| LogCoord::<f64>::from((r.0..r.1).log_scale());
    let (t, xl, yl) = (title, x_label, y_label);
    let drawn = match (log_x, log_y) {
        (false, false) => draw_scatter(&root, t, xl, yl, &pts, lin(xr), lin(yr)),
        (true, false) => draw_scatter(&root, t, xl, yl, &pts, log(xr), lin(yr)),
        (false, true) => draw_scatter(&root, t, xl, yl, &pts, lin(xr), log(yr)),
        (true, true) => draw_scatter(&root, t, xl, yl, &pts, log(xr), log(yr)),
    };
    drawn.map_err(|m| OutputError::plot(path, m))?;
    root.present().map_err(|e| OutputError::plot(path, msg(e)))
}
