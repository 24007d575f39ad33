//! Speedups against baselines of the same run and the same precision (docs/STUDY.md §5). A
//! record's `baseline` is the fastest one-thread CPU search (`cpu1.cells` or `cpu1.tracking`)
//! of its precision at its N in its own run; `speedup_vs_cpu_all` compares with the all-threads
//! CPU (`cpu.cells`) of its precision, and `speedup_vs_cpu1_cells_f64` with `cpu1.cells.f64`
//! (kept for continuity). Speedups are computed once, by the run that measured them:
//! `sphlab report` never recomputes one across runs, and runs whose baselines differ by more
//! than [`AGREE`] are ranked side by side ([`rank_groups`]), never together.

use super::Record;

/// The continuity baseline.
pub const CPU1_CELLS_F64: &str = "cpu1.cells.f64";

/// Largest relative difference between two runs' baselines (same N and precision) for their
/// records to be ranked together.
pub const AGREE: f64 = 0.10;

/// Measured (timed), whatever its verdict: a speedup is a ratio of measurements.
fn timed(r: &Record) -> Option<f64> {
    r.ms_per_step_median.filter(|_| matches!(r.status.as_str(), "ok" | "loaded" | "inaccurate"))
}

/// A usable baseline: timed and not inaccurate.
fn base_ms(r: &Record) -> Option<f64> {
    timed(r).filter(|_| r.status != "inaccurate")
}

/// Whether `b` is a one-thread CPU search of `precision` (a baseline candidate).
fn is_cpu1_search(b: &Record, precision: &str) -> bool {
    b.backend == "cpu1"
        && b.precision == precision
        && (b.variant.starts_with("cpu1.cells.") || b.variant.starts_with("cpu1.tracking."))
}

/// The best of `cands` for `r`: same experiment first, then the fastest.
fn best<'a>(r: &Record, cands: impl Iterator<Item = &'a Record>) -> Option<(&'a Record, f64)> {
    cands.filter_map(|b| Some((b, base_ms(b)?))).min_by(|x, y| {
        ((x.0.experiment != r.experiment), x.1)
            .partial_cmp(&((y.0.experiment != r.experiment), y.1))
            .unwrap_or(std::cmp::Ordering::Equal)
    })
}

/// Fills the baseline and speedup columns of every timed record of `recs` from the records of
/// its own run (an earlier annotation is cleared first).
pub fn annotate(recs: &mut [Record]) {
    let snapshot: Vec<Record> = recs.to_vec();
    for r in recs.iter_mut() {
        r.baseline.clear();
        r.speedup_vs_baseline = None;
        r.speedup_vs_cpu_all = None;
        r.speedup_vs_cpu1_cells_f64 = None;
        r.cpu_ref.clear();
        let Some(ms) = timed(r) else { continue };
        let run: Vec<&Record> = snapshot.iter().filter(|b| b.run == r.run).collect();
        let same_n = || run.iter().copied().filter(|b| b.n == r.n);
        if let Some((b, bms)) = best(r, same_n().filter(|b| is_cpu1_search(b, &r.precision))) {
            r.baseline = b.variant.clone();
            r.speedup_vs_baseline = Some(bms / ms);
        }
        let all = format!("cpu.cells.{}", r.precision);
        if let Some((_, bms)) = best(r, same_n().filter(|b| b.variant == all)) {
            r.speedup_vs_cpu_all = Some(bms / ms);
        }
        let f64_base = run.iter().copied().filter(|b| b.variant == CPU1_CELLS_F64);
        let same = best(r, f64_base.clone().filter(|b| b.n == r.n)).map(|(_, b)| (b, "measured".to_string()));
        let scaled = || {
            f64_base
                .filter(|b| b.n < r.n)
                .filter_map(|b| Some((b, base_ms(b)?)))
                .max_by_key(|(b, _)| (b.n, (b.experiment == r.experiment) as u8))
                .map(|(b, bms)| (bms * r.n as f64 / b.n as f64, format!("scaled from N={}", b.n)))
        };
        if let Some((b, how)) = same.or_else(scaled) {
            r.speedup_vs_cpu1_cells_f64 = Some(b / ms);
            r.cpu_ref = how;
        }
    }
}

/// Each run's baseline ms/step per (N, precision): the fastest one-thread CPU search.
fn baselines(recs: &[Record]) -> Vec<(String, usize, String, f64)> {
    let mut out: Vec<(String, usize, String, f64)> = Vec::new();
    for b in recs.iter().filter(|b| is_cpu1_search(b, &b.precision)) {
        let Some(ms) = base_ms(b) else { continue };
        match out.iter_mut().find(|o| o.0 == b.run && o.1 == b.n && o.2 == b.precision) {
            Some(o) => o.3 = o.3.min(ms),
            None => out.push((b.run.clone(), b.n, b.precision.clone(), ms)),
        }
    }
    out
}

/// One line per pair of runs whose baselines at the same N and precision differ by more than
/// [`AGREE`] (empty: every run may be ranked together).
pub fn disagreements(recs: &[Record]) -> Vec<String> {
    let b = baselines(recs);
    let mut out = Vec::new();
    for (i, x) in b.iter().enumerate() {
        for y in b[i + 1..].iter().filter(|y| y.0 != x.0 && y.1 == x.1 && y.2 == x.2) {
            let diff = (x.3 - y.3).abs() / x.3.min(y.3);
            if diff > AGREE {
                out.push(format!(
                    "N = {}, {}: baseline {:.3} ms/step in run `{}`, {:.3} in run `{}` ({:.0} % apart)",
                    x.1,
                    x.2,
                    x.3,
                    x.0,
                    y.3,
                    y.0,
                    100.0 * diff
                ));
            }
        }
    }
    out
}

/// The groups of records that may be ranked together: all of them when the runs' baselines
/// agree, else one group per run (named by its run).
pub fn rank_groups(recs: &[Record]) -> Vec<(Option<String>, Vec<&Record>)> {
    if disagreements(recs).is_empty() {
        return vec![(None, recs.iter().collect())];
    }
    let mut runs: Vec<&str> = recs.iter().map(|r| r.run.as_str()).collect();
    runs.sort();
    runs.dedup();
    runs.into_iter().map(|run| (Some(run.to_string()), recs.iter().filter(|r| r.run == run).collect())).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(run: &str, variant: &str, n: usize, ms: f64, status: &str) -> Record {
        let mut it = variant.split('.');
        let backend = it.next().unwrap_or("");
        let backend = if backend == "cpu1" || backend == "cpu" { backend } else { "gpu" };
        Record {
            run: run.into(),
            experiment: "e4".into(),
            variant: variant.into(),
            backend: backend.into(),
            precision: variant.rsplit('.').next().unwrap_or("").into(),
            n,
            status: status.into(),
            ms_per_step_median: Some(ms),
            ..Default::default()
        }
    }

    #[test]
    fn the_baseline_is_the_fastest_one_thread_search_of_the_same_precision_and_run() {
        let mut recs = vec![
            rec("a", "cpu1.cells.f64", 100, 10.0, "ok"),
            rec("a", "cpu1.tracking.f64", 100, 6.0, "ok"),
            rec("a", "cpu1.cells.f32", 100, 9.0, "ok"),
            rec("a", "cpu1.tracking.f32", 100, 5.0, "inaccurate"),
            rec("a", "cpu.cells.f32", 100, 4.0, "ok"),
            rec("a", "cells.thread.recomputed.f32", 100, 1.0, "ok"),
            rec("b", "cpu1.tracking.f32", 100, 0.5, "ok"),
        ];
        annotate(&mut recs);
        let g = &recs[5];
        assert_eq!(g.baseline, "cpu1.cells.f32", "same run, same precision, not inaccurate");
        assert_eq!(g.speedup_vs_baseline, Some(9.0));
        assert_eq!(g.speedup_vs_cpu_all, Some(4.0));
        assert_eq!(g.speedup_vs_cpu1_cells_f64, Some(10.0));
        assert_eq!(recs[0].baseline, "cpu1.tracking.f64");
        assert_eq!(recs[6].speedup_vs_cpu1_cells_f64, None, "run b has no cpu1.cells.f64");
    }

    #[test]
    fn runs_whose_baselines_differ_are_ranked_apart() {
        let near = vec![rec("a", "cpu1.cells.f32", 100, 10.0, "ok"), rec("b", "cpu1.cells.f32", 100, 10.5, "ok")];
        assert!(disagreements(&near).is_empty());
        assert_eq!(rank_groups(&near).len(), 1);
        let far = vec![rec("a", "cpu1.cells.f32", 100, 10.0, "ok"), rec("b", "cpu1.cells.f32", 100, 12.0, "ok")];
        assert_eq!(disagreements(&far).len(), 1, "20 % apart");
        let groups = rank_groups(&far);
        assert_eq!(groups.len(), 2);
        assert!(groups.iter().all(|(run, g)| g.len() == 1 && run.is_some()));
    }
}
