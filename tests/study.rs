//! `sphlab study` made honest: a run that overflows or blows up inside the study is a
//! record with its status and no timing; every GPU record's speedup is against a baseline of its
//! own run and precision; a variant made wrong on purpose is `inaccurate` and never the answer; `--budget` keeps the study within its budget (±20 %);
//! `sphlab report` merges two runs into one summary; pipelines
//! are compiled once per variant and reused at every size. Runs on lavapipe (software Vulkan):
//! every study here is a few tiny jobs with `--warmup 0`.

mod common;

use common::{gpu_or_skip, serial};
use std::path::Path;
use std::process::{Command, Output};
use std::time::Instant;

fn sphlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sphlab")).args(args).output().expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `records.csv` as (header → column) maps, one per row.
fn records(dir: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let mut r = csv::Reader::from_path(dir.join("records.csv")).expect("records.csv");
    let head: Vec<String> = r.headers().expect("header").iter().map(String::from).collect();
    r.records().map(|row| head.iter().cloned().zip(row.expect("row").iter().map(String::from)).collect()).collect()
}

/// A tiny study: one size, K = 1 step per sync, one block, no warm-up.
fn tiny<'a>(out: &'a str, variants: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "study",
        "--experiments",
        "scaling",
        "--sizes",
        "16",
        "--steps",
        "1",
        "--repeats",
        "1",
        "--warmup",
        "0",
        "--variants",
        variants,
        "--out",
        out,
    ];
    v.extend_from_slice(extra);
    v
}

const TIMING: [&str; 6] = [
    "ms_per_step_median",
    "ms_per_step_min",
    "ms_per_step_max",
    "latency_ms_median",
    "particle_evals_per_s",
    "ke_rel_error",
];

#[test]
fn a_failed_run_is_a_record_without_timing() {
    let _g = serial();
    if gpu_or_skip().is_none() {
        return;
    }
    // h = 2.4 Δx: ~170 neighbours, over the 64 slots of the block layouts.
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("overflow");
    let o = sphlab(&tiny(
        out.to_str().expect("utf8"),
        "cells.block-atomic.cas.recomputed.f32,cells.thread.recomputed.f32",
        &["--set", "kernel.h_ratio=2.4"],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = records(&out);
    let block = rows.iter().find(|r| r["variant"] == "cells.block-atomic.cas.recomputed.f32").expect("block row");
    assert_eq!(block["status"], "overflow", "{block:?}");
    // The 64 list slots, or first the bits of the compact list mask over the cell walk.
    assert!(block["reason"].contains("more than") && block["reason"].contains("cannot hold them"), "{block:?}");
    for c in TIMING {
        assert!(block[c].is_empty(), "overflow row has {c} = {}", block[c]);
    }
    let thread = rows.iter().find(|r| r["variant"] == "cells.thread.recomputed.f32").expect("thread row");
    // Measured: `ok`, or `loaded` when other work on this machine raised the load average.
    assert!(["ok", "loaded"].contains(&thread["status"].as_str()), "{thread:?}");
    assert!(thread["ms_per_step_median"].parse::<f64>().is_ok_and(|x| x > 0.0), "{thread:?}");
    let md = std::fs::read_to_string(out.join("summary.md")).expect("summary");
    assert!(md.contains("**overflow**"), "{md}");

    // dt far above every limit (policy `warn` lets it through): the CPU runs blow up.
    let out = dir.path().join("blowup");
    let o = sphlab(&tiny(
        out.to_str().expect("utf8"),
        "cells.thread.recomputed.f32",
        &["--set", "time.dt_policy=warn", "--set", "time.dt=0.05"],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = records(&out);
    let cpu1 = rows.iter().find(|r| r["variant"] == "cpu1.cells.f64").expect("cpu1 row");
    assert_eq!(cpu1["status"], "blown-up", "{cpu1:?}");
    assert!(cpu1["reason"].contains("particle"), "{cpu1:?}");
    for r in rows.iter().filter(|r| !["ok", "inaccurate", "loaded"].contains(&r["status"].as_str())) {
        for c in TIMING {
            assert!(r[c].is_empty(), "{} ({}) has {c} = {}", r["variant"], r["status"], r[c]);
        }
    }
}

/// What a budget promises on any machine, fast or loaded: the plan is printed before any job
/// runs, the summary states the budget and what was dropped or given more blocks, no job runs
/// fewer blocks than `--repeats`, and the run ends under 1.2 × the budget plus
/// [`STARTUP_ALLOWANCE_S`] (process start, adapter, plots: outside the study's clock). Which
/// sizes are dropped depends on this machine's speed; `plan::select` is tested on stated costs.
#[test]
fn budget_is_kept() {
    let _g = serial();
    if gpu_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("b");
    let budget = 20.0;
    let t = Instant::now();
    let o = sphlab(&[
        "study",
        "--experiments",
        "scaling",
        "--sizes",
        "16,24,32,48,64,96,128",
        "--steps",
        "2",
        "--repeats",
        "2",
        "--warmup",
        "0.2",
        "--variants",
        "cells.thread.recomputed.f32",
        "--budget",
        "20s",
        "--out",
        out.to_str().expect("utf8"),
    ]);
    let took = t.elapsed().as_secs_f64();
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    let plan_at = e.find("study plan:").unwrap_or_else(|| panic!("no plan printed: {e}"));
    assert!(e[plan_at..].contains("estimated time"), "the plan states its estimate: {e}");
    let first_job = e.find("scaling nx=").unwrap_or_else(|| panic!("no job ran: {e}"));
    assert!(plan_at < first_job, "the plan comes before the first job: {e}");
    let md = std::fs::read_to_string(out.join("summary.md")).expect("summary");
    assert!(md.contains("budget: 20 s; dropped for it (largest first): "), "{md}");
    assert!(md.contains("Budget 20 s: the study took"), "{md}");
    if !md.contains("dropped for it (largest first): nothing") {
        assert!(md.contains("dropped for it (largest first): nx=128"), "the largest size goes first: {md}");
    }
    assert!(
        took < 1.2 * budget + STARTUP_ALLOWANCE_S,
        "a {budget} s budget took {took:.1} s (the promise: under 1.2 × budget + {STARTUP_ALLOWANCE_S} s): {e}\nsummary.md:\n{md}"
    );
    let rows = records(&out);
    assert!(!rows.is_empty());
    for r in rows.iter().filter(|r| r["status"] != "skipped") {
        // A job running late gives back the fill's blocks, never those `--repeats` asked for.
        let reps: usize = r["repeats"].parse().expect("repeats");
        assert!(reps >= 2, "{} nx={} ran {reps} timed blocks (--repeats 2)", r["variant"], r["nx"]);
    }
    // A job the budget left out is a `skipped` row saying so, never a missing one.
    for r in rows.iter().filter(|r| r["status"] == "skipped") {
        assert!(r["reason"].contains("budget") && r["ms_per_step_median"].is_empty(), "{r:?}");
    }
    if !md.contains("dropped for it (largest first): nothing") {
        let dropped = |v: &str| rows.iter().any(|r| r["nx"] == "128" && r["variant"] == v && r["status"] == "skipped");
        assert!(dropped("cpu1.cells.f64") && dropped("cells.thread.recomputed.f32"), "nx=128 dropped, its rows kept");
    }
    assert!(!out.join("records.partial.csv").exists(), "a finished study removes its journal");
}

/// Seconds a study process may take outside its budget's clock: start-up, the adapter, and
/// writing the report and plots.
const STARTUP_ALLOWANCE_S: f64 = 10.0;

#[test]
fn report_merges_two_runs() {
    let _g = serial();
    if gpu_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let (a, b, m) = (dir.path().join("f32"), dir.path().join("f64"), dir.path().join("merged"));
    for (out, v) in [(&a, "cells.thread.recomputed.f32"), (&b, "cells.thread.recomputed.f64")] {
        let o = sphlab(&tiny(out.to_str().expect("utf8"), v, &["--cpu-max-n", "1"]));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = sphlab(&["report", a.to_str().unwrap(), b.to_str().unwrap(), "--out", m.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let md = std::fs::read_to_string(m.join("summary.md")).expect("summary");
    assert!(md.contains("cells.thread.recomputed.f32") && md.contains("cells.thread.recomputed.f64"), "{md}");
    assert_eq!(records(&m).len(), records(&a).len() + records(&b).len());
    // Only `ok` records are plotted as timings (a loaded machine leaves none).
    let ok_gpu = records(&m).iter().any(|r| r["backend"] == "gpu" && r["status"] == "ok");
    assert_eq!(m.join("scaling_cells_thread.svg").exists(), ok_gpu);
    let o = sphlab(&["report", dir.path().join("none").to_str().unwrap(), "--out", m.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn pipelines_are_compiled_once_per_variant() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = std::sync::Arc::new(ctx);
    let spec = sphlab::gpu::variant::VariantSpec::default();
    for nx in [16, 24] {
        let scene = sphlab::study::study_scene(nx);
        let layout = sphlab::scene::build::build_layout(&scene).expect("layout");
        let mut b = sphlab::backend_id::BackendId::Gpu(spec).build(&scene, &layout, Some(&ctx)).expect("builds");
        b.step().expect("steps");
    }
    assert_eq!(ctx.pipelines.compiles(), 1, "one variant at two sizes compiles once");
}

/// The same-run baselines and the accuracy gate: every GPU record names a one-thread CPU
/// baseline of its run and precision and its speedup is that baseline's ms/step over its own;
/// every record has a status from the list, p10/p90 and load columns; a variant given a
/// perturbed viscosity (its scene only) is `inaccurate` and the answer table does not name it.
#[test]
fn baselines_are_same_run_and_a_wrong_variant_is_never_the_answer() {
    let _g = serial();
    if gpu_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let wrong = "cells.thread.recomputed.f32";
    let opts = sphlab::study::StudyOptions {
        experiments: vec!["e4".into()],
        e4_sizes: vec![16],
        protocol: sphlab::study::timing::Protocol { steps: 3, repeats: 5, warmup_s: 0.0, latency_samples: 1 },
        variants: vec![wrong.parse().unwrap(), "cells.thread.recomputed.f64".parse().unwrap()],
        perturb: vec![(wrong.into(), vec!["phases[0].mu=0.06".into()])],
        out: dir.path().to_path_buf(),
        ..Default::default()
    };
    let recs = sphlab::study::run_study(&opts).expect("study");
    assert!(recs.iter().all(|r| r.steps == 10), "K is raised to a whole rebuild period (10 steps)");
    let rows = records(dir.path());
    for r in &rows {
        assert!(sphlab::study::record::STATUSES.contains(&r["status"].as_str()), "{r:?}");
        for c in ["ms_per_step_p10", "ms_per_step_p90", "ms_per_step_ci_lo", "ms_per_step_ci_hi", "load_before"] {
            assert!(r[c].parse::<f64>().is_ok(), "{} has no {c}: {r:?}", r["variant"]);
        }
        // Pair interactions: the particle evaluations times the mean neighbour-list length, which
        // for the quintic at h = 1.2Δx (support 3.6Δx) is near π·3.6² ≈ 41 inside the fluid and
        // fewer at the walls' outer layers.
        let f = |c: &str| r[c].parse::<f64>().unwrap_or_else(|_| panic!("{} has no {c}: {r:?}", r["variant"]));
        let k = f("mean_neighbours");
        assert!((20.0..45.0).contains(&k), "mean neighbours {k}: {r:?}");
        assert!((f("pair_interactions_per_s") / (f("particle_evals_per_s") * k) - 1.0).abs() < 1e-9, "{r:?}");
    }
    let ms = |r: &std::collections::HashMap<String, String>| r["ms_per_step_median"].parse::<f64>().unwrap();
    for g in rows.iter().filter(|r| r["backend"] == "gpu") {
        let b = rows
            .iter()
            .find(|b| b["variant"] == g["baseline"] && b["run"] == g["run"])
            .unwrap_or_else(|| panic!("{}: baseline `{}` not in the run", g["variant"], g["baseline"]));
        assert_eq!(b["backend"], "cpu1", "{b:?}");
        assert_eq!(b["precision"], g["precision"], "{g:?}");
        let fastest = rows
            .iter()
            .filter(|c| c["backend"] == "cpu1" && c["precision"] == g["precision"] && c["variant"] != "cpu1.direct.f64")
            .map(ms)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(ms(b), fastest, "the baseline is the fastest one-thread search: {g:?}");
        let speedup: f64 = g["speedup_vs_baseline"].parse().unwrap();
        assert!((speedup / (ms(b) / ms(g)) - 1.0).abs() < 0.01, "{g:?}");
        assert!(
            g["speedup_vs_cpu_all"].parse::<f64>().is_ok() && g["speedup_vs_cpu1_cells_f64"].parse::<f64>().is_ok()
        );
    }
    let bad = rows.iter().find(|r| r["variant"] == wrong).expect("the perturbed record");
    assert_eq!(bad["status"], "inaccurate", "{bad:?}");
    assert!(bad["reason"].contains("tolerance"), "{bad:?}");
    let md = std::fs::read_to_string(dir.path().join("summary.md")).expect("summary");
    let answer = md.split("## The answer").nth(1).expect("an answer section").split("\n## ").next().unwrap();
    assert!(md.find("## The answer") < md.find("## Plan"), "the answer comes first");
    assert!(!answer.contains(&format!("| `{wrong}` |")), "an inaccurate variant is never the fastest: {answer}");
}

/// `--workgroup-sizes` adds each thread variant's twins at the other sizes (and no block
/// variant's), they run and match the CPU like the 64-thread variant, the answer has the
/// workgroup-size axis; a size that is not 64, 128 or 256 is bad input.
#[test]
fn workgroup_size_is_a_study_axis() {
    let _g = serial();
    if gpu_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().to_str().expect("utf8");
    let o = sphlab(&tiny(out, "cells.block-tree.fixed.recomputed.f32", &["--workgroup-sizes", "96"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--workgroup-sizes") && stderr(&o).contains("64, 128, 256"), "{}", stderr(&o));
    let variants = "cells.thread.recomputed.f32,cells.block-tree.fixed.recomputed.f32";
    let o = sphlab(&tiny(out, variants, &["--workgroup-sizes", "64,256"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = records(dir.path());
    let gpu: Vec<&str> = rows.iter().filter(|r| r["backend"] == "gpu").map(|r| r["variant"].as_str()).collect();
    assert_eq!(
        gpu,
        ["cells.thread.recomputed.f32", "cells.thread.recomputed.f32.wg256", "cells.block-tree.fixed.recomputed.f32"],
        "{rows:?}"
    );
    for r in rows.iter().filter(|r| r["backend"] == "gpu") {
        assert!(["ok", "loaded"].contains(&r["status"].as_str()), "{r:?}");
        assert!(r["ke_rel_error"].parse::<f64>().unwrap() < 1e-5, "{r:?}");
    }
    let md = std::fs::read_to_string(dir.path().join("summary.md")).expect("summary");
    assert!(md.contains("| workgroup size | `wg256` over `wg64` |"), "{md}");
}
