//! Tests of the thesis figures: every search on both backends, one run of a merged report, one
//! E2 table per run.
use super::*;

fn rec(experiment: &str, variant: &str, backend: &str, ms: f64) -> Record {
    let precision = variant.rsplit('.').next().unwrap_or("").into();
    let (experiment, variant, backend) = (experiment.into(), variant.into(), backend.into());
    Record {
        precision,
        experiment,
        variant,
        backend,
        ms_per_step_median: Some(ms),
        status: "ok".into(),
        adapter: "test".into(),
        ..Record::default()
    }
}

#[test]
fn fig_6_3_draws_every_search_on_both_backends() {
    let dir = tempfile::tempdir().expect("tempdir");
    let recs = vec![
        rec("e1", "cpu1.direct.f64", "cpu1", 90.0),
        rec("e1", "cpu1.cells.f64", "cpu1", 4.0),
        rec("e1", "cpu1.tracking.f64", "cpu1", 3.5),
        rec("e1", "direct.thread.recomputed.f32", "gpu", 1000.0),
        rec("e1", "cells.thread.recomputed.f32", "gpu", 40.0),
        rec("e1", "tracking.thread.recomputed.f32", "gpu", 12.0),
    ];
    let mut md = String::new();
    write(dir.path(), &recs, &mut md).expect("figures");
    let svg = std::fs::read_to_string(dir.path().join("fig6_3_search.svg")).expect("fig6_3_search.svg");
    for label in ["direct", "cells", "tracking", "CPU, one thread", "GPU (test)"] {
        assert!(svg.contains(label), "{label}");
    }
    // Six bars (rect elements filled with a series colour), one per (search, backend).
    assert_eq!(svg.matches("fill=\"#1F77B4\"").count() + svg.matches("fill=\"#FF7F0E\"").count(), 6 + 2);
    assert!(md.contains("fig6_3_search.svg") && !dir.path().join("fig6_8_residency.svg").exists());
}

#[test]
fn e2_of_two_runs_gets_a_table_each_against_its_own_cpu_all() {
    let dir = tempfile::tempdir().expect("tempdir");
    let at = |r: Record, run: &str| Record { run: run.into(), ..r };
    let recs = vec![
        at(rec("e2", "hybrid.cpu-all", "hybrid", 10.0), "a"),
        at(rec("e2", "hybrid.gpu-all", "hybrid", 5.0), "a"),
        at(rec("e2", "hybrid.cpu-all", "hybrid", 4.0), "b"),
        at(rec("e2", "hybrid.gpu-all", "hybrid", 1.0), "b"),
    ];
    let mut md = String::new();
    write(dir.path(), &recs, &mut md).expect("figures");
    assert!(md.contains("Run `a`") && md.contains("Run `b`"), "{md}");
    // gpu-all: 2× in run a, 4× in run b (not 10 / 1 = 10× across the runs).
    assert!(md.contains("| 2.00× |") && md.contains("| 4.00× |") && !md.contains("10.00×"), "{md}");
}

#[test]
fn fig_6_3_of_a_merged_report_draws_one_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let at = |r: Record, run: &str, adapter: &str| Record { run: run.into(), adapter: adapter.into(), ..r };
    let recs = vec![
        at(rec("e1", "cpu1.cells.f64", "cpu1", 4.0), "a", "A-GPU"),
        at(rec("e1", "cells.thread.recomputed.f32", "gpu", 40.0), "a", "A-GPU"),
        at(rec("e1", "cpu1.direct.f64", "cpu1", 90.0), "b", "B-GPU"),
        at(rec("e1", "cells.thread.recomputed.f32", "gpu", 2.0), "b", "B-GPU"),
        at(rec("e1", "tracking.thread.recomputed.f32", "gpu", 1.0), "b", "B-GPU"),
    ];
    let mut md = String::new();
    write(dir.path(), &recs, &mut md).expect("figures");
    let svg = std::fs::read_to_string(dir.path().join("fig6_3_search.svg")).expect("fig6_3_search.svg");
    // Run a's two bars only, and its adapter alone in the note.
    assert_eq!(svg.matches("fill=\"#1F77B4\"").count() + svg.matches("fill=\"#FF7F0E\"").count(), 2 + 2);
    assert!(svg.contains("A-GPU") && !svg.contains("B-GPU"));
}
