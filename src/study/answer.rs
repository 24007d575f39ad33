//! The answer `summary.md` opens with (docs/STUDY.md §5): for each N the fastest `ok` GPU
//! variant with its ms/step and 95 % interval, its speedups against the one-thread CPU of its
//! precision and against all cores (both of its own run), its error against the CPU f64 run,
//! its device memory and the largest N it fits on this adapter; then one ratio per strategy
//! axis over the matched `ok` pairs of one run, with the thesis's figure beside it where it
//! gave one, and the residency (E2) and subdomain (E3) comparisons the same way. Records of runs
//! whose baselines disagree are answered run by run
//! ([`super::baseline::rank_groups`]).

use super::baseline::{disagreements, rank_groups};
use super::Record;
use crate::gpu::variant::VariantSpec;
use std::collections::BTreeMap;
use std::fmt::Write;

/// A GPU variant id's parts: (search, mapping, accumulation, kernel values, precision,
/// workgroup size); `None` for a CPU or hybrid id.
fn parts(id: &str) -> Option<[String; 6]> {
    let v: VariantSpec = id.parse().ok()?;
    Some([
        v.search.name().to_string(),
        v.mapping.name().to_string(),
        v.accumulation.name().to_string(),
        v.kernel_values.name().to_string(),
        v.precision.name().to_string(),
        v.workgroup.name(),
    ])
}

/// One strategy comparison: axis name, index of the part it varies, the faster-claimed value,
/// the other, and the thesis's figure (time ratio other ÷ claimed) where it gave one.
struct Axis {
    axis: &'static str,
    part: usize,
    a: &'static str,
    b: &'static str,
    thesis: Option<&'static str>,
}

const AXES: &[Axis] = &[
    Axis { axis: "search", part: 0, a: "cells", b: "direct", thesis: None },
    Axis { axis: "search", part: 0, a: "tracking", b: "cells", thesis: None },
    Axis {
        axis: "mapping",
        part: 1,
        a: "thread",
        b: "block-atomic",
        thesis: Some("≈ 1.17 (one particle per thread ≈ 17 % faster than atomics, §6.4.2)"),
    },
    Axis { axis: "mapping", part: 1, a: "thread", b: "block-tree", thesis: None },
    Axis { axis: "mapping", part: 1, a: "subgroup", b: "thread", thesis: None },
    Axis { axis: "accumulation", part: 1, a: "block-tree", b: "block-atomic", thesis: None },
    Axis { axis: "kernel values", part: 3, a: "recomputed", b: "cached", thesis: None },
    Axis { axis: "precision", part: 4, a: "f32", b: "f64", thesis: None },
    Axis { axis: "workgroup size", part: 5, a: "wg128", b: "wg64", thesis: None },
    Axis { axis: "workgroup size", part: 5, a: "wg256", b: "wg64", thesis: None },
];

/// The matched pairs of `ax` in `rows` (same run, experiment, N and every other part; the
/// mapping axis pairs a block mapping's every accumulation with the thread twin): per pair the
/// time ratio b ÷ a and its interval from the two medians' 95 % intervals.
fn pairs(ax: &Axis, rows: &[&Record]) -> Vec<(f64, f64, f64)> {
    let key = |r: &Record| -> Option<(String, String)> {
        let mut k = parts(&r.variant)?;
        let value = std::mem::replace(&mut k[ax.part], "*".into());
        if ax.part == 1 {
            k[2] = "*".into();
        }
        Some((value, format!("{}|{}|{}|{}", r.run, r.experiment, r.n, k.join("."))))
    };
    let mut by: BTreeMap<String, (Vec<&Record>, Vec<&Record>)> = BTreeMap::new();
    for r in rows.iter().filter(|r| r.is_ok() && r.backend == "gpu") {
        let Some((v, k)) = key(r) else { continue };
        let e = by.entry(k).or_default();
        if v == ax.a {
            e.0.push(r);
        } else if v == ax.b {
            e.1.push(r);
        }
    }
    let mut out = Vec::new();
    for (a_side, b_side) in by.values() {
        for a in a_side {
            for b in b_side {
                let (ma, mb) = (a.ms(), b.ms());
                let (alo, ahi) = (a.ms_per_step_ci_lo.unwrap_or(ma), a.ms_per_step_ci_hi.unwrap_or(ma));
                let (blo, bhi) = (b.ms_per_step_ci_lo.unwrap_or(mb), b.ms_per_step_ci_hi.unwrap_or(mb));
                out.push((mb / ma, blo / ahi, bhi / alo));
            }
        }
    }
    out
}

/// The residency (E2) and subdomain (E3) comparisons: per run and GPU configuration, the
/// record `whole` picks (everything resident / the unsplit run) against the fastest of the
/// others (the hybrids, E2's all-CPU row left out / the splits), as the time ratio other ÷
/// whole with its interval.
fn whole_against_parts(rows: &[&Record], experiment: &str, whole: fn(&Record) -> bool) -> Vec<(f64, f64, f64)> {
    // Per (run, configuration): the whole, and the fastest part so far.
    type WholeAndPart<'a> = (Option<&'a Record>, Option<&'a Record>);
    let mut by: BTreeMap<(String, String), WholeAndPart> = BTreeMap::new();
    // E2's all-CPU row is no hybrid: it is the CPU baseline of that experiment.
    for r in rows.iter().filter(|r| r.experiment == experiment && r.is_ok() && r.variant != "hybrid.cpu-all") {
        let e = by.entry((r.run.clone(), r.config.clone())).or_default();
        if whole(r) {
            e.0 = Some(r);
        } else if e.1.is_none_or(|b| r.ms() < b.ms()) {
            e.1 = Some(r);
        }
    }
    let ci = |r: &Record| (r.ms_per_step_ci_lo.unwrap_or(r.ms()), r.ms_per_step_ci_hi.unwrap_or(r.ms()));
    by.values()
        .filter_map(|(a, b)| {
            let (a, b) = (a.as_ref()?, b.as_ref()?);
            let ((alo, ahi), (blo, bhi)) = (ci(a), ci(b));
            Some((b.ms() / a.ms(), blo / ahi, bhi / alo))
        })
        .collect()
}

fn geo_mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x.ln(), n + 1));
    (s / n.max(1) as f64).exp()
}

fn opt(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map_or("-".into(), f)
}

/// The fastest ok GPU record at each N of `rows`, or the count of its GPU records by status.
fn fastest_per_n<'a>(rows: &[&'a Record]) -> BTreeMap<usize, Result<&'a Record, String>> {
    let mut by_n: BTreeMap<usize, Vec<&Record>> = BTreeMap::new();
    for r in rows.iter().filter(|r| r.backend == "gpu" && matches!(r.experiment.as_str(), "e1" | "e4" | "scaling")) {
        by_n.entry(r.n).or_default().push(r);
    }
    let mut out = BTreeMap::new();
    for (n, v) in by_n {
        let best = v.iter().copied().filter(|r| r.is_ok()).min_by(|a, b| a.ms().total_cmp(&b.ms()));
        let counts = || {
            let mut c: BTreeMap<&str, usize> = BTreeMap::new();
            for r in &v {
                *c.entry(r.status.as_str()).or_default() += 1;
            }
            c.iter().map(|(s, k)| format!("{k} {s}")).collect::<Vec<_>>().join(", ")
        };
        out.insert(n, best.ok_or_else(counts));
    }
    out
}

/// One group's answer table.
fn answer_table(md: &mut String, rows: &[&Record]) {
    let _ = writeln!(
        md,
        "| N (fluid) | fastest ok GPU variant | ms/step [95 % interval] | speedup vs one-thread CPU (baseline) | vs all cores | KE rel. error vs CPU f64 | centroid error (Δx) | device memory | largest N that fits |\n|---|---|---|---|---|---|---|---|---|"
    );
    for (n, best) in fastest_per_n(rows) {
        let Ok(r) = best else {
            let why = best.err().unwrap_or_default();
            let _ = writeln!(md, "| {n} | no ok GPU record ({why}) | - | - | - | - | - | - | - |");
            continue;
        };
        let _ = writeln!(
            md,
            "| {n} ({}) | `{}` | {:.3} [{}, {}] | {} | {} | {} | {} | {} | {} |",
            r.n_fluid,
            r.variant,
            r.ms(),
            opt(r.ms_per_step_ci_lo, |x| format!("{x:.3}")),
            opt(r.ms_per_step_ci_hi, |x| format!("{x:.3}")),
            opt(r.speedup_vs_baseline, |x| format!("{x:.2}× (`{}`)", r.baseline)),
            opt(r.speedup_vs_cpu_all, |x| format!("{x:.2}×")),
            opt(r.ke_rel_error, |x| format!("{x:.1e}")),
            opt(r.centroid_error_dx, |x| format!("{x:.1e}")),
            opt(r.device_bytes.map(|b| b as f64), crate::plan::fmt_bytes),
            r.max_n_fits.map_or("-".into(), |x| x.to_string()),
        );
    }
}

/// One group's strategy-axis table.
fn axis_table(md: &mut String, rows: &[&Record]) {
    let _ = writeln!(
        md,
        "\n| axis | comparison | time ratio (geometric mean) [interval] | matched ok pairs | thesis |\n|---|---|---|---|---|"
    );
    let ratio = |p: &[(f64, f64, f64)]| {
        if p.is_empty() {
            return "no matched ok pair".to_string();
        }
        let (m, lo, hi) =
            (geo_mean(p.iter().map(|x| x.0)), geo_mean(p.iter().map(|x| x.1)), geo_mean(p.iter().map(|x| x.2)));
        format!("{m:.2}× [{lo:.2}, {hi:.2}]")
    };
    for ax in AXES {
        let p = pairs(ax, rows);
        let thesis = ax.thesis.unwrap_or("-");
        let _ = writeln!(md, "| {} | `{}` over `{}` | {} | {} | {thesis} |", ax.axis, ax.a, ax.b, ratio(&p), p.len());
    }
    let resident = whole_against_parts(rows, "e2", |r| r.residency_cpu == "-" || r.residency_cpu.is_empty());
    let unsplit = whole_against_parts(rows, "e3", |r| r.budget.is_none());
    for (axis, what, p) in [
        ("residency", "everything on the GPU over the fastest CPU/GPU hybrid (E2)", resident),
        ("subdomains", "the unsplit run over the fastest subdomain split (E3)", unsplit),
    ] {
        let _ = writeln!(md, "| {axis} | {what} | {} | {} | - |", ratio(&p), p.len());
    }
    let _ = writeln!(
        md,
        "| GPU against CPU | fastest ok GPU variant over the one-thread CPU baseline | see the table above | - | 120× at 2,025 fluid particles (§6.5, a 2012 GPU against a 2012 CPU core) |"
    );
}

/// The opening of `summary.md`: the answer table and the strategy axes, per rank group.
pub fn write(md: &mut String, recs: &[Record]) {
    let _ = writeln!(md, "## The answer\n");
    let flags = disagreements(recs);
    if !flags.is_empty() {
        let _ = writeln!(
            md,
            "**Runs side by side, not ranked together**: their one-thread CPU baselines differ by more than 10 %: {}.\n",
            flags.join("; ")
        );
    }
    for (run, rows) in rank_groups(recs) {
        if let Some(run) = run {
            let _ = writeln!(md, "### Run `{run}`\n");
        }
        answer_table(md, &rows);
        axis_table(md, &rows);
        let _ = writeln!(md);
    }
    let _ = writeln!(
        md,
        "Only `ok` records are ranked: measured, within `verify`'s tolerances against the CPU run of the same precision, \
         and measured while other processes used at most a quarter of the cores. Speedups compare records of one run only. A time \
         ratio above 1 means the first value is faster; its interval combines the two medians' bootstrap 95 % \
         intervals (conservative).\n"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(experiment: &str, variant: &str, ms: f64) -> Record {
        Record {
            experiment: experiment.into(),
            variant: variant.into(),
            status: "ok".into(),
            ms_per_step_median: Some(ms),
            config: "cells.thread.recomputed.f32".into(),
            ..Default::default()
        }
    }

    #[test]
    fn residency_and_subdomain_rows_compare_the_whole_with_its_fastest_part() {
        let mut rows = vec![
            Record { residency_cpu: "-".into(), ..rec("e2", "hybrid.gpu-all", 10.0) },
            Record { residency_cpu: "integration".into(), ..rec("e2", "hybrid.gpu-evaluation", 12.0) },
            Record { residency_cpu: "search+integration".into(), ..rec("e2", "hybrid.gpu-forces", 30.0) },
            // The all-CPU row is faster here but no hybrid: never the comparison.
            Record {
                residency_cpu: "search+density+surface+forces+integration".into(),
                ..rec("e2", "hybrid.cpu-all", 5.0)
            },
            rec("e3", "cells.thread.recomputed.f32", 20.0),
            Record { budget: Some(1500), ..rec("e3", "cells.thread.recomputed.f32", 50.0) },
            Record { budget: Some(4500), ..rec("e3", "cells.thread.recomputed.f32", 30.0) },
        ];
        rows.push(Record {
            status: "inaccurate".into(),
            budget: Some(3000),
            ..rec("e3", "cells.thread.recomputed.f32", 1.0)
        });
        let refs: Vec<&Record> = rows.iter().collect();
        let e2 = whole_against_parts(&refs, "e2", |r| r.residency_cpu == "-");
        assert_eq!(e2, vec![(1.2, 1.2, 1.2)]);
        let e3 = whole_against_parts(&refs, "e3", |r| r.budget.is_none());
        assert_eq!(e3, vec![(1.5, 1.5, 1.5)], "the fastest ok split, never an inaccurate one");
        let mut md = String::new();
        axis_table(&mut md, &refs);
        assert!(md.contains("| residency | everything on the GPU over the fastest CPU/GPU hybrid (E2) | 1.20× [1.20, 1.20] | 1 | - |"), "{md}");
        assert!(
            md.contains(
                "| subdomains | the unsplit run over the fastest subdomain split (E3) | 1.50× [1.50, 1.50] | 1 | - |"
            ),
            "{md}"
        );
    }
}
