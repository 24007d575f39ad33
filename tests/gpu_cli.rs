//! The GPU commands as a user runs them: `sphlab variants`, `sphlab verify` over EVERY variant on
//! `oscillating-drop` and over a cross-section of them (every value of every axis) on a Mode B
//! contact-angle scene (each must pass or be unsupported with a reason), bad ids exit 2, a GPU run writes the same outputs as a CPU run, and `sphlab study`
//! writes its records. Needs an adapter (lavapipe in CI; a missing one fails under CI).

mod common;

use sphlab::gpu::variant::VariantSpec;
use std::process::{Command, Output};

fn sphlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sphlab")).args(args).output().expect("the binary runs")
}

/// One variant per (search, mapping, accumulation), its kernel values and precision rotating
/// with the group's index: every value of every axis, at a third of the cost of all.
fn cross_section() -> Vec<VariantSpec> {
    let all = VariantSpec::all();
    let mut groups: Vec<Vec<VariantSpec>> = Vec::new();
    for s in all {
        match groups
            .iter_mut()
            .find(|g| (g[0].search, g[0].mapping, g[0].accumulation) == (s.search, s.mapping, s.accumulation))
        {
            Some(g) => g.push(s),
            None => groups.push(vec![s]),
        }
    }
    // Offset by the search's ordinal so that each search sees other rotations of the same mapping.
    let search = |s: &VariantSpec| sphlab::neighbours::SearchKind::ALL.iter().position(|x| *x == s.search).unwrap_or(0);
    groups.iter().enumerate().map(|(k, g)| g[(k + search(&g[0])) % g.len()]).collect()
}

fn verify_all(scene_args: &[&str]) {
    verify_variants(scene_args, &VariantSpec::all());
}

fn verify_variants(scene_args: &[&str], ids: &[VariantSpec]) {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().to_str().expect("utf8").to_string();
    let list = ids.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(",");
    let mut args = vec!["verify"];
    args.extend_from_slice(scene_args);
    args.extend_from_slice(&["--variants", &list, "--steps", "20", "--json", "--out", &out]);
    let o = sphlab(&args);
    let text = String::from_utf8_lossy(&o.stdout);
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("JSON ({e}): {text}"));
    let reports = doc["variants"].as_array().expect("a list of variant reports");
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("verify.json")).expect("verify.json"))
            .expect("verify.json parses");
    assert_eq!(written["variants"], doc["variants"], "--json and --out write one schema");
    assert!(doc["provenance"]["commit"].is_string() && doc["provenance"]["gpu"]["adapter"].is_string());
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
    // 24×24 instead of the default 30×30: every variant, with renumbering and many steps per
    // submit, at two thirds of the cost (the suite runs 72 variants on two scenes).
    verify_all(&["oscillating-drop", "--set", "domain.nx=24"]);
}

#[test]
fn verify_every_variant_on_a_mode_b_contact_angle_scene() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    // A cross-section (every search, mapping, accumulation, kernel-value kind and precision):
    // the drop above verifies all 72; `sphlab verify sessile-90` runs all of them here too.
    let ids = cross_section();
    let axes: [fn(&VariantSpec) -> &'static str; 5] = [
        |s| s.kernel_values.name(),
        |s| s.precision.name(),
        |s| s.search.name(),
        |s| s.mapping.name(),
        |s| s.accumulation.name(),
    ];
    for axis in axes {
        let mut want: Vec<&str> = VariantSpec::all().iter().map(axis).collect();
        let mut got: Vec<&str> = ids.iter().map(axis).collect();
        want.sort();
        want.dedup();
        got.sort();
        got.dedup();
        assert_eq!(got, want, "the cross-section covers every value of each axis");
    }
    verify_variants(&["sessile-90", "--set", "domain.nx=33"], &ids);
}

/// Slot lists past the per-buffer limit are split into list chunks (`gpu::list_chunks`): with
/// `--gpu-binding` making lavapipe an adapter of small bindings, the cached kernel values of the
/// thread, block and subgroup mappings (f32 and f64) and slot lists with recomputed values run
/// in several chunks (1,024 particles with the walls; 64 slots × 8 B of f32 cache: 256
/// particles per 128 KiB chunk) and still verify against the CPU, stage by stage and after 20 steps; without the cap
/// they take one chunk. So do the pooled slot lists.
#[test]
fn verify_passes_with_the_lists_in_chunks() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    let cached = "cells.thread.cached.f32,direct.subgroup.cached.f32,cells.block-atomic.cas.cached.f32";
    // The pooled slot layout (`gpu::pooled_lists`: 49 words per particle, 392 B of f32 and
    // 784 B of f64 per particle with the cache) in chunks and whole.
    let pooled = "cells.thread.cached.f32.pooled,cells.subgroup.cached.f64.pooled,\
                   tracking.block-atomic.fixed.cached.f64.masks.pooled";
    let runs: [(Option<&str>, String, &[u64]); 5] = [
        (Some("128K"), format!("{cached},cells.subgroup.recomputed.f32.slots"), &[4, 4, 4, 2]),
        (Some("256K"), "cells.block-tree.fixed.cached.f64,cells.thread.cached.f64".into(), &[4, 4]),
        (None, "cells.thread.cached.f64".into(), &[1]),
        (Some("256K"), pooled.into(), &[2, 4, 4]),
        (None, "cells.block-tree.native.cached.f32.pooled".into(), &[1]),
    ];
    for (cap, ids, chunks) in runs {
        let mut args = vec!["verify", "oscillating-drop", "--set", "domain.nx=24", "--variants", &ids];
        args.extend_from_slice(&["--steps", "20", "--per-stage", "--json"]);
        if let Some(c) = cap {
            args.extend_from_slice(&["--gpu-binding", c]);
        }
        let o = sphlab(&args);
        let text = String::from_utf8_lossy(&o.stdout);
        let doc: serde_json::Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("JSON ({e}): {text}"));
        let reports = doc["variants"].as_array().expect("reports");
        assert_eq!(reports.len(), chunks.len());
        for (r, want) in reports.iter().zip(chunks) {
            assert_eq!(r["status"], "pass", "{cap:?}: {}", serde_json::to_string_pretty(r).unwrap_or_default());
            assert_eq!(r["list_chunks"].as_u64(), Some(*want), "{cap:?}: {}", r["variant"]);
            let (id, ran) = (r["variant"].as_str().unwrap_or(""), r["ran"].as_str().unwrap_or(""));
            assert_eq!(id.ends_with(".pooled"), ran.ends_with(".pooled"), "{id} ran as {ran}");
        }
        assert_eq!(o.status.code(), Some(0));
    }
    let o = sphlab(&["verify", "--variants", "cells.thread.cached.f32", "--gpu-binding", "1K"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--gpu-binding: must be at least 64K"));
    // A run takes the same cap (its chunked lists then stepped and checked as any run's), and
    // its summary records it; the study refuses it (its records time the adapter as it is).
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("run");
    let run = |cap: &str| {
        let mut a = vec!["run", "--backend", "gpu", "--variant", "cells.subgroup.cached.f64.pooled", "--set"];
        a.extend_from_slice(&["domain.nx=24", "--steps", "10", "--quiet", "--gpu-binding", cap]);
        sphlab(&[a.as_slice(), &["--out", out.to_str().expect("utf8")]].concat())
    };
    let o = run("256K");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
    assert_eq!(
        (summary["status"].as_str(), summary["options"]["limits"]["gpu_binding"].as_u64()),
        (Some("ok"), Some(256 << 10))
    );
    assert_eq!(run("1K").status.code(), Some(2));
    let o = sphlab(&["study", "--dry-run", "--gpu-binding", "1M"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--gpu-binding: not for the study"));
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
    for v in VariantSpec::all() {
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
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
        let engine = &summary["gpu_engine"];
        if backend == "gpu" {
            // The variant as it ran (the default has no list-format choice: its id unchanged).
            assert_eq!(summary["ran"], "cells.thread.recomputed.f32", "{summary}");
            assert!(summary["peak_neighbours"].is_null(), "the GPU lists report only an overflow");
            // Device bytes from the memory plan, modelled traffic, and (with timestamps) the
            // measured bandwidth and the roofline fraction.
            assert!(engine["device_bytes"].as_u64().unwrap_or(0) > 0, "{engine}");
            assert!(engine["modelled_bytes_per_evaluation"].as_f64().unwrap_or(0.0) > 0.0, "{engine}");
            if let Some(bw) = engine["bandwidth"]["gb_per_s"].as_f64() {
                assert!(bw > 0.0 && bw.is_finite(), "{engine}");
                let f = engine["roofline_fraction"].as_f64().expect("a fraction with a bandwidth");
                assert!(f > 0.0 && f.is_finite(), "{engine}");
            }
        } else {
            assert!(engine.is_null(), "CPU runs have no GPU engine figures");
            assert!(summary["peak_neighbours"].as_u64().unwrap_or(0) > 0, "CPU runs record their peak neighbours");
        }
        let engine = &summary["engine"];
        if backend == "gpu" {
            // Rows every 10 steps cut the batches: 3 submissions and 3 readbacks for 30 steps.
            let c = &engine["counters"];
            assert_eq!((c["steps"].as_u64(), c["submits"].as_u64()), (Some(30), Some(3)), "{engine}");
            assert_eq!((c["readbacks"].as_u64(), c["writes"].as_u64()), (Some(3), Some(0)), "{engine}");
            assert!(engine["per_step"]["dispatches"].as_f64().is_some_and(|d| d > 10.0), "{engine}");
        } else {
            assert!(engine.is_null(), "the CPU has no engine counters: {engine}");
        }
        rows.push(series);
    }
    let head = |s: &str| s.lines().next().unwrap_or("").to_string();
    assert_eq!(head(&rows[0]), head(&rows[1]), "same columns");
    assert_eq!(rows[0].lines().count(), rows[1].lines().count(), "same rows");
}

/// A GPU run that needs more than the adapter allows is refused with exit 2 and the numbers
/// (buffer, bytes needed, the limit) before any device buffer or output directory exists: a
/// tracking variant whose forced 96-slot candidate lists pass the adapter's binding limit, and a run whose
/// total passes a stated `--gpu-memory`.
#[test]
fn gpu_runs_beyond_the_adapter_exit_2_with_numbers() {
    let _g = common::serial();
    let Some(ctx) = common::gpu_or_skip() else { return };
    let cap = ctx.limits.max_storage_buffer_binding_size.min(ctx.limits.max_buffer_size);
    // Forced slot candidates hold 96 slots × 4 B per particle in one binding (the list slots and
    // cached values would be split into list chunks, and unforced the candidates would take
    // masks); oscillating-drop has at least nx² particles.
    let nx = ((cap / 384) as f64).sqrt().ceil() as u64 + 8;
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let set = format!("domain.nx={nx}");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run",
            "oscillating-drop",
            "--backend",
            "gpu",
            "--steps",
            "1",
            "--quiet",
            "--set",
            "time.dt_policy=scale",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", out.to_str().expect("utf8")]);
        sphlab(&args)
    };
    let o = run(&["--variant", "tracking.thread.cached.f32.slots", "--set", &set]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("`cand`") && err.contains(&cap.to_string()) && err.contains("max_"), "{err}");
    assert!(!out.exists(), "nothing is written before the refusal");
    let o = run(&["--gpu-memory", "1M", "--set", "domain.nx=200"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("device memory") && err.contains("1048576 bytes") && err.contains("--gpu-memory"), "{err}");
    assert!(!out.exists());
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
    assert!(dir.path().join("summary.md").exists());
    // Only `ok` records are plotted as timings (on a loaded machine the GPU record is `loaded`).
    let ok_gpu = csv.lines().any(|l| l.contains(",cells.thread.recomputed.f32,ok,"));
    assert_eq!(dir.path().join("scaling_cells_thread.svg").exists(), ok_gpu, "{csv}");
}

/// `sphlab study --experiments e2,e3` at tiny sizes: a record for every hybrid and every
/// (configuration, budget), each verified; the bytes copied per step rise as more stage groups
/// live on the CPU (all-CPU copies nothing); the halo grows as the budget shrinks.
#[test]
fn study_e2_e3_records_every_hybrid_and_budget() {
    let _g = common::serial();
    if common::gpu_or_skip().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let o = sphlab(&[
        "study",
        "--experiments",
        "e2,e3",
        "--steps",
        "2",
        "--e2-nx",
        "12",
        "--e3-nx",
        "16",
        "--e3-steps",
        "2",
        "--e3-budgets",
        "120,240",
        "--out",
        dir.path().to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut rd = csv::Reader::from_path(dir.path().join("records.csv")).expect("records.csv");
    let head = rd.headers().expect("header").clone();
    let col = |name: &str| head.iter().position(|h| h == name).unwrap_or_else(|| panic!("column {name}"));
    let rows: Vec<csv::StringRecord> = rd.records().map(|r| r.expect("row")).collect();
    let get = |r: &csv::StringRecord, c: &str| r[col(c)].to_string();
    let num = |r: &csv::StringRecord, c: &str| get(r, c).parse::<f64>().unwrap_or(f64::NAN);
    // E2: every hybrid, in order, verified and timed.
    let e2: Vec<&csv::StringRecord> = rows.iter().filter(|r| get(r, "experiment") == "e2").collect();
    let names: Vec<String> =
        sphlab::study::e2_residency::HYBRIDS.iter().map(|h| format!("hybrid.{}", h.name)).collect();
    assert_eq!(e2.iter().map(|r| get(r, "variant")).collect::<Vec<_>>(), names);
    let bytes: Vec<f64> = e2.iter().map(|r| num(r, "bytes_h2d_per_step") + num(r, "bytes_d2h_per_step")).collect();
    for r in &e2 {
        assert!(get(r, "verified").starts_with("pass"), "{:?}", r);
        assert!(num(r, "ms_per_step_median") > 0.0, "{:?}", r);
    }
    assert_eq!(bytes[0], 0.0, "all-CPU copies nothing: {bytes:?}");
    // From gpu-forces (most groups on the CPU) to gpu-all (none) the copies fall strictly.
    assert!(bytes[1..].windows(2).all(|w| w[0] > w[1] && w[1] > 0.0), "{bytes:?}");
    // E3: each configuration's unsplit run and both budgets; smaller budget, more halo.
    for c in sphlab::study::e3_subdomains::CONFIGS {
        let rs: Vec<&csv::StringRecord> =
            rows.iter().filter(|r| get(r, "experiment") == "e3" && get(r, "variant") == c.variant).collect();
        let at =
            |b: &str| rs.iter().find(|r| get(r, "budget") == b).unwrap_or_else(|| panic!("{} budget {b:?}", c.variant));
        let (unsplit, small, large) = (at(""), at("120"), at("240"));
        assert_eq!(num(unsplit, "halo_particles"), 0.0);
        for r in [small, large] {
            assert!(get(r, "verified").starts_with("pass"), "{:?}", r);
            assert!(num(r, "bytes_h2d_per_step") > 0.0 && num(r, "device_bytes") > 0.0, "{:?}", r);
        }
        assert!(num(small, "halo_particles") > num(large, "halo_particles"), "{} halo", c.variant);
        assert!(num(small, "subdomains") > num(large, "subdomains"), "{} subdomains", c.variant);
        assert!(num(small, "halo_particles") > 0.0);
    }
    for f in ["fig6_8_residency.svg", "fig6_9_subdomains.svg", "summary.md"] {
        assert!(dir.path().join(f).exists(), "{f}");
    }
}
