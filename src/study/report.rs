//! Writes the study's outputs: `records.csv` (docs/STUDY.md §5, one row per backend × size, failed
//! runs included with their status and no timing), `summary.md` (the plan, E1/E4/scaling tables
//! with speedups, what the numbers mean on this adapter), SVG plots (scaling log-log, one facet
//! per neighbour search; speed against error); with GPU timestamps also `stage_times.csv` and
//! the E4 per-stage table. [`merge`] (`sphlab report DIR... --out DIR`) reads the records of
//! several runs (shards, adapters) and writes one report from them, adapters side by side.

use super::look;
use super::{Record, RunNotes};
use crate::plot::{line_plot_svg, PlotSpec, Series};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Plot lines by label: (x, y) points.
type Lines = BTreeMap<String, Vec<(f64, f64)>>;

fn e<T: std::fmt::Display>(p: &Path, x: T) -> String {
    format!("{}: {x}", p.display())
}

/// The continuity baseline (`speedup_vs_cpu1_cells_f64`).
pub use super::baseline::CPU1_CELLS_F64 as BASELINE;

/// Errors below this are drawn at it on the log axis of `speed_vs_error.svg` (and said so).
pub const ERROR_FLOOR: f64 = 1e-12;

fn opt(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map_or("-".into(), f)
}

/// The journal of a running study: every record is appended to it as soon as it exists, so an
/// interrupted study keeps what it measured (`sphlab report` reads it where `records.csv` is missing).
/// [`write`] removes it once `records.csv` is written.
pub const JOURNAL: &str = "records.partial.csv";

/// Appends `recs` to `dir`'s [`JOURNAL`] (with the header when the file is new).
pub fn journal(dir: &Path, recs: &[Record]) -> Result<(), String> {
    if recs.is_empty() {
        return Ok(());
    }
    std::fs::create_dir_all(dir).map_err(|x| e(dir, x))?;
    let p = dir.join(JOURNAL);
    let f = std::fs::OpenOptions::new().create(true).append(true).open(&p).map_err(|x| e(&p, x))?;
    let fresh = f.metadata().map_err(|x| e(&p, x))?.len() == 0;
    let mut w = csv::WriterBuilder::new().has_headers(fresh).from_writer(f);
    for r in recs {
        w.serialize(r).map_err(|x| e(&p, x))?;
    }
    w.flush().map_err(|x| e(&p, x))
}

/// Writes every output of the study into `dir` from the records as they are: their speedups
/// were computed by the runs that measured them ([`super::baseline::annotate`]), never here.
pub fn write(dir: &Path, recs: &mut [Record], adapter: Option<String>, notes: &RunNotes) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|x| e(dir, x))?;
    let csv_path = dir.join("records.csv");
    let mut w = csv::Writer::from_path(&csv_path).map_err(|x| e(&csv_path, x))?;
    for r in recs.iter() {
        w.serialize(r).map_err(|x| e(&csv_path, x))?;
    }
    w.flush().map_err(|x| e(&csv_path, x))?;
    let _ = std::fs::remove_file(dir.join(JOURNAL));
    let timed = recs.iter().any(|r| r.gpu_ms_per_step.is_some());
    if recs.iter().any(|r| !r.stage_ms.is_empty()) {
        write_stage_csv(&dir.join("stage_times.csv"), recs)?;
    }
    let mut adapters: Vec<&str> = recs.iter().filter(|r| r.backend == "gpu").map(|r| r.adapter.as_str()).collect();
    adapters.sort();
    adapters.dedup();
    let side_by_side = adapters.len() > 1;

    let mut md = header(recs, adapter, notes, &adapters, timed);
    for exp in ["e1", "e4", "scaling"] {
        experiment_table(&mut md, recs, exp, &adapters);
    }
    super::engine_ab::summary(&mut md, recs);
    scaling_plots(dir, recs, side_by_side, &mut md)?;
    super::overview_plots::write(dir, recs, &mut md)?;
    speed_vs_error(dir, recs, &mut md)?;
    super::thesis_figs::write(dir, recs, &mut md)?;
    if !timed {
        let _ = writeln!(
            md,
            "GPU timestamps: none in these records (the adapter has none, or no GPU ran): all times are wall clock.\n"
        );
    }
    let p = dir.join("summary.md");
    std::fs::write(&p, md).map_err(|x| e(&p, x))
}

/// The head of `summary.md`: commits, date, CPU and adapters, the lavapipe warning, the plan,
/// the run's notes and the protocol.
fn header(recs: &[Record], adapter: Option<String>, notes: &RunNotes, adapters: &[&str], timed: bool) -> String {
    let side_by_side = adapters.len() > 1;
    let mut md = String::new();
    let first = recs.first();
    let _ = writeln!(md, "# sphlab study (thesis Chapter 6)\n");
    super::answer::write(&mut md, recs);
    let mut commits: Vec<&str> = recs.iter().map(|r| r.commit.as_str()).collect();
    commits.sort();
    commits.dedup();
    let _ = writeln!(
        md,
        "Commit `{}`, {}; CPU: {}; GPU adapter{}: {}.\n",
        commits.join("`, `"),
        first.map_or("-", |r| r.date.as_str()),
        first.map_or("-", |r| r.cpu_model.as_str()),
        if side_by_side { "s" } else { "" },
        adapter.unwrap_or_else(|| if adapters.is_empty() { "none".into() } else { adapters.join("; ") })
    );
    if recs.iter().any(|r| r.backend == "gpu" && r.device_type == "Cpu") {
        let _ = writeln!(
            md,
            "**A GPU adapter here is a CPU emulation of Vulkan (lavapipe/llvmpipe): its times are not GPU times.** \
             Read its rows for correctness and relative cost between variants only.\n"
        );
    }
    if !notes.plan.is_empty() {
        let _ = writeln!(md, "## Plan\n\n{}", notes.plan);
    }
    for o in &notes.outcome {
        let _ = writeln!(md, "{o}\n");
    }
    let k = first.map_or(0, |r| r.steps);
    let _ = writeln!(
        md,
        "Scene: `oscillating-drop` (no relaxation, initial velocity field). **Throughput** (ms/step) = wall time of a \
         block of K = {k} steps (a whole number of tracking-list rebuild periods) with one device sync at its end, ÷ K: \
         median over the blocks with its bootstrap 95 % interval (fixed seed), p10 and p90 (after a warm-up of fixed \
         wall time). **Latency** = one step followed by a device sync (median). Device ms/step = one GPU timestamp \
         pair around each submission's steps (the fused engine as it runs, gaps between passes included), median over \
         the blocks; beside it the sum of the stage passes of one more block with every stage in a pass of its own (the \
         unfused debug mode{}). **Modelled GB/s** = the bytes a step must move at least (`gpu::bandwidth`'s model, \
         a lower bound) ÷ ms/step, and its share of the streaming bandwidth this run measured once (copy kernel over \
         2 buffers of up to {} each, smaller under a short budget — the plan names the size; timestamps). Errors: kinetic energy (relative) and centroid (in Δx) after the \
         first K steps, against the CPU f64 one-thread run. **Status**: `ok` (ranked), `inaccurate` (K-step \
         observables or first-evaluation fields beyond `verify`'s tolerances against the CPU run of the same \
         precision), `loaded` (other processes used more than a quarter of the cores), `overflow`, `blown-up`, `failed`, `skipped`; a run \
         that was not measured has no timing. **Speedup vs baseline** = the fastest one-thread CPU search of the \
         row's precision in the same run (named) ÷ the row's ms/step; vs all cores: `cpu.cells` of that precision; \
         vs `{BASELINE}` is kept for continuity, `cpu_ref` saying whether that CPU time was measured at the same N \
         or scaled by N from the largest CPU size.\n",
        if timed { "; per stage in `stage_times.csv`" } else { "" },
        crate::plan::fmt_bytes(crate::gpu::bandwidth::PROBE_BYTES as f64)
    );
    md
}

/// The table of one experiment (`e1`, `e4`, `scaling`), with E4's best variant per adapter and
/// its stage table; nothing when the experiment has no record.
fn experiment_table(md: &mut String, recs: &[Record], exp: &str, adapters: &[&str]) {
    let side_by_side = adapters.len() > 1;
    let rows: Vec<&Record> = recs.iter().filter(|r| r.experiment == exp).collect();
    if rows.is_empty() {
        return;
    }
    let title = match exp {
        "e1" => "E1 — neighbour search × backend (Fig. 6.3; 2,025 fluid particles)",
        "e4" => "E4 — every GPU variant against the single-thread CPU NNPS (§6.5; 2,025 and 10,000 fluid particles)",
        _ => "Scaling — time per step against N",
    };
    let _ = writeln!(md, "## {title}\n");
    let ad = if side_by_side { " adapter |" } else { "" };
    let _ = writeln!(
        md,
        "| variant |{ad} N | status | ms/step median [95 % interval] | p10–p90 | latency ms | particle-evals/s | modelled GB/s (% of measured bandwidth) | speedup vs baseline | vs all cores | vs `{BASELINE}` | KE rel. error | centroid error (Δx) | device ms/step (fused / sum of stages, unfused) | load before/after |\n|---|{}---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        if side_by_side { "---|" } else { "" }
    );
    for r in &rows {
        let sp = opt(r.speedup_vs_cpu1_cells_f64, |s| {
            if r.cpu_ref == "measured" {
                format!("{s:.2}×")
            } else {
                format!("{s:.2}× ({})", r.cpu_ref)
            }
        });
        let status = if r.reason.is_empty() { r.status.clone() } else { format!("**{}**: {}", r.status, r.reason) };
        let ad = if side_by_side { format!(" {} |", r.adapter) } else { String::new() };
        let f3 = |x: Option<f64>| opt(x, |x| format!("{x:.3}"));
        let _ = writeln!(
            md,
            "| `{}` |{ad} {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.variant,
            r.n,
            status,
            opt(r.ms_per_step_median, |x| format!("{x:.3} [{}, {}]", f3(r.ms_per_step_ci_lo), f3(r.ms_per_step_ci_hi))),
            opt(r.ms_per_step_p10, |x| format!("{x:.3}–{}", f3(r.ms_per_step_p90))),
            f3(r.latency_ms_median),
            opt(r.particle_evals_per_s, |x| format!("{x:.3e}")),
            opt(r.achieved_gb_s, |x| format!(
                "{x:.3}{}",
                opt(r.roofline_fraction, |f| format!(" ({:.1} %)", 100.0 * f))
            )),
            opt(r.speedup_vs_baseline, |x| format!("{x:.2}× (`{}`)", r.baseline)),
            opt(r.speedup_vs_cpu_all, |x| format!("{x:.2}×")),
            sp,
            opt(r.ke_rel_error, |x| format!("{x:.1e}")),
            opt(r.centroid_error_dx, |x| format!("{x:.1e}")),
            opt(r.gpu_ms_per_step, |x| format!("{x:.3} / {}", f3(r.stage_sum_ms_per_step))),
            opt(r.load_before, |x| format!("{x:.2}/{}", opt(r.load_after, |y| format!("{y:.2}"))))
        );
    }
    if exp == "e4" {
        stage_table(md, &rows);
    }
    let _ = writeln!(md);
}

/// The scaling plots, faceted by neighbour search, then by mapping
/// (`scaling_<search>_<mapping>.svg`): the GPU variants of that search and mapping (≤ 8 ids, by
/// machine when several, so the 10 colours do not repeat within a facet and no line joins two
/// machines) and the CPU one-thread
/// and all-thread f64 references in every facet.
fn scaling_plots(dir: &Path, recs: &[Record], side_by_side: bool, md: &mut String) -> Result<(), String> {
    let ok: Vec<&Record> = recs.iter().filter(|r| r.experiment == "scaling" && r.is_ok()).collect();
    // One series per id and machine when the records come from several (GPU adapters or CPUs).
    let several = side_by_side || look::several_machines(&ok);
    let facet_of = |variant: &str| {
        let mut it = variant.split('.');
        (it.next().unwrap_or("").to_string(), it.next().unwrap_or("").to_string())
    };
    let mut facets: BTreeMap<(String, String), Lines> = BTreeMap::new();
    for r in ok.iter().filter(|r| r.backend == "gpu") {
        facets.entry(facet_of(&r.variant)).or_default();
    }
    if facets.is_empty() {
        facets.insert(("cpu".into(), "reference".into()), BTreeMap::new());
    }
    let mut ids: BTreeMap<String, String> = BTreeMap::new();
    for ((s, m), f) in facets.iter_mut() {
        let prefix = format!("{s}.{m}.");
        for r in &ok {
            let Some(ms) = r.ms_per_step_median else { continue };
            let reference = r.variant == BASELINE || r.variant == "cpu.cells.f64";
            if !(r.variant.starts_with(&prefix) || reference) {
                continue;
            }
            let short = if reference { r.variant.as_str() } else { r.variant.trim_start_matches(&prefix) };
            let label = look::label_at(short, r, several);
            ids.insert(label.clone(), r.variant.clone());
            f.entry(label).or_default().push((r.n as f64, ms));
        }
    }
    for ((s, m), series) in facets {
        if series.is_empty() {
            continue;
        }
        let mut spec = PlotSpec::new(
            format!("Time per step against N — {s} search, {m} mapping"),
            "particles N",
            "time per step (ms)",
        );
        spec.log_x = true;
        spec.log_y = true;
        spec.legend_outside = true;
        spec.note = look::adapter_note(recs);
        spec.series = series
            .into_iter()
            .map(|(k, mut v)| {
                v.sort_by(|a, b| a.0.total_cmp(&b.0));
                let id = ids.get(&k).cloned().unwrap_or_else(|| k.clone());
                look::styled(Series::line_points(k, v), &id)
            })
            .collect();
        let name = format!("scaling_{s}_{m}.svg");
        let p = dir.join(&name);
        line_plot_svg(&p, &spec).map_err(|x| e(&p, x))?;
        let _ = writeln!(md, "![scaling, {s} search, {m} mapping]({name})\n");
    }
    Ok(())
}

/// Speed against error (E4 rows): time per step against the kinetic-energy error, log-log, one
/// marker per variant in its colour with the legend beside the plot (no labels over the data);
/// errors below [`ERROR_FLOOR`] drawn at it.
fn speed_vs_error(dir: &Path, recs: &[Record], md: &mut String) -> Result<(), String> {
    let pts: Vec<(f64, f64, &str)> = recs
        .iter()
        .filter(|r| r.experiment == "e4" && r.is_ok())
        .filter_map(|r| Some((r.ms_per_step_median?, r.ke_rel_error?.max(ERROR_FLOOR), r.variant.as_str())))
        .collect();
    if pts.is_empty() {
        return Ok(());
    }
    let mut spec = PlotSpec::new(
        "Speed against error (E4)",
        "time per step (ms)",
        format!("kinetic-energy rel. error vs CPU f64 (floor {ERROR_FLOOR:.0e})"),
    );
    (spec.log_x, spec.log_y, spec.legend_outside) = (true, true, true);
    spec.note = look::adapter_note(recs);
    let mut by_id: BTreeMap<&str, Vec<(f64, f64)>> = BTreeMap::new();
    for (x, y, id) in pts {
        by_id.entry(id).or_default().push((x, y));
    }
    spec.series = by_id.into_iter().map(|(id, v)| look::styled(Series::points(id, v), id)).collect();
    let p = dir.join("speed_vs_error.svg");
    line_plot_svg(&p, &spec).map_err(|x| e(&p, x))?;
    let _ = writeln!(
        md,
        "![speed against error](speed_vs_error.svg)\n\nErrors below {ERROR_FLOOR:.0e} (f64 variants agree with the CPU f64 run to rounding) are drawn at {ERROR_FLOOR:.0e}.\n"
    );
    Ok(())
}

/// Reads `records.csv` of a study output directory, or the [`JOURNAL`] of a study that did not
/// finish (with a warning).
pub fn read_records(dir: &Path) -> Result<Vec<Record>, String> {
    let mut p = dir.join("records.csv");
    if !p.exists() && dir.join(JOURNAL).exists() {
        eprintln!("warning: {}: no records.csv; reading the journal of an unfinished study ({JOURNAL})", dir.display());
        p = dir.join(JOURNAL);
    }
    let mut r = csv::Reader::from_path(&p).map_err(|x| e(&p, x))?;
    let mut recs: Vec<Record> = r.deserialize().map(|x| x.map_err(|err| e(&p, err))).collect::<Result<_, _>>()?;
    read_stage_csv(&dir.join("stage_times.csv"), &mut recs)?;
    Ok(recs)
}

/// Gives back each record its per-stage times from `stage_times.csv` (written beside
/// `records.csv`), matched by experiment, variant and N; nothing when the file is missing.
fn read_stage_csv(p: &Path, recs: &mut [Record]) -> Result<(), String> {
    if !p.exists() {
        return Ok(());
    }
    let mut r = csv::Reader::from_path(p).map_err(|x| e(p, x))?;
    for row in r.records() {
        let row = row.map_err(|x| e(p, x))?;
        let (Some(exp), Some(variant), Some(n), Some(stage), Some(ms)) =
            (row.get(0), row.get(1), row.get(2), row.get(3), row.get(4))
        else {
            return Err(format!("{}: a row without its five columns", p.display()));
        };
        let (n, ms): (usize, f64) = match (n.parse(), ms.parse()) {
            (Ok(n), Ok(ms)) => (n, ms),
            _ => return Err(format!("{}: `{n}`, `{ms}` are not N and ms", p.display())),
        };
        if let Some(rec) = recs.iter_mut().find(|q| q.experiment == exp && q.variant == variant && q.n == n) {
            rec.stage_ms.push((stage.to_string(), ms));
        }
    }
    Ok(())
}

/// `sphlab report DIR... --out DIR`: the records of every input directory in one report.
pub fn merge(inputs: &[PathBuf], out: &Path) -> Result<Vec<Record>, String> {
    let mut recs = Vec::new();
    for d in inputs {
        // Records of a version without the `run` column (or a journal) are named by their folder.
        let mut rs = read_records(d)?;
        for r in rs.iter_mut().filter(|r| r.run.is_empty()) {
            r.run = d.display().to_string();
        }
        recs.extend(rs);
    }
    let list: Vec<String> = inputs.iter().map(|d| format!("`{}`", d.display())).collect();
    let notes =
        RunNotes { plan: format!("* merged from {} runs: {}\n", inputs.len(), list.join(", ")), outcome: Vec::new() };
    write(out, &mut recs, None, &notes)?;
    Ok(recs)
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
        fams.entry(super::overview_plots::family(&r.variant)).or_default().push(r);
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
    let _ = writeln!(
        md,
        "\n### E4 — device time per stage (GPU timestamps of the stage-timed block, every stage a pass of its own: \
         the unfused debug mode; ms per step and share of their sum, mean over the variants of each family)\n"
    );
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
    let _ = writeln!(md, "| **sum of the stages (unfused)** | {} |", cells.join(" | "));
    let fused = |v: &[&Record]| {
        let d: Vec<f64> = v.iter().filter_map(|r| r.gpu_ms_per_step).collect();
        opt((d.len() == v.len()).then(|| d.iter().sum::<f64>() / d.len() as f64), |x| format!("{x:.3}"))
    };
    let cells: Vec<String> = fams.values().map(|v| fused(v)).collect();
    let _ = writeln!(
        md,
        "| **step as the engine runs (fused; one timestamp pair per submission)** | {} |",
        cells.join(" | ")
    );
}
