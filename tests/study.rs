//! `sphlab study` made honest: a run that overflows or blows up inside the study is a
//! record with its status and no timing; `--budget` keeps the study within its budget (±20 %);
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
    assert!(block["reason"].contains("more than 64 neighbours"), "{block:?}");
    for c in TIMING {
        assert!(block[c].is_empty(), "overflow row has {c} = {}", block[c]);
    }
    let thread = rows.iter().find(|r| r["variant"] == "cells.thread.recomputed.f32").expect("thread row");
    assert_eq!(thread["status"], "ok");
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
    assert_eq!(cpu1["status"], "blow-up", "{cpu1:?}");
    assert!(cpu1["reason"].contains("particle"), "{cpu1:?}");
    for r in rows.iter().filter(|r| r["status"] != "ok") {
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
    for r in &rows {
        // A job running late gives back the fill's blocks, never those `--repeats` asked for.
        let reps: usize = r["repeats"].parse().expect("repeats");
        assert!(reps >= 2, "{} nx={} ran {reps} timed blocks (--repeats 2)", r["variant"], r["nx"]);
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
    assert!(m.join("scaling_cells_thread.svg").exists());
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
