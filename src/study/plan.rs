//! The study's plan: every job (experiment × size × backend) in one fixed order, the part a
//! `--shard i/n` runs, its estimated time from a short probe, and the `--budget` cut (the
//! largest sizes are dropped first, then any job the running estimate says would overrun), and
//! the resource plan of each size ([`resource_plan`]: a run's, with the reference frames kept).
//!
//! The estimate of a job is `build + warm-up + steps × ms/step(N)`, with ms/step(N) = a + b·N
//! fitted per backend kind on the cell search at two probe sizes (× N/50 for direct search:
//! all pairs instead of ~50 neighbours), and a GPU variant's
//! first build costing the probe's measured build (pipelines are compiled once per variant).
//! While the study runs, the ratio of measured to estimated time corrects the remaining jobs.

use super::timing::{advance, Protocol};
use super::{study_scene_with, StudyOptions, DIRECT_MAX_N};
use crate::backend_id::BackendId;
use crate::exec::Exec;
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::plan::Plan as ResourcePlan;
use crate::real::Precision;
use crate::scene::build::build_layout;
use crate::scene::initial::initial_velocities;
use std::collections::BTreeSet;
use std::fmt::Write;
use std::sync::Arc;
use std::time::Instant;

/// The resource plan of the study scene `scene` (CPU f64) with the reference frames the study
/// keeps, one per size for the whole study: this size's and those of `earlier` particles (the
/// sizes checked before it).
pub fn resource_plan(scene: &crate::scene::Scene, earlier: f64) -> ResourcePlan {
    let p = crate::resources::run_plan(scene, 8, false);
    let kept = (earlier + p.n_total) * crate::backend::Frame::BYTES_PER_PARTICLE;
    p.with_buffer("reference frames kept per size (study)", "copies", kept)
}

/// One timed backend at one size of one experiment.
#[derive(Clone, Debug)]
pub struct Job {
    /// e1, e4, scaling.
    pub experiment: String,
    /// Resolution (particles across the box).
    pub nx: u32,
    /// Planned particles (fluid + wall).
    pub n: usize,
    /// The backend.
    pub id: BackendId,
    /// CPU threads it uses.
    pub threads: usize,
    /// Estimated seconds (0 until [`Probe::estimate`]).
    pub est_s: f64,
    /// Estimated seconds of one more timed block of K steps (what a raised `--repeats` costs).
    pub rep_s: f64,
    /// Timed blocks beyond the study's repeats that the budget gave this job (see [`select`]).
    pub extra_blocks: usize,
}

/// The experiments the job sweep runs (others dispatch elsewhere in `run_study`).
pub const SWEEP_EXPERIMENTS: [&str; 3] = ["e1", "e4", "scaling"];

/// Resolutions of an experiment.
pub fn sizes_of(experiment: &str, opts: &StudyOptions) -> Vec<u32> {
    match experiment {
        "e1" => vec![45],
        "e4" => opts.e4_sizes.clone(),
        _ => opts.sizes.clone(),
    }
}

/// Every job of the sweep experiments, in run order: per size the one-thread CPU cells and
/// tracking searches in f64 and f32 (the baselines; the reference `cpu1.cells.f64` first, E1
/// adds the direct search), the all-threads CPU in both precisions, then the GPU variants, the
/// direct-search ones last (all-pairs walks cost a GPU far more than the plan's fit says, so a
/// study that runs late loses them, not the rest); and notes on what was left out and why (unsupported, over a limit, `--cpu-max-n`).
pub fn jobs(opts: &StudyOptions, gpu: Option<&Arc<GpuContext>>) -> Result<(Vec<Job>, Vec<String>), String> {
    let mut out = Vec::new();
    let mut notes = BTreeSet::new();
    let threads = rayon::current_num_threads();
    let specs: Vec<VariantSpec> = if opts.variants.is_empty() { VariantSpec::all() } else { opts.variants.clone() };
    let mut supported = Vec::new();
    if let Some(g) = gpu {
        for s in specs {
            match s.support(g) {
                Ok(()) => supported.push(s),
                Err(e) => {
                    notes.insert(format!("`{s}`: unsupported on this adapter ({e})"));
                }
            }
        }
    }
    supported.sort_by_key(|s| s.search == SearchKind::Direct);
    for e in opts.experiments.iter().filter(|e| SWEEP_EXPERIMENTS.contains(&e.as_str())) {
        for nx in sizes_of(e, opts) {
            let scene = study_scene_with(nx, &opts.sets)?;
            let plan = crate::resources::run_plan(&scene, 8, false);
            let n = plan.n_total as usize;
            let mut push = |id: BackendId, threads: usize| {
                out.push(Job { experiment: e.clone(), nx, n, id, threads, est_s: 0.0, rep_s: 0.0, extra_blocks: 0 })
            };
            if opts.cpu_max_n.is_none_or(|m| n <= m) {
                // The same-run baselines: one thread, cells and tracking, in both precisions.
                for precision in [Precision::F64, Precision::F32] {
                    for search in [SearchKind::Cells, SearchKind::Tracking] {
                        push(BackendId::Cpu { exec: Exec::Serial, search, precision }, 1);
                    }
                }
                if e == "e1" {
                    let precision = Precision::F64;
                    push(BackendId::Cpu { exec: Exec::Serial, search: SearchKind::Direct, precision }, 1);
                }
                for precision in [Precision::F64, Precision::F32] {
                    push(BackendId::Cpu { exec: Exec::Parallel, search: SearchKind::Cells, precision }, threads);
                }
            } else {
                notes.insert(format!(
                    "CPU rows only up to N = {} (`--cpu-max-n`); above it GPU rows compare with the largest CPU size, scaled by N",
                    opts.cpu_max_n.unwrap_or(0)
                ));
            }
            let Some(g) = gpu else { continue };
            let gplan = crate::resources::run_plan(&scene, 4, true);
            let device = crate::gpu::plan::DeviceLimits::of(g, None);
            for &spec in &supported {
                // E1 compares the searches: the default variant of each.
                if e == "e1" && spec != (VariantSpec { search: spec.search, ..VariantSpec::default() }) {
                    continue;
                }
                if spec.search == SearchKind::Direct && n > DIRECT_MAX_N && opts.variants.is_empty() {
                    notes.insert(format!(
                        "direct GPU variants only up to {DIRECT_MAX_N} particles (O(N²)) unless named in --variants"
                    ));
                    continue;
                }
                if let Err(why) = gplan.clone().for_variant(&spec).check_gpu(&device) {
                    notes.insert(format!("{e} nx={nx}: {spec} not run: {why}"));
                    continue;
                }
                push(BackendId::Gpu(spec), 1);
            }
        }
    }
    Ok((out, notes.into_iter().collect()))
}

/// Typical neighbours per particle of the study scene (direct search visits all N instead).
const NEIGHBOURS: f64 = 50.0;

/// Per-step cost model a + b·N of one backend kind (cell search), from two probe sizes.
#[derive(Clone, Copy, Debug, Default)]
struct Fit {
    a_ms: f64,
    b_ms: f64,
}

impl Fit {
    fn from(n: [f64; 2], ms: [f64; 2]) -> Fit {
        let b = ((ms[1] - ms[0]) / (n[1] - n[0])).max(ms[1] / n[1] * 0.25).max(0.0);
        Fit { a_ms: (ms[1] - b * n[1]).max(0.0), b_ms: b }
    }
    /// ms/step at N; a direct (all-pairs) search visits about N / [`NEIGHBOURS`] times the
    /// candidates of the cell search it was fitted on, which multiplies the per-particle term
    /// only: the fixed term (a GPU's launch and latency floor, which at 10⁴ particles is most
    /// of its step) does not grow with the candidates.
    fn ms(&self, n: f64, direct: bool) -> f64 {
        let visits = if direct { (n / NEIGHBOURS).max(1.0) } else { 1.0 };
        self.a_ms + self.b_ms * n * visits
    }
}

/// The probe's measurements: ms/step fits per backend kind, GPU build time, layout cost.
#[derive(Clone, Debug, Default)]
pub struct Probe {
    cpu1: Fit,
    cpu: Fit,
    gpu: Option<Fit>,
    gpu_build_s: f64,
    layout_s_per_particle: f64,
    /// Wall time the probe took (s).
    pub seconds: f64,
}

/// Default probe resolutions ([`StudyOptions::probe_sizes`]).
pub const PROBE_SIZES: [u32; 2] = [16, 32];
const PROBE_STEPS: u64 = 2;

impl Probe {
    /// One line with the fitted costs (printed with the plan).
    pub fn describe(&self) -> String {
        let f = |x: &Fit| format!("{:.3} ms + {:.2e} ms·N", x.a_ms, x.b_ms);
        format!(
            "probe fits per step: cpu1 {}; cpu {}; gpu {}; first GPU build {:.2} s; layout {:.2e} s/particle",
            f(&self.cpu1),
            f(&self.cpu),
            self.gpu.as_ref().map_or("-".into(), f),
            self.gpu_build_s,
            self.layout_s_per_particle
        )
    }

    /// Times `PROBE_STEPS` steps of `cpu1.cells.f64`, `cpu.cells.f64` and (with a GPU) the first
    /// GPU variant of the plan at two small sizes.
    pub fn run(
        opts: &StudyOptions,
        gpu: Option<&Arc<GpuContext>>,
        first_gpu: Option<VariantSpec>,
    ) -> Result<Probe, String> {
        let t0 = Instant::now();
        let (mut ns, mut c1, mut c, mut g) = ([0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
        let mut p = Probe::default();
        for (k, &nx) in opts.probe_sizes.iter().enumerate() {
            let scene = study_scene_with(nx, &opts.sets)?;
            let tl = Instant::now();
            let layout = build_layout(&scene).map_err(|e| e.to_string())?;
            p.layout_s_per_particle = tl.elapsed().as_secs_f64() / layout.pos.len() as f64;
            let vel0 = initial_velocities(&scene, &layout, None);
            ns[k] = layout.pos.len() as f64;
            // Build time and ms/step; a run that fails while probing still costs its steps (the
            // study records the failure), a backend that cannot be built costs nothing.
            let time = |id: BackendId| -> Option<(f64, f64)> {
                let tb = Instant::now();
                let mut b = id.build(&scene, &layout, gpu).ok()?;
                b.restart_with_velocities(&vel0);
                let build = tb.elapsed().as_secs_f64();
                let _ = advance(b.as_mut(), 1);
                b.sync();
                let t = Instant::now();
                let _ = advance(b.as_mut(), PROBE_STEPS);
                b.sync();
                Some((build, t.elapsed().as_secs_f64() * 1e3 / PROBE_STEPS as f64))
            };
            let cpu1 = BackendId::Cpu { exec: Exec::Serial, search: SearchKind::Cells, precision: Precision::F64 };
            let cpu = BackendId::Cpu { exec: Exec::Parallel, search: SearchKind::Cells, precision: Precision::F64 };
            c1[k] = time(cpu1).map_or(f64::NAN, |x| x.1);
            c[k] = time(cpu).map_or(f64::NAN, |x| x.1);
            if let Some(spec) = first_gpu.filter(|_| gpu.is_some()) {
                let (build, ms) = time(BackendId::Gpu(spec)).unwrap_or((0.0, f64::NAN));
                if k == 0 {
                    p.gpu_build_s = build;
                }
                g[k] = ms;
            }
        }
        // A kind that could not be probed borrows the one-thread CPU's fit (or 1 µs/particle).
        let fallback = Fit { a_ms: 0.0, b_ms: 1e-3 };
        let fit = |ms: [f64; 2], or: Fit| if ms.iter().all(|x| x.is_finite()) { Fit::from(ns, ms) } else { or };
        let cpu1_fit = fit(c1, fallback);
        p.cpu1 = cpu1_fit;
        p.cpu = fit(c, cpu1_fit);
        p.gpu = first_gpu.filter(|_| gpu.is_some()).map(|_| fit(g, cpu1_fit));
        p.seconds = t0.elapsed().as_secs_f64();
        Ok(p)
    }

    /// Fills `est_s` of every job (in run order: a GPU variant's first job pays its compile).
    pub fn estimate(&self, jobs: &mut [Job], proto: &Protocol) {
        let mut compiled = BTreeSet::new();
        let mut sizes_seen = BTreeSet::new();
        for j in jobs.iter_mut() {
            let n = j.n as f64;
            let direct = match j.id {
                BackendId::Cpu { search, .. } => search == SearchKind::Direct,
                BackendId::Gpu(s) => s.search == SearchKind::Direct,
            };
            let (ms, build) = match j.id {
                BackendId::Cpu { exec: Exec::Serial, .. } => (self.cpu1.ms(n, direct), 0.0),
                BackendId::Cpu { .. } => (self.cpu.ms(n, direct), 0.0),
                BackendId::Gpu(s) => {
                    let first = compiled.insert(s.to_string());
                    (
                        self.gpu.unwrap_or(self.cpu).ms(n, direct),
                        if first { self.gpu_build_s } else { 0.1 * self.gpu_build_s },
                    )
                }
            };
            let layout = if sizes_seen.insert((j.experiment.clone(), j.nx)) {
                3.0 * self.layout_s_per_particle * n
            } else {
                0.0
            };
            let steps = proto.steps_besides_warmup(matches!(j.id, BackendId::Gpu(_))) as f64 * ms * 1e-3;
            let warm = proto.warmup_s.max(proto.steps as f64 * ms * 1e-3);
            j.est_s = build + layout + steps + warm;
            j.rep_s = proto.steps as f64 * ms * 1e-3;
        }
    }
}

/// The plan as text (printed first, and kept in `summary.md`).
pub fn describe(opts: &StudyOptions, sel: &Selected, notes: &[String], probe_s: f64) -> String {
    let mut s = String::new();
    let exps: Vec<&str> = opts.experiments.iter().map(String::as_str).collect();
    let _ = writeln!(s, "* experiments: {}", exps.join(", "));
    let mut ids: Vec<String> = sel.jobs.iter().map(|j| j.id.to_string()).collect();
    ids.sort();
    ids.dedup();
    let _ = writeln!(s, "* backends: {} ({})", ids.len(), ids.join(", "));
    let mut sizes: Vec<(u32, usize)> = sel.jobs.iter().map(|j| (j.nx, j.n)).collect();
    sizes.sort();
    sizes.dedup();
    let sz: Vec<String> = sizes.iter().map(|(nx, n)| format!("nx={nx} (N={n})")).collect();
    let _ = writeln!(s, "* sizes: {}", if sz.is_empty() { "none".into() } else { sz.join(", ") });
    let raised = if sel.repeats > opts.protocol.repeats {
        format!(" (raised from --repeats {} to use the budget)", opts.protocol.repeats)
    } else {
        String::new()
    };
    let topped = sel.jobs.iter().filter(|j| j.extra_blocks > 0).count();
    let topped = if topped > 0 {
        format!(
            "; {topped} of {} jobs (the cheapest first) get more timed blocks to fill the budget (records.csv `repeats`)",
            sel.jobs.len()
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        s,
        "* protocol: {} steps per device sync, {} repeats{raised}, {} s warm-up, {} latency samples{topped}",
        opts.protocol.steps, sel.repeats, opts.protocol.warmup_s, opts.protocol.latency_samples
    );
    let _ = writeln!(s, "* shard: {}; jobs: {}", opts.shard.label(), sel.jobs.len());
    let _ = writeln!(
        s,
        "* estimated time: {:.1} s for the kept jobs (all jobs of this shard: {:.1} s; probe: {:.1} s)",
        sel.est_s.max(0.0),
        sel.est_all_s.max(0.0),
        probe_s
    );
    let by: Vec<String> = sel.by_size.iter().map(|(nx, t)| format!("nx={nx}: {t:.1} s")).collect();
    let _ = writeln!(s, "* estimated time by size: {}", if by.is_empty() { "-".into() } else { by.join(", ") });
    if let Some(b) = opts.budget_s {
        let d: Vec<String> = sel.dropped_sizes.iter().map(|nx| format!("nx={nx}")).collect();
        let _ = writeln!(
            s,
            "* budget: {b:.0} s; dropped for it (largest first): {}",
            if d.is_empty() { "nothing".into() } else { d.join(", ") }
        );
        if sel.dropped_jobs > 0 {
            let _ = writeln!(
                s,
                "* budget: the smallest size alone overruns it: {} of its jobs dropped (kept and run in this order: the one-thread CPU references, the GPU rows, the other CPU rows, each while it fits)",
                sel.dropped_jobs
            );
        }
    }
    let e = &opts.e23;
    if exps.contains(&"e2") {
        let _ = writeln!(
            s,
            "* e2 (after the sweep, not in the estimate): nx={} ({} fluid), {} hybrids, {} verification steps each",
            e.e2_nx,
            e.e2_nx * e.e2_nx,
            super::e2_residency::HYBRIDS.len(),
            e.verify_steps
        );
    }
    if exps.contains(&"e3") {
        let b: Vec<String> = e.e3_budgets.iter().map(|b| b.to_string()).collect();
        let _ = writeln!(
            s,
            "* e3 (after the sweep, not in the estimate): nx={} ({} fluid), {} iterations, budgets {}, configurations {}",
            e.e3_nx,
            e.e3_nx * e.e3_nx,
            e.e3_steps,
            b.join(", "),
            super::e3_subdomains::CONFIGS.iter().map(|c| format!("{} {}", c.symbol, c.variant)).collect::<Vec<_>>().join(", ")
        );
    }
    for n in notes {
        let _ = writeln!(s, "* {n}");
    }
    s
}

mod select;
pub use select::{blocks_that_fit, select, Selected, BUDGET_FILL, MAX_REPEAT_FACTOR};

#[cfg(test)]
mod tests;
