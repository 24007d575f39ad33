//! Tests of the study's plan: the `--budget` cut (largest sizes dropped first, the fill by
//! blocks up to the repeat cap, a late job giving its blocks back) on stated probe costs.

use super::*;

fn job(nx: u32, est_s: f64, rep_s: f64) -> Job {
    Job {
        experiment: "scaling".into(),
        nx,
        n: (nx * nx) as usize,
        id: crate::study::measured::reference(Precision::F64),
        threads: 1,
        est_s,
        rep_s,
        extra_blocks: 0,
    }
}

#[test]
fn a_budget_drops_the_largest_size_and_is_filled_block_by_block() {
    // A round of blocks (0.35 + 0.7 + 1.3 = 2.35 s) is larger than the slack the dropped size
    // leaves (0.95 × 20 − 1 − 16.5 = 1.5 s): only single blocks of the cheapest jobs fit.
    let all = vec![job(16, 4.0, 0.35), job(24, 5.0, 0.7), job(32, 7.5, 1.3), job(48, 12.0, 2.0)];
    let opts = StudyOptions { budget_s: Some(20.0), ..StudyOptions::default() };
    let sel = select(&all, &opts, 1.0);
    assert_eq!(sel.dropped_sizes, vec![48]);
    assert_eq!(sel.repeats, opts.protocol.repeats, "a whole round does not fit");
    let extra: Vec<usize> = sel.jobs.iter().map(|j| j.extra_blocks).collect();
    assert_eq!(extra, vec![2, 1, 0], "cheapest first, round by round: 0.35 + 0.7 + 0.35 = 1.4 s");
    let target = BUDGET_FILL * 20.0 - 1.0;
    assert!(sel.est_s <= target && sel.est_s > target - 0.35, "{} vs {target}", sel.est_s);
    // Without a binding budget nothing changes.
    let free = select(&all, &StudyOptions { budget_s: Some(100.0), ..StudyOptions::default() }, 1.0);
    assert!(free.dropped_sizes.is_empty() && free.jobs.iter().all(|j| j.extra_blocks == 0));
    assert_eq!(free.repeats, opts.protocol.repeats);
}

/// The whole budget logic on stated costs: probe fits → estimates → the largest size dropped
/// → a whole round of blocks raised → single blocks to the cheapest jobs. Every number below
/// is worked by hand from the stated fits, so no machine's speed enters.
#[test]
fn stated_probe_costs_give_the_planned_drops_blocks_and_total() {
    // cpu1: 0 + 2e-3 ms·N; GPU: 2 ms + 2e-2 ms·N; first GPU build 1.5 s (0.15 s after);
    // layout free; the probe took 2 s. Protocol: K = 2, 2 repeats, 0.2 s warm-up, 3 latency
    // steps, so a job costs build + 9·ms + max(0.2 s, 2·ms) (GPU: 11·ms, with the stage-timed
    // block) and a block 2·ms.
    let probe = Probe {
        cpu1: Fit { a_ms: 0.0, b_ms: 2e-3 },
        cpu: Fit { a_ms: 0.0, b_ms: 2e-3 },
        gpu: Some(Fit { a_ms: 2.0, b_ms: 2e-2 }),
        gpu_build_s: 1.5,
        layout_s_per_particle: 0.0,
        seconds: 2.0,
    };
    let proto = Protocol { steps: 2, repeats: 2, warmup_s: 0.2, latency_samples: 3 };
    let gpu = BackendId::Gpu(VariantSpec::default());
    let mut all = Vec::new();
    for nx in [16, 32, 64, 128] {
        for id in [crate::study::measured::reference(Precision::F64), gpu] {
            all.push(Job { id, ..job(nx, 0.0, 0.0) });
        }
    }
    probe.estimate(&mut all, &proto);
    // nx = 16 (N = 256): cpu1 0.512 ms/step → 0.004608 + 0.2 s; GPU 7.12 ms → 1.5 + 0.07832 + 0.2 s.
    // nx = 128 (N = 16384): GPU 329.68 ms → 0.15 + 3.62648 + 0.65936 s.
    let want = [0.204608, 1.77832, 0.218432, 0.59728, 0.273728, 1.27312, 0.494912, 4.43584];
    for (j, w) in all.iter().zip(want) {
        assert!((j.est_s - w).abs() < 1e-9, "{} nx={}: {} s, by hand {w} s", j.id, j.nx, j.est_s);
    }
    assert!((all[7].rep_s - 0.65936).abs() < 1e-9);
    // 8 s budget: all jobs are 2 + 9.27624 s, without nx = 128 2 + 4.345488 s.
    let budget = 8.0;
    let opts = StudyOptions { budget_s: Some(budget), protocol: proto, ..StudyOptions::default() };
    let sel = select(&all, &opts, probe.seconds);
    assert_eq!(sel.dropped_sizes, vec![128]);
    assert_eq!(sel.jobs.len(), 6);
    // Room 0.95·8 − 2 − 4.345488 = 1.254512 s; a round of blocks is 0.248544 s, so 5 rounds
    // (cap 4 × 2 = 8 blocks) → 7 repeats; the 0.011792 s left buys one block each for the
    // two cheapest jobs (CPU nx = 16 and 32, 0.00512 s), not for GPU nx = 16 (0.01424 s).
    assert_eq!(sel.repeats, 7);
    let extra: Vec<usize> = sel.jobs.iter().map(|j| j.extra_blocks).collect();
    assert_eq!(extra, vec![1, 0, 1, 0, 0, 0]);
    let predicted = probe.seconds + sel.est_s;
    assert!((sel.est_s - 5.593328).abs() < 1e-9, "{}", sel.est_s);
    assert!((0.8 * budget..=1.2 * budget).contains(&predicted), "predicted {predicted} s of {budget} s");
    assert!(predicted <= BUDGET_FILL * budget + 1e-9, "aimed at most at the fill target");
}

#[test]
fn a_late_job_gives_back_its_fill_blocks_before_it_is_dropped() {
    // 4 s planned with 8 blocks of 0.5 s; --repeats asked for 2.
    let j = job(96, 4.0, 0.5);
    assert_eq!(blocks_that_fit(&j, 8, 2, 5.0, 1.0), Some(8), "on time: as planned");
    assert_eq!(blocks_that_fit(&j, 8, 2, 3.0, 1.0), Some(6), "2 blocks late: 2 given back");
    // Running 20 % slow: 8 blocks are 4.8 s, 5 blocks (2.5 s) × 1.2 = 3.0 s fit in 3.1 s.
    assert_eq!(blocks_that_fit(&j, 8, 2, 3.1, 1.2), Some(5));
    assert_eq!(blocks_that_fit(&j, 8, 2, 1.0, 1.0), Some(2), "down to --repeats exactly: 1 s");
    assert_eq!(blocks_that_fit(&j, 8, 2, 0.99, 1.0), None, "never below --repeats: dropped");
    assert_eq!(blocks_that_fit(&j, 2, 2, 0.99, 1.0), None);
}

#[test]
fn a_budget_below_the_smallest_size_keeps_the_jobs_that_fit() {
    // One size of four 3 s jobs, 1 s spent, 8 s budget: the first two fit (1 + 3 + 3 = 7).
    let all = vec![job(45, 3.0, 0.1), job(45, 3.0, 0.1), job(45, 3.0, 0.1), job(45, 3.0, 0.1)];
    let opts = StudyOptions { budget_s: Some(8.0), ..StudyOptions::default() };
    let sel = select(&all, &opts, 1.0);
    assert!(sel.dropped_sizes.is_empty());
    assert_eq!((sel.jobs.len(), sel.dropped_jobs), (2, 2));
    // Two sizes: the larger goes whole first, then the smaller is trimmed.
    let all = vec![job(45, 3.0, 0.1), job(45, 3.0, 0.1), job(45, 3.0, 0.1), job(100, 1.0, 0.1)];
    let sel = select(&all, &opts, 1.0);
    assert_eq!(sel.dropped_sizes, vec![100]);
    assert_eq!((sel.jobs.len(), sel.dropped_jobs), (2, 1));
    // A costly job early does not shut out cheaper ones after it.
    let all = vec![job(45, 2.0, 0.1), job(45, 30.0, 0.1), job(45, 3.0, 0.1), job(45, 3.0, 0.1)];
    let sel = select(&all, &opts, 1.0);
    let kept: Vec<f64> = sel.jobs.iter().map(|j| j.est_s).collect();
    assert_eq!((kept, sel.dropped_jobs), (vec![2.0, 3.0], 2));
}

#[test]
fn a_starved_size_keeps_references_then_gpu_rows_before_other_cpu_rows() {
    let with = |id: &str, est_s: f64| Job { id: id.parse().unwrap(), ..job(45, est_s, 0.1) };
    // Run order: the all-core CPU, the two references, a second CPU search, two GPU variants.
    let all = vec![
        with("cpu.cells.f64", 2.0),
        with("cpu1.cells.f32", 1.0),
        with("cpu1.cells.f64", 1.0),
        with("cpu1.tracking.f64", 1.0),
        with("direct.thread.recomputed.f32", 50.0),
        with("cells.thread.recomputed.f32", 4.0),
    ];
    let opts = StudyOptions { budget_s: Some(8.0), ..StudyOptions::default() };
    let sel = select(&all, &opts, 1.0);
    let kept: Vec<String> = sel.jobs.iter().map(|j| j.id.to_string()).collect();
    // 7 s left: the references (2 s), the GPU row that fits (4 s), then one CPU row (1 s);
    // the all-core row (2 s) no longer fits.
    // They run in that order: a study running late skips the last, least needed rows.
    assert_eq!(kept, ["cpu1.cells.f32", "cpu1.cells.f64", "cells.thread.recomputed.f32", "cpu1.tracking.f64"]);
    assert_eq!(sel.dropped_jobs, 2);
}

#[test]
fn the_fill_stops_at_the_repeat_cap() {
    let all = vec![job(16, 1.0, 0.01), job(96, 100.0, 1.0)];
    let opts = StudyOptions { budget_s: Some(20.0), ..StudyOptions::default() };
    let sel = select(&all, &opts, 0.0);
    assert_eq!(sel.dropped_sizes, vec![96]);
    let cap = MAX_REPEAT_FACTOR * opts.protocol.repeats;
    assert_eq!(sel.repeats + sel.jobs[0].extra_blocks, cap);
}

#[test]
fn a_direct_search_multiplies_the_per_particle_term_only() {
    // A GPU-like fit: a 1 ms floor and 0.1 µs per particle at the cell search's ~50 candidates.
    let f = Fit { a_ms: 1.0, b_ms: 1e-4 };
    assert!((f.ms(5000.0, false) - 1.5).abs() < 1e-12);
    // 100× the candidates: 1 + 0.5 × 100, not (1 + 0.5) × 100.
    assert!((f.ms(5000.0, true) - 51.0).abs() < 1e-9);
    // Below NEIGHBOURS particles a direct search visits no more than the cell search.
    assert!((f.ms(20.0, true) - f.ms(20.0, false)).abs() < 1e-12);
}
