//! The stability map of one backend/precision as an SVG: one row per case, one column per dt
//! factor; a cell is green (stable over the steps), red (unstable, with the step it failed at)
//! or grey (not measured).

use super::Record;
use plotters::prelude::*;
use std::path::Path;

const GREEN: RGBColor = RGBColor(120, 200, 120);
const RED: RGBColor = RGBColor(220, 90, 80);
const GREY: RGBColor = RGBColor(210, 210, 210);

/// Draws the map of `records` (one target) over `cases` × `factors`.
pub fn write_svg(
    path: &Path,
    title: &str,
    cases: &[String],
    factors: &[f64],
    records: &[&Record],
) -> Result<(), String> {
    let (left, top, cw, ch) = (230i32, 70i32, 110i32, 34i32);
    let w = (left + cw * factors.len() as i32 + 20) as u32;
    let h = (top + ch * cases.len() as i32 + 60) as u32;
    let root = SVGBackend::new(path, (w.max(480), h)).into_drawing_area();
    let e = |e: DrawingAreaErrorKind<_>| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(e)?;
    let font = |s: i32| ("sans-serif", s).into_font();
    root.draw(&Text::new(title.to_string(), (10, 10), font(18))).map_err(e)?;
    root.draw(&Text::new("dt / tightest limit at load →".to_string(), (left, top - 40), font(14))).map_err(e)?;
    for (j, f) in factors.iter().enumerate() {
        root.draw(&Text::new(format!("{f}×"), (left + cw * j as i32 + cw / 3, top - 20), font(14))).map_err(e)?;
    }
    for (i, c) in cases.iter().enumerate() {
        let y = top + ch * i as i32;
        root.draw(&Text::new(c.clone(), (10, y + ch / 3), font(14))).map_err(e)?;
        for (j, f) in factors.iter().enumerate() {
            let x = left + cw * j as i32;
            let r = records.iter().find(|r| &r.case == c && r.dt_factor == *f);
            let (colour, label) = match r {
                Some(r) if r.stable => (GREEN, "stable".to_string()),
                Some(r) => (RED, format!("step {}", r.fail_step.unwrap_or(0))),
                None => (GREY, "—".to_string()),
            };
            root.draw(&Rectangle::new([(x + 1, y + 1), (x + cw - 1, y + ch - 1)], colour.filled())).map_err(e)?;
            root.draw(&Text::new(label, (x + 8, y + ch / 3), font(13))).map_err(e)?;
        }
    }
    let note = "green: stable over the steps · red: unstable (step) · grey: not measured";
    root.draw(&Text::new(note.to_string(), (10, top + ch * cases.len() as i32 + 20), font(13))).map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}
