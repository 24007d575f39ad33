//! GPU device timing (`gpu::timing`): with stage timing on, every dispatched stage has a positive
//! device time, only the stages the scene activates appear, and the stage sum fits inside the
//! batch time, which fits in the wall clock of the same steps; batch timing keeps the fused
//! engine (the dispatches of an untimed run) and reports no stages; with timing off nothing is
//! reported; and timing never changes the physics (bit-identical states).

mod common;

use common::{gpu_or_skip, scene, serial};
use sphlab::backend::{Backend, DeviceTiming};
use sphlab::gpu::solver::GpuSolver;
use sphlab::gpu::variant::VariantSpec;
use sphlab::gpu::GpuContext;
use sphlab::scene::Scene;
use sphlab::stage::Stage;
use std::sync::Arc;
use std::time::Instant;

fn has_timestamps(ctx: &GpuContext) -> bool {
    let ok = ctx.has(wgpu::Features::TIMESTAMP_QUERY);
    if !ok {
        eprintln!("SKIP: adapter {} has no TIMESTAMP_QUERY", ctx.describe());
    }
    ok
}

/// Stage names a step of `g` may record: the force stages, the integrator's, `check`, the cell
/// count with (on small grids) the cell scan, and `reduce_max` under automatic dt.
fn allowed(g: &GpuSolver<f32>, s: &Scene) -> Vec<&'static str> {
    let mut v = g.model.stages.names();
    v.extend(integrator_stages(s));
    v.push(Stage::Check.name());
    if g.spec().search != sphlab::neighbours::SearchKind::Direct {
        v.push(Stage::CellCount.name());
        if g.cells() <= sphlab::gpu::plan::FUSED_SCAN_CELLS {
            v.push(Stage::CellScan.name());
        }
    }
    if g.model.dt_fixed <= 0.0 {
        v.push(Stage::ReduceMax.name());
    }
    v
}

fn integrator_stages(s: &Scene) -> [&'static str; 2] {
    let (open, close) = Stage::step_pair(s.time.integrator);
    [open.name(), close.name()]
}

#[test]
fn stage_times_are_positive_scene_specific_and_within_wall_clock() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if !has_timestamps(&ctx) {
        return;
    }
    let ctx = Arc::new(ctx);
    let cases: &[(&str, &[&str], &str)] = &[
        ("oscillating-drop", &[], "cells.thread.recomputed.f32"),
        ("poiseuille", &[], "cells.thread.recomputed.f32"),
        ("oscillating-drop", &[], "tracking.block-tree.fixed.cached.f32"),
    ];
    for &(name, sets, id) in cases {
        let (s, l) = scene(name, sets);
        let spec: VariantSpec = id.parse().unwrap();
        let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
        assert!(g.enable_timestamps(DeviceTiming::Stages), "adapter has TIMESTAMP_QUERY");
        g.step().unwrap();
        g.sync();
        let _ = g.device_time().expect("device time while enabled");
        let steps = 10;
        let t0 = Instant::now();
        for _ in 0..steps {
            g.step().unwrap();
        }
        g.sync();
        let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        let d = g.device_time().expect("device time while enabled");
        println!(
            "{name} {id}: stages {:.3} ms, batches {:.3} ms, wall {wall_ms:.3} ms over {steps} steps",
            d.stage_sum_ms, d.batch_ms
        );
        for (stage, ms) in &d.stages {
            println!("  {stage:<20} {ms:>9.4} ms");
        }
        assert_eq!(d.steps, steps);
        let allowed = allowed(&g, &s);
        for (stage, ms) in &d.stages {
            assert!(allowed.contains(&stage.as_str()), "{name} {id}: stage `{stage}` not active in this scene");
            assert!(*ms > 0.0, "{name} {id}: stage `{stage}` has {ms} ms");
        }
        let reported: Vec<&str> = d.stages.iter().map(|(s, _)| s.as_str()).collect();
        let core =
            [Stage::NeighbourSearch, Stage::NumberDensity, Stage::EquationOfState, Stage::Acceleration, Stage::Check]
                .map(Stage::name);
        for stage in core.iter().chain(&integrator_stages(&s)) {
            assert!(reported.contains(stage), "{name} {id}: `{stage}` missing from {reported:?}");
        }
        // On a small grid the integrator's last workgroup scans the cell counts it fused.
        let scans = g.spec().search != sphlab::neighbours::SearchKind::Direct
            && g.cells() <= sphlab::gpu::plan::FUSED_SCAN_CELLS;
        assert_eq!(reported.contains(&Stage::CellScan.name()), scans, "{name} {id}: {reported:?}");
        let two_phase = name == "oscillating-drop";
        let colour = Stage::ColourGradient.name();
        assert_eq!(reported.contains(&colour), two_phase, "{name}: {colour} {reported:?}");
        let sum: f64 = d.stages.iter().map(|s| s.1).sum();
        assert!((sum - d.stage_sum_ms).abs() <= 1e-9 * sum.max(1.0));
        // The batches bracket every stage pass; device work cannot exceed the wall clock (slack
        // for the two clock domains).
        assert!(d.batch_ms >= 0.99 * d.stage_sum_ms, "{name} {id}: batches {} < stages {sum} ms", d.batch_ms);
        assert!(d.batch_ms <= wall_ms * 1.05 + 0.5, "{name} {id}: device {} ms > wall {wall_ms} ms", d.batch_ms);
        // A second call covers only what ran since the first.
        let again = g.device_time().expect("still enabled");
        assert!(again.stages.is_empty() && again.steps == 0 && again.stage_sum_ms == 0.0 && again.batch_ms == 0.0);
    }
}

#[test]
fn batch_timing_keeps_the_fused_engine_and_fits_the_wall_clock() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if !has_timestamps(&ctx) {
        return;
    }
    let ctx = Arc::new(ctx);
    let (s, l) = scene("oscillating-drop", &[]);
    // Dispatches of 8 steps in one submission, and the device time reported for them.
    let run = |what: DeviceTiming| {
        let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        g.enable_timestamps(what);
        g.advance(8).unwrap();
        g.sync();
        let _ = g.device_time();
        let c0 = g.engine_counters();
        let t0 = Instant::now();
        g.advance(8).unwrap();
        g.sync();
        let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        let dispatches = g.engine_counters().since(&c0).dispatches;
        (dispatches, g.device_time(), wall_ms)
    };
    let (untimed, none, _) = run(DeviceTiming::Off);
    let (batch, d, wall_ms) = run(DeviceTiming::Batch);
    let (unfused, _, _) = run(DeviceTiming::Stages);
    assert!(none.is_none());
    assert_eq!(batch, untimed, "batch timing changed the dispatches (the fused engine)");
    assert!(unfused > batch, "stage timing records every stage its own pass: {unfused} vs {batch} dispatches");
    let d = d.expect("device time while enabled");
    assert!(d.stages.is_empty() && d.stage_sum_ms == 0.0, "batch timing times no stage: {:?}", d.stages);
    assert_eq!(d.steps, 8);
    assert!(d.batch_ms > 0.0 && d.batch_ms <= wall_ms * 1.05 + 0.5, "batches {} ms, wall {wall_ms} ms", d.batch_ms);
}

#[test]
fn timing_off_reports_nothing_and_does_not_change_results() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene("sessile-90", &["contact.mode=a", "domain.nx=33"]);
    let run = |what: DeviceTiming| {
        let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        let enabled = g.enable_timestamps(what);
        let on = what != DeviceTiming::Off;
        assert_eq!(enabled, on && ctx.has(wgpu::Features::TIMESTAMP_QUERY));
        for _ in 0..12 {
            g.step().unwrap();
        }
        let d = g.device_time();
        assert_eq!(d.is_some(), enabled);
        if !on {
            assert!(g.take_stage_times().unwrap().is_none());
        }
        let f = g.frame();
        (f.pos, f.vel, f.acc, f.rho, f.contacts)
    };
    let off = run(DeviceTiming::Off);
    assert!(off == run(DeviceTiming::Batch), "batch timestamps changed the results");
    assert!(off == run(DeviceTiming::Stages), "stage timestamps changed the results");
    // Switching off again drops the pool.
    let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
    g.enable_timestamps(DeviceTiming::Stages);
    assert!(!g.enable_timestamps(DeviceTiming::Off));
    g.step().unwrap();
    assert!(g.device_time().is_none() && !g.timestamps_enabled());
}

#[test]
fn cpu_backend_has_no_device_time() {
    let (s, l) = scene("poiseuille", &[]);
    let mut c =
        sphlab::cpu::CpuSolver::<f64>::new(&s, &l, sphlab::exec::Exec::Serial, sphlab::neighbours::SearchKind::Cells);
    assert!(!c.enable_device_time(DeviceTiming::Batch));
    c.step().unwrap();
    assert!(c.device_time().is_none());
}

#[test]
fn study_records_device_time_and_stage_table() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let timed = ctx.has(wgpu::Features::TIMESTAMP_QUERY);
    drop(ctx);
    let dir = tempfile::tempdir().expect("tempdir");
    let opts = sphlab::study::StudyOptions {
        experiments: vec!["e4".into()],
        sizes: vec![],
        protocol: sphlab::study::timing::Protocol { steps: 2, repeats: 2, warmup_s: 0.0, latency_samples: 1 },
        variants: vec![VariantSpec::default()],
        out: dir.path().to_path_buf(),
        ..Default::default()
    };
    let recs = sphlab::study::run_study(&opts).expect("study");
    let gpu = recs.iter().find(|r| r.backend == "gpu").expect("a GPU record");
    let md = std::fs::read_to_string(dir.path().join("summary.md")).expect("summary");
    let stages = dir.path().join("stage_times.csv");
    assert!(recs.iter().filter(|r| r.backend != "gpu").all(|r| r.timing == "wall" && r.gpu_ms_per_step.is_none()));
    if !timed {
        assert!(gpu.timing == "wall" && gpu.gpu_ms_per_step.is_none() && !stages.exists());
        return;
    }
    assert_eq!(gpu.timing, "wall+timestamps");
    let d = gpu.gpu_ms_per_step.expect("device ms");
    let slowest = gpu.ms_per_step_max.expect("timed");
    assert!(d > 0.0 && d <= slowest * 1.05 + 0.5, "device {d} ms, slowest block {slowest} ms");
    assert!(gpu.stage_sum_ms_per_step.is_some_and(|x| x > 0.0), "the stage-timed block's sum");
    // Every measured GPU record carries its modelled bytes and the run's measured bandwidth.
    let (bytes, bw) = (gpu.modelled_bytes_per_step.expect("bytes"), gpu.bandwidth_gb_s.expect("bandwidth"));
    let achieved = bytes / (gpu.ms_per_step_median.expect("timed") * 1e-3) * 1e-9;
    assert!(bytes > 0.0 && bw > 0.0 && (gpu.achieved_gb_s.expect("achieved") - achieved).abs() <= 1e-9 * achieved);
    assert!((gpu.roofline_fraction.expect("fraction") - achieved / bw).abs() <= 1e-9 * achieved / bw);
    assert!(recs.iter().filter(|r| r.backend != "gpu").all(|r| r.modelled_bytes_per_step.is_none()));
    let csv = std::fs::read_to_string(stages).expect("stage_times.csv");
    assert!(csv.starts_with("experiment,variant,n,stage,device_ms_per_step,share"), "{csv}");
    // Each GPU record's stage shares (one record per E4 size) sum to 1.
    let mut shares: std::collections::BTreeMap<(String, String), f64> = Default::default();
    for l in csv.lines().skip(1) {
        let c: Vec<&str> = l.split(',').collect();
        *shares.entry((c[1].to_string(), c[2].to_string())).or_default() += c[5].parse::<f64>().unwrap();
    }
    // Every measured GPU record (`ok`, or `loaded` on a busy machine) has its stage times.
    let measured = recs.iter().filter(|r| r.backend == "gpu" && r.ms_per_step_median.is_some()).count();
    assert_eq!(shares.len(), measured, "{csv}");
    for (rec, share) in &shares {
        assert!((share - 1.0).abs() < 1e-2, "{rec:?}: shares sum to {share}");
    }
    let column = format!(",{},", Stage::ColourGradient);
    assert!(csv.contains(&column) && md.contains("device time per stage"), "{md}");
}
