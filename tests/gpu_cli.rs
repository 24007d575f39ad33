//! The GPU commands as a user runs them: `sphlab variants`, `sphlab verify` over EVERY variant on
//! `oscillating-drop` and on a Mode B contact-angle scene (each must pass or be unsupported with a
//! reason), bad ids exit 2, a GPU run writes the same outputs as a CPU run, and `sphlab study`
//! writes its records. Needs an adapter (lavapipe in CI; a missing one fails under CI).

mod common;

use std::process::{Command, Output};

fn sphlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sphlab")).args(args).output().expect("the binary runs")
}

fn verify_all(scene_args: &[&str]) {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().to_str().expect("utf8").to_string();
    let mut args = vec!["verify"];
    args.extend_from_slice(scene_args);
    args.extend_from_slice(&["--variants", "all", "--steps", "20", "--json", "--out", &out]);
    let o = sphlab(&args);
    let text = String::from_utf8_lossy(&o.stdout);
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("JSON ({e}): {text}"));
    let reports = doc["variants"].as_array().expect("a list of variant reports");
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("verify.json")).expect("verify.json"))
            .expect("verify.json parses");
    assert_eq!(written["variants"], doc["variants"], "--json and --out write one schema");
    assert!(doc["provenance"]["commit"].is_string() && doc["provenance"]["gpu"]["adapter"].is_string());
    let ids = sphlab::gpu::variant::VariantSpec::all();
    assert_eq!(reports.len(), ids.len(), "every variant is reported");
    let mut passed = 0;
    for r in reports {
        let (v, status, reason) =
            (&r["variant"], r["status"].as_str().unwrap_or(""), r["reason"].as_str().unwrap_or(""));
        match status {
            "pass" => passed += 1,
            "unsupported" => assert!(!reason.is_empty(), "{v}: unsupported needs a reason"),
            _ => panic!("{v}: {status}: {reason}\n{}", serde_json::to_string_pretty(r).unwrap_or_default()),
        }
    }
    eprintln!("{scene_args:?}: {passed} of {} variants pass", reports.len());
    assert!(passed >= 4, "at least the thread variants (direct/cells × f32/f64) pass");
    assert_eq!(o.status.code(), Some(0), "verify exits 0 when nothing fails: {}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(dir.path().join("verify.csv")).expect("verify.csv");
    assert!(csv.lines().count() > reports.len(), "one row per check");
    assert!(
        csv.contains("llvmpipe") || csv.lines().nth(1).is_some_and(|l| l.split(',').count() >= 12),
        "adapter recorded"
    );
}

#[test]
fn verify_every_variant_on_the_oscillating_drop() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    verify_all(&["oscillating-drop"]);
}

#[test]
fn verify_every_variant_on_a_mode_b_contact_angle_scene() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    verify_all(&["sessile-90", "--set", "domain.nx=33"]);
}

#[test]
fn variants_lists_every_id_and_bad_ids_exit_2() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    let o = sphlab(&["variants"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for v in sphlab::gpu::variant::VariantSpec::all() {
        assert!(text.contains(&v.to_string()), "{v} listed");
    }
    let o = sphlab(&["verify", "--variants", "cells.warp.recomputed.f32"]);
    assert_eq!(o.status.code(), Some(2), "bad id: {}", String::from_utf8_lossy(&o.stderr));
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("r");
    let o = sphlab(&["run", "--backend", "gpu", "--variant", "nope", "--out", out.to_str().expect("utf8")]);
    assert_eq!(o.status.code(), Some(2), "bad variant in run");
}

#[test]
fn a_gpu_run_writes_the_same_outputs_as_a_cpu_run() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let mut rows = Vec::new();
    for backend in ["cpu", "gpu"] {
        let out = dir.path().join(backend);
        // A GPU variant's precision is part of its id: --precision applies to the CPU only.
        let precision: &[&str] = if backend == "cpu" { &["--precision", "f32"] } else { &[] };
        let o = sphlab(
            &[
                &[
                    "run",
                    "sessile-90",
                    "--set",
                    "domain.nx=26",
                    "--steps",
                    "30",
                    "--set",
                    "output.every=10",
                    "--backend",
                    backend,
                    "--out",
                    out.to_str().expect("utf8"),
                    "--quiet",
                ],
                precision,
            ]
            .concat(),
        );
        assert!(o.status.success(), "{backend}: {}", String::from_utf8_lossy(&o.stderr));
        let series = std::fs::read_to_string(out.join("series.csv")).expect("series");
        assert!(out.join("particles_00000030.csv").exists() && out.join("summary.json").exists());
        rows.push(series);
    }
    let head = |s: &str| s.lines().next().unwrap_or("").to_string();
    assert_eq!(head(&rows[0]), head(&rows[1]), "same columns");
    assert_eq!(rows[0].lines().count(), rows[1].lines().count(), "same rows");
}

#[test]
fn study_writes_records() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let o = sphlab(&[
        "study",
        "--experiments",
        "scaling",
        "--sizes",
        "20",
        "--steps",
        "2",
        "--variants",
        "cells.thread.recomputed.f32",
        "--out",
        dir.path().to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(dir.path().join("records.csv")).expect("records");
    assert!(csv.contains("cells.thread.recomputed.f32") && csv.contains("cpu1.cells.f64"), "{csv}");
    assert!(dir.path().join("summary.md").exists() && dir.path().join("scaling_cells.svg").exists());
}
