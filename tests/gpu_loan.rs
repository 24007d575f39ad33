//! The GPU-loan rehearsal: `scripts/gpu-report.sh` run the way the lent machine runs it (no
//! cargo on PATH, the binary from `SPHLAB_BIN`), on lavapipe with `--allow-cpu-adapter` (the
//! `rehearsal` scale): the archive holds provenance, the smoke result, scaling records at two
//! sizes or more, E4, and every later part's records or the reason it has none; a SIGTERM
//! mid-run still leaves a readable archive up to the last finished part (exit 143). The preset
//! refuses lavapipe without the flag (exit 2, naming adapter and backend) and its dry run
//! prints each part's share and sizes and writes nothing.

mod common;

use common::{gpu_or_skip, serial};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Seconds the whole rehearsal may take besides its budget (process start, adapter, archive):
/// the preset stops any part at 1.05 × the budget.
const ALLOWANCE_S: f64 = 15.0;

/// PATH without any directory that holds cargo, as on the lent machine.
fn path_without_cargo() -> String {
    let path = std::env::var("PATH").unwrap_or_default();
    let kept: Vec<&str> = path.split(':').filter(|d| !Path::new(d).join("cargo").exists()).collect();
    kept.join(":")
}

fn report_sh(args: &[&str]) -> Command {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut c = Command::new("bash");
    c.arg(Path::new(root).join("scripts/gpu-report.sh"))
        .args(args)
        .env("PATH", path_without_cargo())
        .env("SPHLAB_BIN", env!("CARGO_BIN_EXE_sphlab"))
        .stdin(Stdio::null());
    c
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// The archive's files, by path inside it, with their contents.
fn unpack(archive: &Path) -> BTreeMap<String, String> {
    let f = std::fs::File::open(archive.join("gpu-report.tar.gz")).expect("gpu-report.tar.gz");
    let mut tar = tar::Archive::new(flate2::read::GzDecoder::new(f));
    let mut out = BTreeMap::new();
    for e in tar.entries().expect("a tar archive") {
        let mut e = e.expect("entry");
        let path = e.path().expect("path").display().to_string();
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut e, &mut s);
        out.insert(path, s);
    }
    out
}

/// The archived file at `rel` inside the report directory (the archive's one top folder).
fn file<'a>(files: &'a BTreeMap<String, String>, rel: &str) -> &'a str {
    let tops: std::collections::BTreeSet<&str> = files.keys().filter_map(|k| k.split('/').next()).collect();
    assert_eq!(tops.len(), 1, "one top folder, the adapter's: {tops:?}");
    let path = format!("{}/{rel}", tops.first().unwrap());
    files.get(&path).unwrap_or_else(|| panic!("no `{path}` in the archive: {:?}", files.keys().collect::<Vec<_>>()))
}

/// `records.csv` rows as (header → column) maps.
fn rows(csv_text: &str) -> Vec<BTreeMap<String, String>> {
    let mut r = csv::Reader::from_reader(csv_text.as_bytes());
    let head: Vec<String> = r.headers().expect("header").iter().map(String::from).collect();
    r.records().map(|row| head.iter().cloned().zip(row.expect("row").iter().map(String::from)).collect()).collect()
}

/// A measured record: `ok`, or `loaded` when other work raised this machine's load average.
fn measured(r: &BTreeMap<String, String>) -> bool {
    r["status"] == "ok" || r["status"] == "loaded"
}

fn parts_json(files: &BTreeMap<String, String>) -> Vec<serde_json::Value> {
    serde_json::from_str::<Vec<serde_json::Value>>(file(files, "parts.json")).expect("parts.json")
}

#[test]
fn rehearsal_without_cargo_returns_every_part() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    drop(ctx);
    assert!(
        Command::new("bash")
            .args(["-c", "command -v cargo"])
            .env("PATH", path_without_cargo())
            .status()
            .is_ok_and(|s| !s.success()),
        "cargo is still on the PATH the rehearsal uses"
    );
    let dir = tempfile::tempdir().expect("tempdir");
    let (root, archive) = (dir.path().join("gpu"), dir.path().join("out"));
    let budget = 60.0;
    let t = Instant::now();
    let o = report_sh(&[
        "--allow-cpu-adapter",
        "--budget",
        "60s",
        "--archive",
        archive.to_str().unwrap(),
        "--out",
        root.to_str().unwrap(),
    ])
    .output()
    .expect("bash runs");
    let took = t.elapsed().as_secs_f64();
    let log = text(&o);
    assert_eq!(o.status.code(), Some(0), "{log}");
    assert!(log.contains("adapter: ") && log.contains("01-smoke share"), "adapter and plan first: {log}");
    assert!(took < 1.05 * budget + ALLOWANCE_S, "a {budget} s budget took {took:.0} s: {log}");
    let files = unpack(&archive);
    let prov: serde_json::Value = serde_json::from_str(file(&files, "provenance.json")).expect("provenance");
    for key in ["commit", "date", "gpu", "adapter_backend", "limits", "binary_sha256"] {
        assert!(!prov[key].is_null(), "provenance lacks {key}: {prov}");
    }
    assert_eq!(prov["binary_sha256"].as_str().map(str::len), Some(64));
    assert_eq!(prov["adapter_backend"], "Vulkan");
    let smoke: serde_json::Value = serde_json::from_str(file(&files, "parts/01-smoke/verify.json")).expect("smoke");
    let verdicts: Vec<&str> =
        smoke["variants"].as_array().unwrap().iter().map(|v| v["status"].as_str().unwrap()).collect();
    assert_eq!(verdicts, ["pass", "pass"], "{smoke}");
    // The walk probe: every form × two accesses at each of its two sides.
    let walk = rows(file(&files, "parts/02-walk/walk.csv"));
    assert_eq!(walk.len(), 2 * 2 * sphlab::gpu::walk_probe::FORMS.len(), "{walk:?}");
    let scaling = rows(file(&files, "parts/03-scaling/records.csv"));
    let mut gpu_sizes: Vec<&str> =
        scaling.iter().filter(|r| r["backend"] == "gpu" && measured(r)).map(|r| r["nx"].as_str()).collect();
    gpu_sizes.dedup();
    assert!(!gpu_sizes.is_empty(), "scaling: no GPU record is ok: {scaling:?}");
    if gpu_sizes.len() < 2 {
        // How many sizes fit the part's share depends on the machine's speed at the time; a size
        // not timed must be one the budget dropped (the plan) or skipped while running (the
        // outcome), or the part was cut at the end of its share.
        let cut = parts_json(&files).iter().any(|p| p["name"] == "03-scaling" && p["status"] == "cut");
        let said = files
            .iter()
            .filter(|(k, _)| k.ends_with("parts/03-scaling/summary.md"))
            .any(|(_, s)| s.contains("dropped for it") || s.contains("Not run because"));
        assert!(cut || said, "scaling: GPU records at {gpu_sizes:?} only, and nothing says why");
    }
    let e4 = rows(file(&files, "parts/04-e4/records.csv"));
    // A GPU row timed; or, on a machine others load (the CPU rows say so), every GPU row left
    // out for the budget: dropped by the plan, which the calibration sizes on that load, or not
    // started because the running estimate (the loaded CPU rows' overrun) said it would not fit.
    let gpu_timed = e4.iter().any(|r| r["experiment"] == "e4" && measured(r) && r["backend"] == "gpu");
    let loaded = e4.iter().any(|r| r["backend"] != "gpu" && r["status"] == "loaded");
    let gpu_rows: Vec<_> = e4.iter().filter(|r| r["backend"] == "gpu").collect();
    let all_dropped = !gpu_rows.is_empty()
        && gpu_rows.iter().all(|r| {
            r["status"] == "skipped"
                && (r["reason"].starts_with("dropped by the plan")
                    || r["reason"].starts_with("not run: the running estimate would have overrun"))
        });
    assert!(gpu_timed || (loaded && all_dropped), "e4: no GPU row timed: {e4:?}");
    // Every part: done with its output, or a reason it has none.
    let parts = parts_json(&files);
    assert_eq!(parts.len(), 11, "{parts:?}");
    for p in &parts {
        let (name, status, note) =
            (p["name"].as_str().unwrap(), p["status"].as_str().unwrap(), p["note"].as_str().unwrap());
        assert!(["done", "cut", "failed", "skipped"].contains(&status), "{name}: {status}");
        assert!(!note.is_empty(), "{name} ({status}) says nothing about its result");
        if status == "done" {
            assert!(files.keys().any(|k| k.contains(&format!("parts/{name}/"))), "{name}: done but no output archived");
        }
    }
    let md = std::fs::read_to_string(archive.join("summary.md")).expect("summary.md beside the archive");
    assert!(md.contains("| `01-smoke` |") && md.contains("finished after"), "{md}");
    assert!(md.contains("CPU adapter: this run rehearses the pipeline"), "{md}");
    assert!(!files.keys().any(|k| k.contains("particles_")), "no snapshots in the archive");
}

#[test]
fn sigterm_leaves_the_archive_complete_to_the_last_finished_part() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    drop(ctx);
    let dir = tempfile::tempdir().expect("tempdir");
    let (root, archive) = (dir.path().join("gpu"), dir.path().join("out"));
    let mut child = report_sh(&[
        "--allow-cpu-adapter",
        "--budget",
        "5m",
        "--archive",
        archive.to_str().unwrap(),
        "--out",
        root.to_str().unwrap(),
    ])
    .stdout(Stdio::null())
    .stderr(Stdio::piped())
    .spawn()
    .expect("bash runs");
    // Wait (a hang guard, not a speed claim) until the smoke test has finished and is archived.
    let t0 = Instant::now();
    let smoke_done = || {
        std::fs::read_to_string(archive.join("summary.md"))
            .is_ok_and(|md| md.lines().any(|l| l.starts_with("| `01-smoke` |") && l.contains("| done |")))
    };
    while !smoke_done() {
        assert!(t0.elapsed() < Duration::from_secs(300), "hang guard: the smoke test never finished");
        assert!(child.try_wait().expect("wait").is_none(), "the preset ended before the smoke test was archived");
        std::thread::sleep(Duration::from_millis(100));
    }
    // The script `exec`s sphlab: the child's pid is the preset's.
    let ok = Command::new("kill").args(["-TERM", &child.id().to_string()]).status().expect("kill");
    assert!(ok.success());
    let o = child.wait_with_output().expect("wait");
    assert_eq!(o.status.code(), Some(143), "{}", text(&o));
    let files = unpack(&archive);
    assert!(file(&files, "provenance.json").contains("binary_sha256"));
    assert!(file(&files, "parts/01-smoke/verify.json").contains("pass"));
    let parts = parts_json(&files);
    assert_eq!(parts[0]["status"], "done");
    assert!(parts.iter().skip(1).all(|p| p["status"] != "pending"), "every part says where it stopped: {parts:?}");
    let md = std::fs::read_to_string(archive.join("summary.md")).expect("summary.md");
    assert!(md.contains("interrupted by a signal"), "{md}");
}

#[test]
fn preset_refuses_a_cpu_adapter_and_dry_runs_its_plan() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if ctx.adapter_info.device_type != wgpu::DeviceType::Cpu {
        eprintln!("SKIP: the adapter is a real GPU; the refusal is tested on lavapipe");
        return;
    }
    drop(ctx);
    let dir = tempfile::tempdir().expect("tempdir");
    let root: PathBuf = dir.path().join("gpu");
    let o = report_sh(&["--out", root.to_str().unwrap()]).output().expect("bash runs");
    let e = text(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("CPU adapter") && e.contains("--allow-cpu-adapter") && e.contains("backend Vulkan"), "{e}");
    let o = report_sh(&["--allow-cpu-adapter", "--dry-run", "--budget", "90s", "--out", root.to_str().unwrap()])
        .output()
        .expect("bash runs");
    let e = text(&o);
    assert!(o.status.success(), "{e}");
    for needle in [
        "adapter: ",
        "limits: ",
        "budget: 90 s; scale: rehearsal",
        "01-smoke share",
        "02-walk share",
        "walk-probe --sides 16,32",
        "03-scaling share",
        "--sizes 16,32,64 --probe-sizes 16,32",
        "04-e4 share",
        "--e4-sizes 45",
        "08-verify share",
        "09-young share",
        "10-chunks share",
        "--gpu-binding 256K",
        "sphlab validate impact",
    ] {
        assert!(e.contains(needle), "plan lacks `{needle}`: {e}");
    }
    assert!(!root.exists(), "a dry run writes nothing");
}
