//! The study's overview plots (docs/STUDY.md §5): the scaling overview (the leading backend of
//! each family against N, one plot), the roofline of the E4 size (pair interactions per second
//! against pair interactions per modelled byte, under the memory roof this run measured), and the
//! per-stage stacked bars of each GPU variant family (the stage-timed, unfused block). Only `ok`
//! records are drawn; each id in its colour and marker ([`super::look`]).

use super::look;
use super::Record;
use crate::plot::{line_plot_svg, palette, PlotSpec, Series};
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// The family of a backend id: `cpu1`, `cpu` or the GPU variant's search and mapping.
pub(super) fn family(id: &str) -> String {
    let p: Vec<&str> = id.split('.').collect();
    match p[0] {
        "cpu1" | "cpu" => p[0].to_string(),
        _ => p.iter().take(2).copied().collect::<Vec<_>>().join("."),
    }
}

/// The fastest `ok` record of each key at the largest N where that key has one.
fn leaders<'a>(rows: &[&'a Record], key: impl Fn(&Record) -> String) -> BTreeMap<String, &'a Record> {
    let mut best: BTreeMap<String, &Record> = BTreeMap::new();
    for r in rows {
        let k = key(r);
        let better = best.get(&k).is_none_or(|b| r.n > b.n || (r.n == b.n && r.ms() < b.ms()));
        if better {
            best.insert(k, r);
        }
    }
    best
}

/// `scaling_overview.svg`: per family (one-thread CPU, all-cores CPU, each GPU search) the id
/// fastest at its largest N, drawn at every N.
fn scaling_overview(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    let ok: Vec<&Record> = recs.iter().filter(|r| r.experiment == "scaling" && r.is_ok()).collect();
    let by_search = |r: &Record| {
        if r.backend == "gpu" {
            r.variant.split('.').next().unwrap_or("").into()
        } else {
            family(&r.variant)
        }
    };
    let several = look::several_machines(&ok);
    let lead = leaders(&ok, |r| look::label_at(&by_search(r), r, several));
    if lead.len() < 2 {
        return Ok(());
    }
    let mut spec =
        PlotSpec::new("Scaling overview — the leading backend of each family", "particles N", "time per step (ms)");
    (spec.log_x, spec.log_y, spec.legend_outside) = (true, true, true);
    spec.note = look::adapter_note(recs);
    for r in lead.values() {
        let mut pts: Vec<(f64, f64)> = ok
            .iter()
            .filter(|q| q.variant == r.variant && (!several || look::machine(q) == look::machine(r)))
            .map(|q| (q.n as f64, q.ms()))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let label = look::label_at(&r.variant, r, several);
        spec.series.push(look::styled(Series::line_points(label, pts), &r.variant));
    }
    let p = dir.join("scaling_overview.svg");
    line_plot_svg(&p, &spec).map_err(|x| format!("{}: {x}", p.display()))?;
    let _ = writeln!(
        md,
        "![scaling overview](scaling_overview.svg)\n\nEach family (one-thread CPU, all-cores CPU, GPU by search) by its \
         fastest `ok` id at its largest N; one line per machine when the records come from several.\n"
    );
    Ok(())
}

/// `roofline.svg`: the fastest `ok` variant of each GPU family at the largest E4 size, as pair
/// interactions per second against pair interactions per modelled byte, with the memory roof
/// (the run's measured bandwidth × intensity).
fn roofline(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    let rows: Vec<&Record> = recs
        .iter()
        .filter(|r| r.experiment == "e4" && r.backend == "gpu" && r.is_ok())
        .filter(|r| r.achieved_gb_s.is_some() && r.pair_interactions_per_s.is_some())
        .collect();
    let Some(n) = rows.iter().map(|r| r.n).max() else { return Ok(()) };
    let at_n: Vec<&Record> = rows.into_iter().filter(|r| r.n == n).collect();
    let lead = leaders(&at_n, |r| family(&r.variant));
    let point = |r: &Record| -> Option<(f64, f64)> {
        let perf = r.pair_interactions_per_s?;
        Some((perf / (r.achieved_gb_s? * 1e9), perf))
    };
    let pts: Vec<(&Record, (f64, f64))> = lead.values().filter_map(|r| Some((*r, point(r)?))).collect();
    let Some(bw) = pts.iter().find_map(|(r, _)| r.bandwidth_gb_s) else { return Ok(()) };
    let (lo, hi) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), (_, p)| (a.min(p.0), b.max(p.0)));
    let mut spec = PlotSpec::new(
        format!("Roofline, E4 at N = {n}: each GPU family's fastest"),
        "pair interactions per modelled byte",
        "pair interactions per second",
    );
    (spec.log_x, spec.log_y, spec.legend_outside) = (true, true, true);
    spec.note = look::adapter_note(recs);
    let roof: Vec<(f64, f64)> = [lo / 3.0, hi * 3.0].iter().map(|&x| (x, bw * 1e9 * x)).collect();
    spec.series.push(Series::line(format!("memory roof: {bw:.1} GB/s measured"), roof).with_colour((0, 0, 0)));
    for (r, p) in &pts {
        spec.series.push(look::styled(Series::points(r.variant.clone(), vec![*p]), &r.variant));
    }
    let p = dir.join("roofline.svg");
    line_plot_svg(&p, &spec).map_err(|x| format!("{}: {x}", p.display()))?;
    let _ = writeln!(
        md,
        "![roofline](roofline.svg)\n\nBytes are the modelled compulsory traffic (a lower bound), so a point's distance \
         below the roof is an upper bound of the bandwidth it leaves unused; no compute roof is drawn (none is measured).\n"
    );
    Ok(())
}

/// `stages_stacked.svg`: per GPU family at the largest E4 size, the mean device ms per step of
/// each stage in the stage-timed block (every stage its own pass), stacked.
fn stage_bars(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    let rows: Vec<&Record> = recs
        .iter()
        .filter(|r| r.experiment == "e4" && r.backend == "gpu" && r.is_ok() && !r.stage_ms.is_empty())
        .collect();
    let Some(n) = rows.iter().map(|r| r.n).max() else { return Ok(()) };
    let mut fams: BTreeMap<String, Vec<&Record>> = BTreeMap::new();
    for r in rows.into_iter().filter(|r| r.n == n) {
        fams.entry(family(&r.variant)).or_default().push(r);
    }
    let mut stages: Vec<String> = Vec::new();
    for r in fams.values().flatten() {
        for (s, _) in &r.stage_ms {
            if !stages.contains(s) {
                stages.push(s.clone());
            }
        }
    }
    let mean = |v: &[&Record], s: &str| {
        v.iter().map(|r| r.stage_ms.iter().find(|x| x.0 == s).map_or(0.0, |x| x.1)).sum::<f64>() / v.len() as f64
    };
    let cats: Vec<String> = fams.keys().cloned().collect();
    let stacks: Vec<Vec<f64>> = fams.values().map(|v| stages.iter().map(|s| mean(v, s)).collect()).collect();
    let top = stacks.iter().map(|v| v.iter().sum::<f64>()).fold(0.0f64, f64::max).max(1e-9);
    let p = dir.join("stages_stacked.svg");
    let title = format!("Device time per stage, mean over each family's variants (E4, N = {n}, unfused)");
    let drawn = draw_stacks(&p, &title, &cats, &stages, &stacks, top, &look::adapter_note(recs));
    drawn.map_err(|x| format!("{}: {x}", p.display()))?;
    let _ = writeln!(md, "![device time per stage](stages_stacked.svg)\n");
    Ok(())
}

/// Draws stacked bars: one bar per category, one segment per stage, the legend in a column
/// right of the plot, `note` at the bottom left.
fn draw_stacks(
    path: &Path,
    title: &str,
    cats: &[String],
    stages: &[String],
    stacks: &[Vec<f64>],
    top: f64,
    note: &str,
) -> Result<(), String> {
    let m = |e: &dyn std::fmt::Debug| format!("{e:?}");
    let root = SVGBackend::new(path, crate::plot::PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| m(&e))?;
    let (plot, legend) = root.split_horizontally(crate::plot::PLOT_SIZE.0 - 260);
    let nc = cats.len().max(1) as f64;
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, ("sans-serif", 18))
        .margin(16)
        .x_label_area_size(90)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..nc, 0.0..top * 1.08)
        .map_err(|e| m(&e))?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_label_formatter(&|_| String::new())
        .y_label_formatter(&|y| crate::plot::fmt_tick(*y))
        .y_desc("device ms per step")
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| m(&e))?;
    let colour = palette;
    for (i, stack) in stacks.iter().enumerate() {
        let mut y = 0.0;
        for (j, v) in stack.iter().enumerate().filter(|(_, v)| **v > 0.0) {
            let x = i as f64;
            chart
                .draw_series([Rectangle::new([(x + 0.2, y), (x + 0.8, y + v)], colour(j).filled())])
                .map_err(|e| m(&e))?;
            y += v;
        }
    }
    // Category labels in two lines (search, then mapping) under each bar.
    let small = ("sans-serif", 13).into_font();
    for (i, c) in cats.iter().enumerate() {
        let (x, y) = chart.backend_coord(&(i as f64 + 0.5, 0.0));
        for (k, part) in c.splitn(2, '.').enumerate() {
            let w = 7 * part.chars().count() as i32 / 2;
            plot.draw(&Text::new(part.to_string(), (x - w, y + 10 + 16 * k as i32), small.clone()))
                .map_err(|e| m(&e))?;
        }
    }
    let font = ("sans-serif", 14).into_font();
    for (j, s) in stages.iter().enumerate() {
        let y = 60 + 24 * j as i32;
        legend.draw(&Rectangle::new([(10, y - 6), (26, y + 6)], colour(j).filled())).map_err(|e| m(&e))?;
        legend.draw(&Text::new(s.clone(), (34, y - 8), font.clone())).map_err(|e| m(&e))?;
    }
    let grey = ("sans-serif", 12).into_font().color(&RGBColor(80, 80, 80));
    root.draw(&Text::new(note.to_string(), (8, crate::plot::PLOT_SIZE.1 as i32 - 16), grey)).map_err(|e| m(&e))?;
    root.present().map_err(|e| m(&e))
}

/// Every overview plot of `recs` into `dir`, each with its line in `md`.
pub fn write(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    scaling_overview(dir, recs, md)?;
    roofline(dir, recs, md)?;
    stage_bars(dir, recs, md)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(experiment: &str, variant: &str, n: usize, ms: f64) -> Record {
        let gpu = !variant.starts_with("cpu");
        let (bytes, evals) = (4.0e3 * n as f64, 2.0 * n as f64);
        Record {
            experiment: experiment.into(),
            variant: variant.into(),
            backend: if gpu { "gpu" } else { "cpu" }.into(),
            n,
            status: "ok".into(),
            ms_per_step_median: Some(ms),
            pair_interactions_per_s: Some(evals * 36.0 / (ms * 1e-3)),
            achieved_gb_s: gpu.then(|| bytes / (ms * 1e-3) * 1e-9),
            bandwidth_gb_s: gpu.then_some(2.5),
            stage_ms: if gpu {
                vec![("number_density".into(), 0.4 * ms), ("acceleration".into(), 0.6 * ms)]
            } else {
                vec![]
            },
            ..Default::default()
        }
    }

    #[test]
    fn overview_plots_draw_the_leaders_the_roof_and_every_family() {
        let mut recs = Vec::new();
        for (n, k) in [(1000, 1.0), (4000, 4.0)] {
            recs.push(rec("scaling", "cpu1.cells.f64", n, 10.0 * k));
            recs.push(rec("scaling", "cpu1.tracking.f64", n, 8.0 * k));
            recs.push(rec("scaling", "cells.thread.recomputed.f32", n, 30.0 * k));
            recs.push(rec("scaling", "cells.subgroup.recomputed.f32", n, 20.0 * k));
        }
        recs.push(rec("e4", "cells.thread.recomputed.f32", 4000, 120.0));
        recs.push(rec("e4", "cells.thread.cached.f32", 4000, 100.0));
        recs.push(rec("e4", "tracking.block-tree.fixed.cached.f32", 4000, 90.0));
        recs.push(Record { status: "inaccurate".into(), ..rec("e4", "direct.thread.recomputed.f32", 4000, 1.0) });
        let dir = tempfile::tempdir().expect("tempdir");
        let mut md = String::new();
        write(dir.path(), &recs, &mut md).expect("plots");
        let read = |f: &str| std::fs::read_to_string(dir.path().join(f)).expect(f);
        let scaling = read("scaling_overview.svg");
        // Leaders: cpu1 by tracking (faster), GPU cells by subgroup (faster at the largest N).
        assert!(scaling.contains("cpu1.tracking.f64") && !scaling.contains("cpu1.cells.f64"));
        assert!(scaling.contains("cells.subgroup.recomputed.f32") && !scaling.contains("cells.thread.recomputed"));
        let roof = read("roofline.svg");
        assert!(roof.contains("memory roof: 2.5 GB/s measured"));
        assert!(roof.contains("cells.thread.cached.f32") && !roof.contains("cells.thread.recomputed.f32"));
        assert!(!roof.contains("direct.thread"), "an inaccurate record is never drawn");
        let bars = read("stages_stacked.svg");
        assert!(bars.contains("block-tree") && bars.contains("acceleration"));
        assert!(md.contains("roofline.svg") && md.contains("stages_stacked.svg"));
    }
}
