//! Writes the study's outputs: `records.csv` (STUDY.md §5, one row per backend × size),
//! `summary.md` (E1 and E4 tables, speedups, what the numbers mean on this adapter) and SVG
//! plots (scaling log-log, speed against error).

use crate::plot::{line_plot_svg, scatter_labeled_svg, PlotSpec, Series};
use crate::study::Record;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

fn e<T: std::fmt::Display>(p: &Path, x: T) -> String {
    format!("{}: {x}", p.display())
}

/// Writes every output of the study into `dir`.
pub fn write(dir: &Path, recs: &[Record], adapter: Option<String>) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|x| e(dir, x))?;
    let csv_path = dir.join("records.csv");
    let mut w = csv::Writer::from_path(&csv_path).map_err(|x| e(&csv_path, x))?;
    for r in recs {
        w.serialize(r).map_err(|x| e(&csv_path, x))?;
    }
    w.flush().map_err(|x| e(&csv_path, x))?;

    let mut md = String::new();
    let first = recs.first();
    let _ = writeln!(md, "# sphlab study (thesis Chapter 6)\n");
    let _ = writeln!(
        md,
        "Commit `{}`, {}; CPU: {} ({} threads); GPU adapter: {}.\n",
        first.map_or("-", |r| r.commit.as_str()),
        first.map_or("-", |r| r.date.as_str()),
        first.map_or("-", |r| r.cpu_model.as_str()),
        rayon::current_num_threads(),
        adapter.as_deref().unwrap_or("none")
    );
    if adapter.as_deref().is_some_and(|a| a.contains("llvmpipe") || a.contains("Cpu")) {
        let _ = writeln!(
            md,
            "**The adapter is lavapipe, a CPU emulation of Vulkan: its times are not GPU times.** Read the GPU rows for \
             correctness and relative cost between variants only.\n"
        );
    }
    let _ = writeln!(md, "Scene: `oscillating-drop` (no relaxation, initial velocity field), time per step = median wall clock of the timed steps (each followed by a device sync). Errors: kinetic energy (relative) and centroid (in Δx) after the same steps, against the CPU f64 one-thread run.\n");
    for exp in ["e1", "e4", "scaling"] {
        let rows: Vec<&Record> = recs.iter().filter(|r| r.experiment == exp).collect();
        if rows.is_empty() {
            continue;
        }
        let title = match exp {
            "e1" => "E1 — neighbour search × backend (Fig. 6.3; 2,025 fluid particles)",
            "e4" => "E4 — every GPU variant against the single-thread CPU NNPS (§6.5; 10,000 fluid particles)",
            _ => "Scaling — time per step against N",
        };
        let _ = writeln!(md, "## {title}\n");
        let _ = writeln!(md, "| variant | N | ms/step (median) | p10 | p90 | particle-evals/s | speedup vs cpu1.cells.f64 | KE rel. error | centroid error (Δx) |\n|---|---|---|---|---|---|---|---|---|");
        let base: BTreeMap<usize, f64> =
            rows.iter().filter(|r| r.variant == "cpu1.cells.f64").map(|r| (r.n, r.ms_per_step_median)).collect();
        for r in &rows {
            let sp = base.get(&r.n).map_or("-".to_string(), |b| format!("{:.2}×", b / r.ms_per_step_median));
            let _ = writeln!(
                md,
                "| `{}` | {} | {:.3} | {:.3} | {:.3} | {:.3e} | {} | {:.1e} | {:.1e} |",
                r.variant, r.n, r.ms_per_step_median, r.ms_per_step_p10, r.ms_per_step_p90, r.particle_evals_per_s, sp, r.ke_rel_error, r.centroid_error_dx
            );
        }
        if exp == "e4" {
            if let (Some(b), Some(best)) = (
                base.values().next(),
                rows.iter().filter(|r| r.backend == "gpu").min_by(|a, b| a.ms_per_step_median.total_cmp(&b.ms_per_step_median)),
            ) {
                let _ = writeln!(md, "\nBest GPU variant: `{}` at {:.3} ms/step, {:.2}× the single-thread CPU NNPS (thesis: 120× on a 2012 GPU against a 2012 CPU core).", best.variant, best.ms_per_step_median, b / best.ms_per_step_median);
            }
        }
        let _ = writeln!(md);
    }
    // Scaling plot.
    let mut by_variant: BTreeMap<&str, Vec<(f64, f64)>> = BTreeMap::new();
    for r in recs.iter().filter(|r| r.experiment == "scaling") {
        by_variant.entry(&r.variant).or_default().push((r.n as f64, r.ms_per_step_median));
    }
    if !by_variant.is_empty() {
        let mut spec = PlotSpec::new("Time per step against particle count", "particles N", "time per step (ms)");
        spec.log_x = true;
        spec.log_y = true;
        spec.series = by_variant.into_iter().map(|(k, v)| Series::line_points(k, v)).collect();
        let p = dir.join("scaling.svg");
        line_plot_svg(&p, &spec).map_err(|x| e(&p, x))?;
        let _ = writeln!(md, "![scaling](scaling.svg)\n");
    }
    // Speed against error (E4 rows).
    let pts: Vec<(f64, f64, String)> = recs
        .iter()
        .filter(|r| r.experiment == "e4" && r.ke_rel_error > 0.0)
        .map(|r| (r.ms_per_step_median, r.ke_rel_error, r.variant.clone()))
        .collect();
    if !pts.is_empty() {
        let p = dir.join("speed_vs_error.svg");
        scatter_labeled_svg(&p, "Speed against error (E4)", "time per step (ms)", "kinetic-energy rel. error vs CPU f64", &pts, true, true)
            .map_err(|x| e(&p, x))?;
        let _ = writeln!(md, "![speed against error](speed_vs_error.svg)\n");
    }
    let _ = writeln!(md, "Not implemented: E2 (stages moved to the GPU one group at a time) and E3 (subdomain budgets); GPU timestamp queries (all times are wall clock).");
    let p = dir.join("summary.md");
    std::fs::write(&p, md).map_err(|x| e(&p, x))
}
