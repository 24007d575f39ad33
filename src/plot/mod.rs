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
//!
//! This module holds what a plot is ([`PlotSpec`], [`Series`], [`RefLine`]) and the SVG canvas;
//! `axes` the ranges and tick labels, `line` the line plot, `scatter` the labelled scatter.

use std::path::Path;

use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};

use crate::output::{ensure_parent, OutputError, Result};

mod axes;
mod line;
mod scatter;

pub use axes::fmt_tick;
pub use line::line_plot_svg;
pub use scatter::scatter_labeled_svg;

/// Picture size of every plot (pixels).
pub const PLOT_SIZE: (u32, u32) = (1024, 720);
/// Width (px) of the legend column of a plot with [`PlotSpec::legend_outside`].
pub(crate) const LEGEND_WIDTH: i32 = 330;

/// Colours of the series, in order (Tableau 10), then reused.
pub(crate) const PALETTE: [RGBColor; 10] = [
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

/// Colour k of a series or a stack segment: the ten of [`PALETTE`], then the same hues darker,
/// then lighter, so that up to 30 entries never share a colour.
pub(crate) fn palette(k: usize) -> RGBColor {
    let RGBColor(r, g, b) = PALETTE[k % PALETTE.len()];
    let shade = |c: u8| match (k / PALETTE.len()) % 3 {
        0 => c,
        1 => (f64::from(c) * 0.55).round() as u8,
        _ => (f64::from(c) + (255.0 - f64::from(c)) * 0.55).round() as u8,
    };
    RGBColor(shade(r), shade(g), shade(b))
}

/// The shape of a series' points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Marker {
    /// ○ (filled).
    #[default]
    Circle,
    /// △ (filled).
    Triangle,
    /// □ (filled).
    Square,
    /// ◇ (filled).
    Diamond,
    /// ▽ (filled).
    TriangleDown,
    /// ×.
    Cross,
}

impl Marker {
    /// The marker centred at `at` (data or pixel coordinates) in `color`; with `line`, on a short
    /// horizontal line of that colour (a legend entry of a line with points).
    pub(crate) fn at<C>(self, at: C, color: RGBColor, line: bool) -> Mark<C> {
        Mark { at, marker: self, color, line }
    }
}

/// A drawn [`Marker`]: a plotters element of one point.
pub(crate) struct Mark<C> {
    at: C,
    marker: Marker,
    color: RGBColor,
    line: bool,
}

impl<'a, C> PointCollection<'a, C> for &'a Mark<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Mark<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        b: &mut DB,
        _: (u32, u32),
    ) -> std::result::Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = pos.next() else { return Ok(()) };
        let (fill, stroke) = (self.color.filled(), self.color.stroke_width(2));
        if self.line {
            b.draw_line((x - 12, y), (x + 12, y), &stroke)?;
        }
        let poly = |v: [(i32, i32); 4]| v.map(|(dx, dy)| (x + dx, y + dy));
        match self.marker {
            Marker::Circle => b.draw_circle((x, y), 4, &fill, true),
            Marker::Triangle => b.fill_polygon(poly([(0, -6), (5, 4), (-5, 4), (0, -6)]), &fill),
            Marker::Square => b.draw_rect((x - 4, y - 4), (x + 4, y + 4), &fill, true),
            Marker::Diamond => b.fill_polygon(poly([(0, -6), (5, 0), (0, 6), (-5, 0)]), &fill),
            Marker::TriangleDown => b.fill_polygon(poly([(0, 6), (5, -4), (-5, -4), (0, 6)]), &fill),
            Marker::Cross => {
                b.draw_line((x - 4, y - 4), (x + 4, y + 4), &stroke)?;
                b.draw_line((x - 4, y + 4), (x + 4, y - 4), &stroke)
            }
        }
    }
}

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
    /// Its colour `(r, g, b)`, e.g. one per variant id across plots; `None`: the palette's
    /// colour of its position.
    pub colour: Option<(u8, u8, u8)>,
    /// The shape of its points (styles with points).
    pub marker: Marker,
}

impl Series {
    /// A series with the given style.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Series { label: label.into(), points, style, colour: None, marker: Marker::Circle }
    }
    /// The series' points drawn as `marker`.
    pub fn with_marker(mut self, marker: Marker) -> Self {
        self.marker = marker;
        self
    }
    /// The series in a given colour.
    pub fn with_colour(mut self, rgb: (u8, u8, u8)) -> Self {
        self.colour = Some(rgb);
        self
    }
    /// The series in the palette's colour `k`, whatever its position in the plot (one colour per
    /// family of series across several plots).
    pub fn with_palette_colour(self, k: usize) -> Self {
        let RGBColor(r, g, b) = palette(k);
        self.with_colour((r, g, b))
    }
    /// The colour it is drawn in as the `k`-th series.
    pub(crate) fn colour(&self, k: usize) -> RGBColor {
        self.colour.map_or(palette(k), |(r, g, b)| RGBColor(r, g, b))
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
    /// A line of provenance drawn on the picture (e.g. the adapter), empty for none.
    pub note: String,
}

impl PlotSpec {
    /// A plot with a title and axis labels, no series, linear automatic axes.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        PlotSpec { title: title.into(), x_label: x_label.into(), y_label: y_label.into(), ..Default::default() }
    }
}

pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Maps any plotters error to a message.
pub(crate) fn msg<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Opens an SVG drawing area at `path` (creating its directory) with a white background.
pub(crate) fn svg_area<'a>(path: &'a Path) -> Result<Area<'a>> {
    ensure_parent(path)?;
    let root = SVGBackend::new(path, PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| OutputError::plot(path, msg(e)))?;
    Ok(root)
}
