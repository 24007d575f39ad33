//! The study's `engine` experiment: the legacy GPU engine and the current one,
//! side by side in ONE run at the E4 size (nx = 100: 11,236 particles; `--engine-nx`).
//!
//! * **before** ([`EngineMode::BEFORE`]): particles stay in lattice order (no renumbering),
//!   every stage is its own kernel, and every step is its own submission followed by a
//!   blocking control readback, as the engine ran before `advance(k)`;
//! * **after** ([`EngineMode::AFTER`], the solver's default): cell-order renumbering every 16
//!   steps, the per-particle stages fused into the neighbour passes the stage table allows,
//!   the K steps of a block in one submission with one readback;
//! * **unfused** ([`EngineMode::UNFUSED`]): **after** with every stage of the table its own
//!   pass (the debug mode), so that fused ÷ unfused of the same variant in the same run is the
//!   gain of the fused passes alone.
//!
//! Runs, in order: the single-thread CPU references (`cpu1.cells.f64`, whose snapshot is the
//! accuracy reference, and `cpu1.cells.f32`); (a) every GPU variant (`--variants`, else all;
//! direct search only up to [`super::DIRECT_MAX_N`] unless named; `cells.thread.recomputed.f32`
//! always) in **after** mode, to find the fastest; (b) the fastest and
//! `cells.thread.recomputed.f32` in **before** and in **unfused** mode. Every run goes through the
//! study's protocol ([`super::timing`]) and is one [`Record`] (experiment `engine`) with its
//! `engine`, the device bytes, the modelled bytes per evaluation, the measured streaming
//! bandwidth and the fraction of it the time per step reaches ([`crate::gpu::bandwidth`]), and
//! the submissions, readbacks and dispatches per step, counted by the engine over one extra
//! untimed block of K steps. A failed run is a record with its status and reason, no timing.
//! [`summary`] writes the before/after table of `summary.md`.

use super::measured::{Common, Judge, References};
use super::plan::Job;
use super::timing::{self, Failure, Timed};
use super::{run_job, stats, study_scene_with, Record, Start, StudyOptions, DIRECT_MAX_N};
use crate::backend::Backend;
use crate::backend_id::BackendId;
use crate::exec::Exec;
use crate::gpu::bandwidth::{measure_bandwidth_within, Bandwidth, EngineTraffic, PROBE_BYTES};
use crate::gpu::solver::{EngineMode, GpuSolver};
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::real::Real;
use crate::scene::build::build_layout;
use crate::scene::initial::initial_velocities;
use std::fmt::Write;
use std::sync::Arc;

/// The experiment's name (`--experiments engine`).
pub const EXPERIMENT: &str = "engine";

/// Its default resolution: the E4 size (10,000 fluid, 11,236 particles).
pub const DEFAULT_NX: u32 = 100;

/// The variant compared before/after besides the fastest one.
pub const THREAD_RECOMPUTED: &str = "cells.thread.recomputed.f32";

/// What the engine's own counters and traffic model say about one GPU run.
struct Engine {
    traffic: EngineTraffic,
    /// (submits, readbacks, dispatches) per step over one untimed block of K steps.
    per_step: Option<(f64, f64, f64)>,
}

/// Builds `spec` in `mode` from the shared start, times it, then counts one more block.
fn time_gpu<T: Real>(
    ctx: &Arc<GpuContext>,
    s: &Start,
    spec: VariantSpec,
    mode: EngineMode,
    opts: &StudyOptions,
    bandwidth: &Option<Bandwidth>,
) -> (Result<Timed, Failure>, Option<Engine>) {
    let mut g = match GpuSolver::<T>::new(ctx.clone(), &s.scene, &s.layout, spec) {
        Ok(g) => g,
        Err(e) => return (Err(Failure::build(e.to_string())), None),
    };
    if let Err(e) = g.set_engine_mode(mode) {
        return (Err(Failure::build(e.to_string())), None);
    }
    g.restart_with_velocities(&s.vel0);
    let res = timing::time_backend(&mut g, &opts.protocol);
    let (n, nf) = (s.layout.pos.len(), s.layout.n_fluid);
    let mut traffic = EngineTraffic::new(&spec, &s.scene, n, nf, g.device_bytes(), bandwidth.clone());
    let per_step = res.as_ref().ok().and_then(|_| {
        let k = opts.protocol.steps;
        let c0 = g.engine_counters();
        timing::advance(&mut g, k).ok()?;
        g.sync();
        let c = g.engine_counters().since(&c0);
        g.take_error().is_none().then_some(())?;
        let k = k as f64;
        Some((c.submits as f64 / k, c.readbacks as f64 / k, c.dispatches as f64 / k))
    });
    if let Ok(t) = &res {
        traffic.roofline_fraction = traffic.fraction(timing::median(&t.block_ms) * 1e-3);
    }
    (res, Some(Engine { traffic, per_step }))
}

/// What every GPU run of the experiment shares.
struct Runs<'a> {
    common: Common<'a>,
    ctx: &'a Arc<GpuContext>,
    start: &'a Start,
    opts: &'a StudyOptions,
    bandwidth: Option<Bandwidth>,
    references: References,
}

/// The judge of a record of precision `p` at `s` (the engine experiment checks observables
/// against the CPU run of the same precision; its variants' fields are `verify`'s).
fn judge<'a>(refs: &'a References, s: &Start, p: Precision, watch: stats::Watch) -> Judge<'a> {
    let (load, others) = watch.stop();
    let nx = s.scene.domain.nx;
    Judge {
        f64_ref: refs.frame(nx, Precision::F64),
        same_ref: refs.frame(nx, p),
        fields: None,
        load,
        others,
        cores: stats::cores(),
    }
}

impl Runs<'_> {
    /// One GPU record of `spec` in `mode`.
    fn record(&self, spec: VariantSpec, mode: EngineMode) -> Record {
        let (s, opts, bw) = (self.start, self.opts, &self.bandwidth);
        let watch = stats::Watch::start();
        let (res, engine) = match spec.precision {
            Precision::F32 => time_gpu::<f32>(self.ctx, s, spec, mode, opts, bw),
            Precision::F64 => time_gpu::<f64>(self.ctx, s, spec, mode, opts, bw),
        };
        let reps = self.common.protocol.repeats;
        let j = judge(&self.references, s, spec.precision, watch);
        let mut r = self.common.record(&job(s, BackendId::Gpu(spec)), reps, s, &res, &j);
        r.engine = mode.name();
        if let Some(e) = engine {
            r.device_bytes = Some(e.traffic.device_bytes);
            r.modelled_bytes_per_eval = Some(e.traffic.modelled_bytes_per_evaluation);
            r.bandwidth_gb_s = e.traffic.bandwidth.as_ref().map(|b| b.gb_per_s);
            r.roofline_fraction = e.traffic.roofline_fraction;
            if let Some((sub, rb, d)) = e.per_step {
                (r.submits_per_step, r.readbacks_per_step, r.dispatches_per_step) = (Some(sub), Some(rb), Some(d));
            }
        }
        log(&r);
        r
    }
}

fn job(s: &Start, id: BackendId) -> Job {
    Job {
        experiment: EXPERIMENT.into(),
        nx: s.scene.domain.nx,
        n: s.layout.pos.len(),
        id,
        threads: 1,
        est_s: 0.0,
        rep_s: 0.0,
        extra_blocks: 0,
    }
}

fn log(r: &Record) {
    match r.ms_per_step_median {
        Some(ms) => eprintln!(
            "engine nx={} {:<44} {:<6} {:>10.3} ms/step  roofline {}  submits/step {}",
            r.nx,
            r.variant,
            r.engine,
            ms,
            r.roofline_fraction.map_or("-".into(), |f| format!("{:.2} %", 100.0 * f)),
            r.submits_per_step.map_or("-".into(), |x| format!("{x:.2}"))
        ),
        None => eprintln!("engine nx={} {} {}: {}: {}", r.nx, r.variant, r.engine, r.status, r.reason),
    }
}

/// Runs the experiment (module doc) at `opts.engine_nx`; appends its records to `out`.
pub fn run(opts: &StudyOptions, gpu: Option<&Arc<GpuContext>>, out: &mut Vec<Record>) -> Result<(), String> {
    let scene = study_scene_with(opts.engine_nx, &opts.sets)?;
    let layout = build_layout(&scene).map_err(|e| e.to_string())?;
    let vel0 = initial_velocities(&scene, &layout, None);
    let s = Start::new(scene, layout, vel0);
    let n = s.layout.pos.len();
    let c = Common {
        gpu,
        commit: crate::provenance::commit_label(),
        date: crate::output::now_utc_iso8601(),
        cpu_model: crate::provenance::cpu_model(),
        shard: opts.shard.label(),
        protocol: opts.protocol,
        bandwidth: None,
    };
    // (c) The single-thread CPU references of each precision: the records' accuracy references.
    let mut references = References::default();
    if opts.cpu_max_n.is_none_or(|m| n <= m) {
        for precision in [Precision::F64, Precision::F32] {
            let id = BackendId::Cpu { exec: Exec::Serial, search: SearchKind::Cells, precision };
            let j = job(&s, id);
            let watch = stats::Watch::start();
            let res = run_job(&j, &s, None, None, &opts.protocol);
            references.note(&j, &res);
            let mut r = c.record(&j, opts.protocol.repeats, &s, &res, &judge(&references, &s, precision, watch));
            r.engine = "cpu".into();
            log(&r);
            out.push(r);
        }
    }
    let Some(ctx) = gpu else {
        eprintln!("engine: GPU rows skipped: no GPU adapter");
        return Ok(());
    };
    let bandwidth = measure_bandwidth_within(ctx, PROBE_BYTES, opts.budget_s)
        .map_err(|e| format!("engine: bandwidth probe: {e}"))?;
    let runs = Runs { common: c, ctx, start: &s, opts, bandwidth, references };
    let mut specs = if opts.variants.is_empty() { VariantSpec::all() } else { opts.variants.clone() };
    let thread: VariantSpec = THREAD_RECOMPUTED.parse()?;
    if !specs.contains(&thread) {
        specs.push(thread);
    }
    // (a) Every variant on the current engine.
    let mut after: Vec<Record> = Vec::new();
    for spec in specs {
        if let Err(e) = spec.support(ctx) {
            eprintln!("engine: {spec}: unsupported on this adapter: {e}");
            continue;
        }
        if spec.search == SearchKind::Direct && n > DIRECT_MAX_N && opts.variants.is_empty() {
            continue;
        }
        after.push(runs.record(spec, EngineMode::AFTER));
    }
    let best = after
        .iter()
        .filter(|r| r.ms_per_step_median.is_some())
        .min_by(|a, b| a.ms().total_cmp(&b.ms()))
        .map(|r| r.variant.clone());
    out.append(&mut after);
    // (b) The fastest and the thread/recomputed f32 variant on the legacy engine.
    let mut before: Vec<String> = best.into_iter().collect();
    if !before.iter().any(|v| v == THREAD_RECOMPUTED) {
        before.push(THREAD_RECOMPUTED.into());
    }
    for v in before {
        out.push(runs.record(v.parse()?, EngineMode::BEFORE));
        out.push(runs.record(v.parse()?, EngineMode::UNFUSED));
    }
    Ok(())
}

fn fmt<X>(x: Option<X>, f: impl Fn(X) -> String) -> String {
    x.map_or("-".into(), f)
}

/// a ÷ b of the median times per step, with the interval their 95 % intervals bound (the
/// lowest a over the highest b, and the reverse); `None` unless both were timed.
pub fn ratio_interval(a: &Record, b: &Record) -> Option<(f64, f64, f64)> {
    let (ma, mb) = (a.ms_per_step_median?, b.ms_per_step_median?);
    let (alo, ahi) = (a.ms_per_step_ci_lo.unwrap_or(ma), a.ms_per_step_ci_hi.unwrap_or(ma));
    let (blo, bhi) = (b.ms_per_step_ci_lo.unwrap_or(mb), b.ms_per_step_ci_hi.unwrap_or(mb));
    Some((ma / mb, alo / bhi, ahi / blo))
}

/// The sentence on what limits a variant's time on the current engine, from its record: the roofline
/// fraction, the largest stage (GPU timestamps) and the engine's per-step work.
fn limit_sentence(r: &Record) -> String {
    let mut s = match r.roofline_fraction {
        Some(f) if f >= 0.5 => format!("at {:.0} % of the measured streaming bandwidth it is memory bound", 100.0 * f),
        Some(f) => format!(
            "at {:.2} % of the measured streaming bandwidth ({}) it is not limited by memory bandwidth (the modelled \
             traffic is a lower bound)",
            100.0 * f,
            fmt(r.bandwidth_gb_s, |b| format!("{b:.2} GB/s"))
        ),
        None => "no bandwidth was measured (no timestamps), so the roofline fraction is unknown".into(),
    };
    let total: f64 = r.stage_ms.iter().map(|x| x.1).sum();
    if let Some((stage, ms)) = r.stage_ms.iter().max_by(|a, b| a.1.total_cmp(&b.1)).filter(|_| total > 0.0) {
        let _ = write!(s, "; its largest stage is `{stage}` ({:.0} % of device time)", 100.0 * ms / total);
    }
    if let Some(d) = r.dispatches_per_step {
        let _ = write!(s, "; {d:.0} dispatches per step");
    }
    s
}

/// The before/after table of `summary.md` (nothing without `engine` records).
pub fn summary(md: &mut String, recs: &[Record]) {
    let rows: Vec<&Record> = recs.iter().filter(|r| r.experiment == EXPERIMENT).collect();
    let Some(first) = rows.first() else { return };
    let find = |v: &str, e: &str| rows.iter().find(|r| r.variant == v && r.engine == e).copied();
    let _ = writeln!(
        md,
        "## Engine — legacy against current ({} particles, commit `{}`)\n\n**before**: lattice order, one step per \
         submission with a blocking control readback every step; **after**: cell-order renumbering every 16 steps, K = \
         {} steps per submission, one readback. Throughput timing as above; submissions, readbacks and dispatches per \
         step counted by the engine over one more block of K steps; % of roofline = modelled bytes per step ÷ (time \
         per step × measured streaming bandwidth). Every run's record is in `records.csv` (experiment `engine`).\n",
        first.n, first.commit, first.steps
    );
    for cpu in rows.iter().filter(|r| r.backend != "gpu") {
        let what = match cpu.ms_per_step_median {
            Some(x) => format!("{x:.3} ms/step"),
            None => format!("**{}**: {}", cpu.status, cpu.reason),
        };
        let _ = writeln!(md, "* `{}`: {what}", cpu.variant);
    }
    let after: Vec<&Record> = rows.iter().filter(|r| r.engine == "after").copied().collect();
    let best = after.iter().filter(|r| r.ms_per_step_median.is_some()).min_by(|a, b| a.ms().total_cmp(&b.ms()));
    match best {
        Some(b) => {
            let _ =
                writeln!(md, "\nFastest GPU variant on the current engine ({} run): `{}`.\n", after.len(), b.variant);
        }
        None => {
            let _ = writeln!(md, "\nNo GPU variant ran successfully on the current engine ({} tried).\n", after.len());
        }
    }
    let _ = writeln!(
        md,
        "| variant | before ms/step | after ms/step | before ÷ after | × CPU 1 thread (after) | % of roofline (after) | \
         submits / readbacks per step (before → after) |\n|---|---|---|---|---|---|---|"
    );
    let mut shown: Vec<&str> = best.map(|b| b.variant.as_str()).into_iter().collect();
    if !shown.contains(&THREAD_RECOMPUTED) {
        shown.push(THREAD_RECOMPUTED);
    }
    for v in &shown {
        let (b, a) = (find(v, "before"), find(v, "after"));
        let ms = |r: Option<&Record>| r.and_then(|r| r.ms_per_step_median);
        let counts = |r: Option<&Record>| {
            r.and_then(|r| Some(format!("{:.2} / {:.2}", r.submits_per_step?, r.readbacks_per_step?)))
                .unwrap_or("-".into())
        };
        let ratio = ms(b).zip(ms(a)).map(|(x, y)| x / y);
        let _ = writeln!(
            md,
            "| `{v}` | {} | {} | {} | {} | {} | {} → {} |",
            fmt(ms(b), |x| format!("{x:.3}")),
            fmt(ms(a), |x| format!("{x:.3}")),
            fmt(ratio, |x| format!("{x:.2}×")),
            fmt(a.and_then(|r| r.speedup_vs_cpu1_cells_f64), |x| format!("{x:.2}×")),
            fmt(a.and_then(|r| r.roofline_fraction), |x| format!("{:.2} %", 100.0 * x)),
            counts(b),
            counts(a)
        );
    }
    let _ = writeln!(
        md,
        "\nFused against unfused, the same variant in the same run (**unfused**: the current engine with every stage \
         of the stage table its own pass):\n\n| variant | unfused ms/step | fused (after) ms/step | unfused ÷ fused \
         [95 % interval] | dispatches per step (unfused → fused) |\n|---|---|---|---|---|"
    );
    for v in &shown {
        let (u, a) = (find(v, "unfused"), find(v, "after"));
        let ms = |r: Option<&Record>| r.and_then(|r| r.ms_per_step_median);
        let dispatches = |r: Option<&Record>| fmt(r.and_then(|r| r.dispatches_per_step), |x| format!("{x:.2}"));
        let _ = writeln!(
            md,
            "| `{v}` | {} | {} | {} | {} → {} |",
            fmt(ms(u), |x| format!("{x:.3}")),
            fmt(ms(a), |x| format!("{x:.3}")),
            fmt(u.zip(a).and_then(|(u, a)| ratio_interval(u, a)), |(r, lo, hi)| format!("{r:.2}× [{lo:.2}, {hi:.2}]")),
            dispatches(u),
            dispatches(a)
        );
    }
    let _ = writeln!(md);
    for v in &shown {
        if let Some(a) = find(v, "after").filter(|r| r.status == "ok") {
            let _ = writeln!(md, "What limits `{v}` on the current engine: {}.\n", limit_sentence(a));
        }
    }
    for r in rows.iter().filter(|r| r.backend == "gpu" && r.status != "ok") {
        let _ = writeln!(md, "* `{}` ({}): **{}**: {}", r.variant, r.engine, r.status, r.reason);
    }
    let _ = writeln!(md);
}
