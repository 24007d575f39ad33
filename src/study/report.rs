//! Writes the study's outputs: `records.csv` (STUDY.md §5, one row per backend × size),
//! `summary.md` (E1 and E4 tables, speedups, what the numbers mean on this adapter) and SVG
//! plots (scaling log-log, speed against error); with GPU timestamps also `stage_times.csv`
//! (device ms per step and share of each stage) and the E4 per-stage table by variant family.

use super::Record;
use crate::plot::{line_plot_svg, scatter_labeled_svg, PlotSpec, Series};
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
    let timed = recs.iter().any(|r| !r.stage_ms.is_empty());
    if timed {
        write_stage_csv(&dir.join("stage_times.csv"), recs)?;
    }

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
    let _ = writeln!(md, "Scene: `oscillating-drop` (no relaxation, initial velocity field), time per step = median wall clock of the timed steps (each followed by a device sync){}. Errors: kinetic energy (relative) and centroid (in Δx) after the same steps, against the CPU f64 one-thread run.\n", if timed { "; device ms/step = median of the summed GPU timestamps of the stage passes (`stage_times.csv`)" } else { "" });
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
        let _ = writeln!(md, "| variant | N | ms/step (median) | p10 | p90 | particle-evals/s | speedup vs cpu1.cells.f64 | KE rel. error | centroid error (Δx) | device ms/step |\n|---|---|---|---|---|---|---|---|---|---|");
        let base: BTreeMap<usize, f64> =
            rows.iter().filter(|r| r.variant == "cpu1.cells.f64").map(|r| (r.n, r.ms_per_step_median)).collect();
        for r in &rows {
            let sp = base.get(&r.n).map_or("-".to_string(), |b| format!("{:.2}×", b / r.ms_per_step_median));
            let _ = writeln!(
                md,
                "| `{}` | {} | {:.3} | {:.3} | {:.3} | {:.3e} | {} | {:.1e} | {:.1e} | {} |",
                r.variant,
                r.n,
                r.ms_per_step_median,
                r.ms_per_step_p10,
                r.ms_per_step_p90,
                r.particle_evals_per_s,
                sp,
                r.ke_rel_error,
                r.centroid_error_dx,
                r.gpu_ms_per_step.map_or("-".to_string(), |x| format!("{x:.3}"))
            );
        }
        if exp == "e4" {
            if let (Some(b), Some(best)) = (
                base.values().next(),
                rows.iter()
                    .filter(|r| r.backend == "gpu")
                    .min_by(|a, b| a.ms_per_step_median.total_cmp(&b.ms_per_step_median)),
            ) {
                let _ = writeln!(md, "\nBest GPU variant: `{}` at {:.3} ms/step, {:.2}× the single-thread CPU NNPS (thesis: 120× on a 2012 GPU against a 2012 CPU core).", best.variant, best.ms_per_step_median, b / best.ms_per_step_median);
            }
        }
        if exp == "e4" {
            stage_table(&mut md, &rows);
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
        scatter_labeled_svg(
            &p,
            "Speed against error (E4)",
            "time per step (ms)",
            "kinetic-energy rel. error vs CPU f64",
            &pts,
            true,
            true,
        )
        .map_err(|x| e(&p, x))?;
        let _ = writeln!(md, "![speed against error](speed_vs_error.svg)\n");
    }
    super::thesis_figs::write(dir, recs, &mut md)?;
    if !timed && !recs.iter().any(|r| r.timing.contains("timestamps")) {
        let _ = writeln!(md, "This adapter has no GPU timestamps: all times are wall clock.");
    }
    let p = dir.join("summary.md");
    std::fs::write(&p, md).map_err(|x| e(&p, x))
}

/// `stage_times.csv`: experiment, variant, N, stage, device ms per step, share of the step.
fn write_stage_csv(p: &Path, recs: &[Record]) -> Result<(), String> {
    let mut w = csv::Writer::from_path(p).map_err(|x| e(p, x))?;
    w.write_record(["experiment", "variant", "n", "stage", "device_ms_per_step", "share"]).map_err(|x| e(p, x))?;
    for r in recs.iter().filter(|r| !r.stage_ms.is_empty()) {
        let total: f64 = r.stage_ms.iter().map(|s| s.1).sum();
        for (stage, ms) in &r.stage_ms {
            let row = [
                r.experiment.clone(),
                r.variant.clone(),
                r.n.to_string(),
                stage.clone(),
                format!("{ms:.6}"),
                format!("{:.4}", ms / total.max(1e-300)),
            ];
            w.write_record(&row).map_err(|x| e(p, x))?;
        }
    }
    w.flush().map_err(|x| e(p, x))
}

/// The E4 per-stage table: device ms per step (share of the step) of each stage, averaged over
/// the variants of each family (`{search}.{mapping}`).
fn stage_table(md: &mut String, rows: &[&Record]) {
    let mut fams: BTreeMap<String, Vec<&Record>> = BTreeMap::new();
    for r in rows.iter().filter(|r| !r.stage_ms.is_empty()) {
        let fam: Vec<&str> = r.variant.split('.').take(2).collect();
        fams.entry(fam.join(".")).or_default().push(r);
    }
    if fams.is_empty() {
        return;
    }
    let mut stages: Vec<&str> = Vec::new();
    for r in fams.values().flatten() {
        for (s, _) in &r.stage_ms {
            if !stages.contains(&s.as_str()) {
                stages.push(s);
            }
        }
    }
    let _ = writeln!(md, "\n### E4 — device time per stage (GPU timestamps; ms per step and share of the step, mean over the variants of each family)\n");
    let heads: Vec<String> = fams.iter().map(|(f, v)| format!("`{f}` ({})", v.len())).collect();
    let _ = writeln!(md, "| stage | {} |\n|---|{}", heads.join(" | "), "---|".repeat(heads.len()));
    let mean = |v: &[&Record], f: &dyn Fn(&Record) -> f64| v.iter().map(|r| f(r)).sum::<f64>() / v.len() as f64;
    let total = |r: &Record| r.stage_ms.iter().map(|s| s.1).sum::<f64>().max(1e-300);
    let get = |r: &Record, s: &str| r.stage_ms.iter().find(|x| x.0 == s).map_or(0.0, |x| x.1);
    for s in &stages {
        let cells: Vec<String> = fams
            .values()
            .map(|v| format!("{:.3} ({:.1}%)", mean(v, &|r| get(r, s)), 100.0 * mean(v, &|r| get(r, s) / total(r))))
            .collect();
        let _ = writeln!(md, "| `{s}` | {} |", cells.join(" | "));
    }
    let cells: Vec<String> = fams.values().map(|v| format!("**{:.3}**", mean(v, &total))).collect();
    let _ = writeln!(md, "| **step** | {} |", cells.join(" | "));
}
