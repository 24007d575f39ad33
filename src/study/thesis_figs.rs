//! The study's figures drawn like the thesis's Figs. 6.3 (E1: search × backend), 6.8 (E2:
//! residency) and 6.9 (E3: subdomain budgets), with what the thesis states beside sphlab's
//! values, and the E2/E3 tables of `summary.md`. The thesis's figures survive only as captions
//! in the thesis text; the numbers its text gives are [`THESIS`], each with the line of the
//! thesis text it comes from. SVG via plotters, as `crate::plot`.

use super::Record;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// What the thesis's text states about Figs. 6.3, 6.8 and 6.9: (figure, statement, seed line).
pub const THESIS: [(&str, &str, u32); 5] = [
    (
        "6.3",
        "caption only: runtime of direct search and NNPS, CPU and GPU, 2,025 particles (no values in the text)",
        380,
    ),
    ("6.8", "caption only: runtime falls as more routines are compiled for the GPU, 2,025 particles (no values)", 400),
    ("6.9", "no atomics (∆) takes ~17 % less time than the atomic versions: t(∆)/t(atomic) ≈ 0.83", 3762),
    ("6.9", "∆ and □ runtimes stop falling at a constant rate around 4,500 particles per subdomain", 3800),
    ("6.9", "○ (cached) caps the subdomain size: more ghosts, more transfers, lower GPU load", 3788),
];

/// The thesis's ratio t(∆) / t(atomic configurations) (seed line 3762: "~17% reduction").
pub const THESIS_NO_ATOMICS_RATIO: f64 = 0.83;
/// Particles per subdomain where the thesis's ∆ and □ curves bend (seed line 3800).
pub const THESIS_KINK_BUDGET: f64 = 4500.0;

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

fn m<E: std::fmt::Debug>(e: E) -> String {
    format!("{e:?}")
}

/// Grouped bars: one group per category, one bar per series; `log`: log10 y (bars from the
/// lowest decade).
fn bars(
    area: &Area,
    title: &str,
    y_label: &str,
    cats: &[String],
    series: &[(String, Vec<f64>)],
    log: bool,
) -> Result<(), String> {
    let tf = |v: f64| if log { v.max(1e-300).log10() } else { v };
    let vals: Vec<f64> =
        series.iter().flat_map(|s| s.1.iter().copied()).filter(|v| v.is_finite() && (!log || *v > 0.0)).collect();
    let (lo, hi) = vals.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(tf(*v)), b.max(tf(*v))));
    let (y0, y1) = if lo > hi {
        (0.0, 1.0)
    } else if log {
        (lo.floor(), hi.ceil().max(lo.floor() + 1.0))
    } else {
        (0.0, hi * 1.15 + 1e-300)
    };
    let nc = cats.len().max(1) as f64;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..nc, y0..y1)
        .map_err(m)?;
    let cats_c = cats.to_vec();
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(cats.len() * 2 + 1)
        .x_label_formatter(&|x| {
            let k = x.floor() as usize;
            if (x - x.floor() - 0.5).abs() < 0.26 && k < cats_c.len() {
                cats_c[k].clone()
            } else {
                String::new()
            }
        })
        // A log axis is labelled at its decades only.
        .y_label_formatter(&|y| match (log, (y - y.round()).abs() < 1e-6) {
            (true, true) => crate::plot::fmt_tick(10f64.powi(y.round() as i32)),
            (true, false) => String::new(),
            (false, _) => crate::plot::fmt_tick(*y),
        })
        .y_desc(y_label)
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(m)?;
    let ns = series.len().max(1) as f64;
    let w = 0.8 / ns;
    for (k, (label, v)) in series.iter().enumerate() {
        let c = PALETTE[k % PALETTE.len()];
        let rects: Vec<Rectangle<(f64, f64)>> = v
            .iter()
            .enumerate()
            .filter(|(_, y)| y.is_finite() && (!log || **y > 0.0))
            .map(|(i, y)| {
                let x = i as f64 + 0.1 + w * k as f64;
                Rectangle::new([(x, y0), (x + w * 0.92, tf(*y))], c.filled())
            })
            .collect();
        chart
            .draw_series(rects)
            .map_err(m)?
            .label(label.clone())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], c.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(m)
}

/// Lines with markers against x, dashed horizontal references (`hrefs`, coloured like the
/// series of the same index) and an optional dashed vertical reference.
#[allow(
    clippy::too_many_arguments,
    reason = "a figure's data, axes, labels and the thesis's values are named at every call"
)]
fn lines(
    area: &Area,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(String, Vec<(f64, f64)>)],
    hrefs: &[(String, usize, f64)],
    vref: Option<(&str, f64)>,
) -> Result<(), String> {
    let pts: Vec<(f64, f64)> =
        series.iter().flat_map(|s| s.1.iter().copied()).filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
    let xs = pts.iter().map(|p| p.0).chain(vref.map(|v| v.1));
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    let ys = pts.iter().map(|p| p.1).chain(hrefs.iter().map(|h| h.2).filter(|v| v.is_finite()));
    let y1 = ys.fold(0.0f64, f64::max);
    let (x0, x1) = if x0 < x1 { (x0 - 0.05 * (x1 - x0), x1 + 0.05 * (x1 - x0)) } else { (0.0, 1.0) };
    // Headroom above the data for the legend (upper right), so that it never covers a curve.
    let y1 = if y1 > 0.0 { y1 * 1.45 } else { 1.0 };
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, 0.0..y1)
        .map_err(m)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| crate::plot::fmt_tick(*v))
        .y_label_formatter(&|v| crate::plot::fmt_tick(*v))
        .label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(m)?;
    for (k, (label, p)) in series.iter().enumerate() {
        let c = PALETTE[k % PALETTE.len()];
        let p: Vec<(f64, f64)> = p.iter().copied().filter(|q| q.0.is_finite() && q.1.is_finite()).collect();
        // The thesis's ○ ∆ □ where a label starts with one (Fig. 6.9), else circles.
        let mk = super::look::thesis_marker(label);
        chart
            .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))
            .map_err(m)?
            .label(label.clone())
            .legend(move |(x, y)| mk.at((x + 9, y), c, true));
        chart.draw_series(p.iter().map(|q| mk.at(*q, c, false))).map_err(m)?;
    }
    for (label, k, v) in hrefs.iter().filter(|h| h.2.is_finite()) {
        let c = PALETTE[k % PALETTE.len()];
        chart
            .draw_series(std::iter::once(DashedPathElement::new(vec![(x0, *v), (x1, *v)], 6, 4, c.stroke_width(1))))
            .map_err(m)?
            .label(label.clone())
            .legend(move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 18, y)], 4, 3, c.stroke_width(1)));
    }
    if let Some((label, v)) = vref {
        chart
            .draw_series(std::iter::once(DashedPathElement::new(vec![(v, 0.0), (v, y1)], 6, 4, BLACK.stroke_width(1))))
            .map_err(m)?
            .label(label.to_string())
            .legend(|(x, y)| DashedPathElement::new(vec![(x, y), (x + 18, y)], 4, 3, BLACK.stroke_width(1)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 11))
        .draw()
        .map_err(m)
}

/// A figure of `size` at `path`, drawn by `draw`, with `note` (the adapter) at its bottom left.
fn svg(
    path: &Path,
    size: (u32, u32),
    note: &str,
    draw: impl FnOnce(&Area) -> Result<(), String>,
) -> Result<(), String> {
    let p = path.display().to_string();
    let root = SVGBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| format!("{p}: {e:?}"))?;
    draw(&root).map_err(|e| format!("{p}: {e}"))?;
    let font = ("sans-serif", 12).into_font().color(&RGBColor(80, 80, 80));
    root.draw(&Text::new(note.to_string(), (8, size.1 as i32 - 16), font)).map_err(|e| format!("{p}: {e:?}"))?;
    root.present().map_err(|e| format!("{p}: {e:?}"))
}

/// The records of `experiment` (ok ones only with `ok_only`) from one run: the run of its first
/// GPU record, else of its first record. A merged report holds several machines' runs, and one
/// figure's bars compare one machine's backends.
fn one_run<'a>(recs: &'a [Record], experiment: &str, ok_only: bool) -> Vec<&'a Record> {
    let of: Vec<&Record> = recs.iter().filter(|r| r.experiment == experiment && (!ok_only || r.is_ok())).collect();
    let Some(run) = of.iter().find(|r| r.backend == "gpu").or(of.first()).map(|r| r.run.clone()) else {
        return of;
    };
    of.into_iter().filter(|r| r.run == run).collect()
}

/// Fig. 6.3 from the E1 rows of one run: ms/step of each search on one CPU thread and on the GPU (log).
fn fig_6_3(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    let e1 = one_run(recs, "e1", true);
    if e1.is_empty() {
        return Ok(());
    }
    let drawn: Vec<Record> = e1.iter().map(|r| (*r).clone()).collect();
    let cats: Vec<String> = ["direct", "cells", "tracking"].iter().map(|s| s.to_string()).collect();
    let get = |backend: &str, search: &str| {
        e1.iter()
            .find(|r| {
                r.backend == backend
                    && (backend == "gpu" || r.precision == "f64")
                    && r.variant.split('.').nth(if backend == "gpu" { 0 } else { 1 }) == Some(search)
            })
            .map_or(f64::NAN, |r| r.ms())
    };
    let series = vec![
        ("CPU, one thread (f64)".to_string(), cats.iter().map(|c| get("cpu1", c)).collect::<Vec<_>>()),
        (
            format!("GPU ({})", e1.iter().find(|r| r.backend == "gpu").map_or("-", |r| r.adapter.as_str())),
            cats.iter().map(|c| get("gpu", c)).collect(),
        ),
    ];
    svg(&dir.join("fig6_3_search.svg"), (900, 560), &super::look::adapter_note(&drawn), |a| {
        bars(
            a,
            "Fig. 6.3 — neighbour search on CPU and GPU (2,025 fluid particles)",
            "time per step (ms, log)",
            &cats,
            &series,
            true,
        )
    })?;
    let _ = writeln!(md, "![Fig. 6.3](fig6_3_search.svg)\n");
    Ok(())
}

/// The E2 table of one run's hybrids, with the speedup against that run's `cpu-all`.
fn e2_table(md: &mut String, e2: &[&&Record]) {
    let _ = writeln!(md, "| hybrid | on the CPU | ms/step (median) | p10 | p90 | H→D B/step | D→H B/step | speedup vs `cpu-all` | verified |\n|---|---|---|---|---|---|---|---|---|");
    let cpu_all = e2.iter().find(|r| r.variant == "hybrid.cpu-all").map(|r| r.ms());
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.0}"));
    for r in e2 {
        let sp = cpu_all.map_or("-".into(), |b| format!("{:.2}×", b / r.ms()));
        let _ = writeln!(
            md,
            "| `{}` | {} | {:.3} | {:.3} | {:.3} | {} | {} | {} | {} |",
            r.variant,
            r.residency_cpu,
            r.ms(),
            r.ms_per_step_p10.unwrap_or(f64::NAN),
            r.ms_per_step_p90.unwrap_or(f64::NAN),
            opt(r.bytes_h2d_per_step),
            opt(r.bytes_d2h_per_step),
            sp,
            r.verified
        );
    }
    let _ = writeln!(md);
}

/// Fig. 6.8 from the E2 rows: ms/step and bytes copied per step of each hybrid (the figure one
/// run's, the tables every run's).
fn fig_6_8(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    let e2 = one_run(recs, "e2", false);
    if e2.is_empty() {
        return Ok(());
    }
    let drawn: Vec<Record> = e2.iter().map(|r| (*r).clone()).collect();
    let _ = writeln!(
        md,
        "## E2 — residency: stage groups moved to the GPU one at a time (Fig. 6.8; {} fluid particles)\n",
        e2[0].n_fluid
    );
    let _ = writeln!(md, "GPU variant `{}`; CPU stages on one thread in f32 (the reference's own stage functions). Bytes are counted at the copy calls (host → device / device → host), per step, over the timed steps; every step ends with a device sync. Verified after {} steps against the CPU f32 reference with the tolerance table of `sphlab verify`.\n", e2[0].config, super::e23::E23Options::default().verify_steps);
    // One table per run, each hybrid against its own run's `cpu-all` (a merged report holds
    // several machines); the figure draws the first.
    let all: Vec<&Record> = recs.iter().filter(|r| r.experiment == "e2").collect();
    let mut runs: Vec<&str> = Vec::new();
    for r in &all {
        if !runs.contains(&r.run.as_str()) {
            runs.push(&r.run);
        }
    }
    for run in &runs {
        let rows: Vec<&&Record> = all.iter().filter(|r| r.run == *run).collect();
        if runs.len() > 1 {
            let _ = writeln!(md, "Run `{run}` ({}):\n", super::look::machine(rows[0]));
        }
        e2_table(md, &rows);
    }
    let cats: Vec<String> = e2
        .iter()
        .map(|r| r.variant.trim_start_matches("hybrid.").replace("-surface-forces", "-s-f").to_string())
        .collect();
    let t = vec![("time per step".to_string(), e2.iter().map(|r| r.ms()).collect::<Vec<_>>())];
    let b = vec![
        (
            "host → device".to_string(),
            e2.iter().map(|r| r.bytes_h2d_per_step.unwrap_or(f64::NAN) / 1024.0).collect::<Vec<_>>(),
        ),
        ("device → host".to_string(), e2.iter().map(|r| r.bytes_d2h_per_step.unwrap_or(f64::NAN) / 1024.0).collect()),
    ];
    svg(&dir.join("fig6_8_residency.svg"), (1100, 820), &super::look::adapter_note(&drawn), |a| {
        let (top, bottom) = a.split_vertically(410);
        let title = "Fig. 6.8 — runtime as stage groups move to the GPU (thesis: caption only, seed l. 400)";
        bars(&top, title, "time per step (ms)", &cats, &t, false)?;
        bars(&bottom, "host↔device copies each hybrid implies (counted)", "KiB per step", &cats, &b, false)
    })?;
    let _ = writeln!(md, "\n![Fig. 6.8](fig6_8_residency.svg)\n");
    Ok(())
}

/// Fig. 6.9 from the E3 rows: device memory, GPU busy fraction and the time of the run against
/// the particle budget per subdomain, one line per configuration, the unsplit runs dashed.
fn fig_6_9(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    let e3: Vec<&Record> = recs.iter().filter(|r| r.experiment == "e3").collect();
    if e3.is_empty() {
        return Ok(());
    }
    let steps = e3[0].steps;
    let _ = writeln!(
        md,
        "## E3 — subdomain budgets × configurations (Fig. 6.9; {} fluid particles, {steps} iterations)\n",
        e3[0].n_fluid
    );
    let _ = writeln!(md, "Strips along x of at most *budget* particles, each with halo particles within 3 supports + Δx (boundary images included), loaded one after another into one device solver; per force evaluation: upload positions, velocities, phases, colours, masses; download acceleration and ṽ of the owned fluid particles; the host integrates. Configurations: ○ = `cells.block-atomic.cas.cached.f32`, ∆ = `cells.thread.recomputed.f32`, □ = `cells.block-tree.cas.recomputed.f32`. GPU busy = device time (timestamps) ÷ wall time. Each split verified against the unsplit run after a few steps (same tolerance table).\n");
    let _ = writeln!(md, "| config | budget | subdomains | halo / eval | ms/step | time of {steps} it. (s) | device MiB | GPU busy | H→D KiB/step | D→H KiB/step | verified |\n|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &e3 {
        let o = |x: Option<f64>, s: f64, d: usize| x.map_or("-".to_string(), |v| format!("{:.*}", d, v * s));
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.2} | {:.2} | {} | {} | {} | {} | {} |",
            r.config,
            r.budget.map_or("unsplit".into(), |b| b.to_string()),
            r.subdomains.map_or("-".into(), |s| s.to_string()),
            o(r.halo_particles, 1.0, 0),
            r.ms(),
            r.ms() * steps as f64 * 1e-3,
            o(r.device_bytes.map(|b| b as f64), 1.0 / 1048576.0, 2),
            o(r.gpu_busy, 100.0, 0) + if r.gpu_busy.is_some() { " %" } else { "" },
            o(r.bytes_h2d_per_step, 1.0 / 1024.0, 0),
            o(r.bytes_d2h_per_step, 1.0 / 1024.0, 0),
            r.verified
        );
    }
    let mut by: BTreeMap<&str, Vec<&Record>> = BTreeMap::new();
    for r in &e3 {
        by.entry(r.config.as_str()).or_default().push(r);
    }
    let line = |f: &dyn Fn(&Record) -> Option<f64>| -> Vec<(String, Vec<(f64, f64)>)> {
        by.iter()
            .map(|(c, v)| (c.to_string(), v.iter().filter_map(|r| Some((r.budget? as f64, f(r)?))).collect()))
            .collect()
    };
    let unsplit = |f: &dyn Fn(&Record) -> Option<f64>| -> Vec<(String, usize, f64)> {
        by.iter()
            .enumerate()
            .filter_map(|(k, (c, v))| {
                let r = v.iter().find(|r| r.budget.is_none())?;
                Some((format!("{} unsplit", c.split(' ').next().unwrap_or("")), k, f(r)?))
            })
            .collect()
    };
    let mem = |r: &Record| r.device_bytes.map(|b| b as f64 / 1048576.0);
    let busy = |r: &Record| r.gpu_busy.map(|b| 100.0 * b);
    let time = |r: &Record| Some(r.ms() * steps as f64 * 1e-3);
    let kink = Some(("thesis: ∆, □ bend near 4,500 (seed l. 3800)", THESIS_KINK_BUDGET));
    let x = "particles per subdomain";
    svg(&dir.join("fig6_9_subdomains.svg"), (1500, 560), &super::look::adapter_note(recs), |a| {
        let p = a.split_evenly((1, 3));
        lines(&p[0], "(a) device memory", x, "MiB", &line(&mem), &unsplit(&mem), None)?;
        lines(&p[1], "(b) GPU busy (device ÷ wall time)", x, "%", &line(&busy), &unsplit(&busy), None)?;
        lines(&p[2], &format!("(c) time of {steps} iterations"), x, "s", &line(&time), &unsplit(&time), kink)
    })?;
    let _ = writeln!(md, "\n![Fig. 6.9](fig6_9_subdomains.svg)\n");
    Ok(())
}

/// The thesis's statements beside sphlab's ratios (E2, E3).
fn thesis_table(recs: &[Record], md: &mut String) {
    let e3: Vec<&Record> = recs.iter().filter(|r| r.experiment == "e3" && r.ms().is_finite()).collect();
    let e2: Vec<&Record> = recs.iter().filter(|r| r.experiment == "e2" && r.ms().is_finite()).collect();
    if e2.is_empty() && e3.is_empty() {
        return;
    }
    let _ = writeln!(md, "### Thesis beside sphlab (ratios only; the thesis's figures survive as captions)\n");
    let _ = writeln!(md, "| figure | the thesis (seed line) | sphlab, this adapter |\n|---|---|---|");
    let ms = |v: &str| e2.iter().find(|r| r.variant == v).map(|r| r.ms());
    if let (Some(c), Some(g)) = (ms("hybrid.cpu-all"), ms("hybrid.gpu-all")) {
        let _ = writeln!(md, "| 6.8 | {} (l. {}) | t(gpu-all) / t(cpu-all) = {:.2} |", THESIS[1].1, THESIS[1].2, g / c);
    }
    let t = |sym: &str, budget: Option<usize>| {
        e3.iter().find(|r| r.config.starts_with(sym) && r.budget == budget).map(|r| r.ms())
    };
    let mut budgets: Vec<Option<usize>> = e3.iter().map(|r| r.budget).collect();
    budgets.sort();
    budgets.dedup();
    for b in budgets {
        let name = b.map_or("unsplit".into(), |b| format!("budget {b}"));
        let r = |a: &str| match (t("∆", b), t(a, b)) {
            (Some(d), Some(x)) => format!("{:.2}", d / x),
            _ => "-".into(),
        };
        let _ = writeln!(
            md,
            "| 6.9 ({name}) | t(∆)/t(atomic) ≈ {THESIS_NO_ATOMICS_RATIO} (l. {}) | t(∆)/t(○) = {}, t(∆)/t(□) = {} |",
            THESIS[2].2,
            r("○"),
            r("□")
        );
    }
    let _ = writeln!(
        md,
        "\nOther statements of the thesis: {}.\n",
        THESIS.iter().map(|t| format!("Fig. {}: {} (l. {})", t.0, t.1, t.2)).collect::<Vec<_>>().join("; ")
    );
}

/// Writes Figs. 6.3, 6.8 and 6.9 (those whose experiments ran) into `dir` and their sections
/// into `md`.
pub fn write(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    fig_6_3(dir, recs, md)?;
    fig_6_8(dir, recs, md)?;
    fig_6_9(dir, recs, md)?;
    thesis_table(recs, md);
    Ok(())
}

#[cfg(test)]
mod tests;
