//! The line plot ([`line_plot_svg`]): curves as lines, points or both, reference lines dashed,
//! the legend inside the plot or in a column beside it, linear or log axes.

use std::path::Path;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::axes::{axis_label, axis_range, drawable, log_axis, segments, snap_span};
use super::{msg, palette, svg_area, Area, Marker, PlotSpec, Style, LEGEND_WIDTH, PLOT_SIZE};
use crate::output::{OutputError, Result};

/// Draws `spec` on `root` in the coordinates `xc`, `yc` (linear or log).
#[allow(
    clippy::too_many_arguments,
    reason = "the drawing area, both coordinate systems and the style are named at every call"
)]
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
        .caption(&spec.title, ("sans-serif", caption_px(&spec.title, root.dim_in_pixel().0)))
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
        .x_label_formatter(&|v| axis_label(*v, xspan, spec.log_x))
        .y_label_formatter(&|v| axis_label(*v, yspan, spec.log_y))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(msg)?;

    let inside = |x: f64, y: f64| {
        drawable(x, spec.log_x) && drawable(y, spec.log_y) && (xr.0..=xr.1).contains(&x) && (yr.0..=yr.1).contains(&y)
    };
    let mut labelled = false;
    for (k, s) in spec.series.iter().enumerate() {
        let color = s.colour(k);
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
                let mk = s.marker;
                chart
                    .draw_series(pts.into_iter().map(|p| mk.at(p, color, false)))
                    .map_err(msg)?
                    .label(s.label.as_str())
                    .legend(move |p| mk.at(p, color, false));
            }
            Style::LinePoints => {
                let mk = s.marker;
                chart
                    .draw_series(segs.into_iter().map(|seg| PathElement::new(seg, line_style)))
                    .map_err(msg)?
                    .label(s.label.as_str())
                    .legend(move |p| mk.at(p, color, true));
                chart.draw_series(pts.into_iter().map(|p| mk.at(p, color, false))).map_err(msg)?;
            }
        }
    }
    for (j, r) in spec.refs.iter().enumerate() {
        let color = palette(spec.series.len() + j);
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

/// The caption's font size: 26 px, smaller when the title would not fit `width` px (a
/// character of sans-serif is at most about 0.58 of the size wide).
fn caption_px(title: &str, width: u32) -> f64 {
    let chars = title.chars().count().max(1) as f64;
    (f64::from(width.saturating_sub(40)) / (0.58 * chars)).clamp(12.0, 26.0)
}

/// `label` in lines of at most `width` characters, broken between words.
fn wrap(label: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = vec![String::new()];
    for word in label.split_whitespace() {
        let last = lines.last_mut().expect("one line");
        if !last.is_empty() && last.chars().count() + 1 + word.chars().count() > width {
            lines.push(word.to_string());
        } else {
            last.push_str(if last.is_empty() { "" } else { " " });
            last.push_str(word);
        }
    }
    lines
}

/// The legend of `spec` as a column in `area` (right of the plot): one row per labelled series
/// and reference line, in the colours and styles [`draw_lines`] gives them.
fn draw_legend_column(area: &Area<'_>, spec: &PlotSpec) -> std::result::Result<(), String> {
    // 13 px: a 42-character variant id fits the column.
    let font = ("sans-serif", 13).into_font();
    let mut y = 80;
    // `dashed` without `dot` draws a dashed line; with `dot`, the marker alone (a point series).
    let mut row =
        |label: &str, color: RGBColor, dashed: bool, dot: Option<Marker>| -> std::result::Result<(), String> {
            if label.is_empty() {
                return Ok(());
            }
            let style = color.stroke_width(2);
            match (dashed, dot.is_some()) {
                (true, true) => {}
                (true, false) => area
                    .draw(&DashedPathElement::new(vec![(10, y), (40, y)], 5, 3, style))
                    .map_err(|e| e.to_string())?,
                _ => area.draw(&PathElement::new(vec![(10, y), (40, y)], style)).map_err(|e| e.to_string())?,
            }
            if let Some(mk) = dot {
                area.draw(&mk.at((25, y), color, false)).map_err(|e| e.to_string())?;
            }
            // 13 px text in the column's 282 px after the sample: 40 characters a line.
            for (k, line) in wrap(label, 40).into_iter().enumerate() {
                if k > 0 {
                    y += 16;
                }
                area.draw(&Text::new(line, (48, y - 8), font.clone())).map_err(|e| e.to_string())?;
            }
            y += 24;
            Ok(())
        };
    for (k, s) in spec.series.iter().enumerate() {
        row(&s.label, s.colour(k), s.style == Style::Points, (s.style != Style::Line).then_some(s.marker))?;
    }
    for (j, r) in spec.refs.iter().enumerate() {
        row(&r.label, palette(spec.series.len() + j), true, None)?;
    }
    Ok(())
}

/// The note of `spec`: above the legend column (wrapped to its width, at most three lines), or
/// at the bottom left of a plot without one.
fn draw_note(root: &Area<'_>, spec: &PlotSpec) -> std::result::Result<(), String> {
    if spec.note.is_empty() {
        return Ok(());
    }
    let font = ("sans-serif", 14).into_font().color(&RGBColor(80, 80, 80));
    if !spec.legend_outside {
        let at = (10, PLOT_SIZE.1 as i32 - 18);
        return root.draw(&Text::new(spec.note.clone(), at, font)).map_err(msg);
    }
    let lines = wrap(&spec.note, 37);
    for (k, l) in lines.iter().take(3).enumerate() {
        let at = (PLOT_SIZE.0 as i32 - LEGEND_WIDTH + 10, 10 + 18 * k as i32);
        root.draw(&Text::new(l.clone(), at, font.clone())).map_err(msg)?;
    }
    Ok(())
}

/// Would the legend drawn over the plot's upper right (plotters' box: 15 px text, a 24 px row per
/// entry, the label after a 40 px sample) cover anything drawn, given the axis ranges `xr`, `yr`?
/// Each series is checked at its points and along its line segments, and each reference line
/// where it runs; the box is estimated in pixels of the plot area of [`draw_lines`] (margin 20,
/// caption ≈ 40, axis label areas 56 and 84 px).
fn legend_covers_data(spec: &PlotSpec, xr: (f64, f64), yr: (f64, f64)) -> bool {
    let labels: Vec<&str> = spec
        .series
        .iter()
        .map(|s| s.label.as_str())
        .chain(spec.refs.iter().map(|r| r.label.as_str()))
        .filter(|l| !l.is_empty())
        .collect();
    if labels.is_empty() {
        return false;
    }
    let (w_px, h_px) = (PLOT_SIZE.0 as f64 - 20.0 - 20.0 - 84.0, PLOT_SIZE.1 as f64 - 20.0 - 40.0 - 20.0 - 56.0);
    let chars = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64;
    // 8.5 px per character of 15 px sans-serif (a safe upper side), the box's padding and margin.
    let box_w = (chars * 8.5 + 40.0 + 30.0) / w_px;
    let box_h = (labels.len() as f64 * 24.0 + 30.0) / h_px;
    let frac = |v: f64, r: (f64, f64), log: bool| {
        if log {
            (v.log10() - r.0.log10()) / (r.1.log10() - r.0.log10())
        } else {
            (v - r.0) / (r.1 - r.0)
        }
    };
    let covered = |x: f64, y: f64| {
        drawable(x, spec.log_x)
            && drawable(y, spec.log_y)
            && frac(x, xr, spec.log_x) >= 1.0 - box_w
            && frac(y, yr, spec.log_y) >= 1.0 - box_h
            && (xr.0..=xr.1).contains(&x)
            && (yr.0..=yr.1).contains(&y)
    };
    let series = spec.series.iter().any(|s| {
        s.points.iter().any(|&(x, y)| covered(x, y))
            || (s.style != Style::Points
                && s.points.windows(2).any(|w| {
                    (1..8).any(|k| {
                        let t = f64::from(k) / 8.0;
                        covered(w[0].0 + t * (w[1].0 - w[0].0), w[0].1 + t * (w[1].1 - w[0].1))
                    })
                }))
    });
    let refs = spec.refs.iter().any(|r| {
        let at = if r.horizontal {
            frac(r.value, yr, spec.log_y) >= 1.0 - box_h
        } else {
            frac(r.value, xr, spec.log_x) >= 1.0 - box_w
        };
        at && drawable(r.value, if r.horizontal { spec.log_y } else { spec.log_x })
    });
    series || refs
}

/// Draws `spec` into the SVG file `path` (parent directory created if missing); the legend goes
/// in a column beside the plot when asked, or when over the plot it would cover a curve.
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

    let outside = spec.legend_outside || legend_covers_data(spec, xr, yr);
    let placed;
    let spec = if outside && !spec.legend_outside {
        placed = PlotSpec { legend_outside: true, ..spec.clone() };
        &placed
    } else {
        spec
    };
    let root = svg_area(path)?;
    let (plot, legend) = if spec.legend_outside {
        let (p, l) = root.split_horizontally(PLOT_SIZE.0 as i32 - LEGEND_WIDTH);
        (p, Some(l))
    } else {
        (root.clone(), None)
    };
    let lin = |r: (f64, f64)| RangedCoordf64::from(r.0..r.1);
    let log = log_axis;
    let l = legend.as_ref();
    let drawn = match (spec.log_x, spec.log_y) {
        (false, false) => draw_lines(&plot, l, spec, lin(xr), lin(yr), xr, yr),
        (true, false) => draw_lines(&plot, l, spec, log(xr), lin(yr), xr, yr),
        (false, true) => draw_lines(&plot, l, spec, lin(xr), log(yr), xr, yr),
        (true, true) => draw_lines(&plot, l, spec, log(xr), log(yr), xr, yr),
    };
    drawn.map_err(|m| OutputError::plot(path, m))?;
    draw_note(&root, spec).map_err(|m| OutputError::plot(path, m))?;
    root.present().map_err(|e| OutputError::plot(path, msg(e)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::{RefLine, Series};

    fn spec(points: Vec<(f64, f64)>) -> PlotSpec {
        let mut s = PlotSpec::new("t", "x", "y");
        s.series.push(Series::line("a curve", points));
        s
    }

    #[test]
    fn the_legend_leaves_the_plot_only_when_it_would_cover_a_curve() {
        let (xr, yr) = ((0.0, 1.0), (0.0, 1.0));
        // A curve along the bottom leaves the upper right free.
        assert!(!legend_covers_data(&spec(vec![(0.0, 0.0), (1.0, 0.1)]), xr, yr));
        // One through the upper right corner does not, nor does a segment crossing it between
        // two points outside it.
        assert!(legend_covers_data(&spec(vec![(0.0, 0.0), (0.97, 0.97)]), xr, yr));
        assert!(legend_covers_data(&spec(vec![(0.8, 1.0), (1.0, 0.8)]), xr, yr));
        // Points alone are checked at the points only.
        let mut p = spec(vec![(0.8, 1.0), (1.0, 0.8)]);
        p.series[0] = Series::points("points", p.series[0].points.clone());
        assert!(!legend_covers_data(&p, xr, yr));
        // A horizontal reference line at the top, and a log axis read in decades.
        let mut r = spec(vec![(0.0, 0.0)]);
        r.refs.push(RefLine::horizontal("top", 0.99));
        assert!(legend_covers_data(&r, xr, yr));
        let mut l = spec(vec![(1.0, 1.0), (1000.0, 900.0)]);
        (l.log_x, l.log_y) = (true, true);
        assert!(legend_covers_data(&l, (1.0, 1000.0), (1.0, 1000.0)));
        assert!(!legend_covers_data(&l, (1.0, 1e6), (1.0, 1e6)), "the curve ends half-way in decades");
    }

    #[test]
    fn long_titles_shrink_and_long_labels_wrap() {
        assert_eq!(caption_px("short", 694), 26.0);
        let long = "Relaxation 90° → 60°: spread factor D/D0 at the first row (Fig. 4.13)";
        let px = caption_px(long, 694);
        assert!(px < 26.0 && px * 0.58 * long.chars().count() as f64 <= 654.0 + 1e-9, "{px}");
        let lines = wrap("sphlab: field on all particles, quintic h = 1.2Δx, p_b by the capillary rule (default)", 40);
        assert!(lines.len() == 3 && lines.iter().all(|l| l.chars().count() <= 40), "{lines:?}");
        assert_eq!(
            lines.join(" "),
            "sphlab: field on all particles, quintic h = 1.2Δx, p_b by the capillary rule (default)"
        );
    }
}
