//! `sphlab study`: the thesis's Chapter 6 timing study (STUDY.md §4) and beyond, as records in
//! the format of STUDY.md §5 (`records.csv`, one row per backend × size) plus `summary.md` and
//! SVG plots.
//!
//! * **E1** (Fig. 6.3): neighbour search {direct, cells, tracking} × {CPU one thread, GPU} at
//!   2,025 fluid particles (the oscillating-drop box at nx = 45).
//! * **E4** (§6.5 headline): every GPU variant against the single-thread CPU NNPS (cells) at
//!   2,025 and 10,000 fluid particles (nx = 45, 100): the speedup (thesis: 120× on a 2012 GPU
//!   at 2,025).
//! * **scaling**: time per step against N for the CPU (one thread, all threads) and the GPU
//!   variants, log-log.
//!
//! The sweep is a list of jobs ([`plan`]): printed first with its estimated time, cut to
//! `--shard i/n` and to `--budget` (largest sizes dropped first; while running, a job that would
//! overrun gives back the budget's extra timed blocks before it is skipped). Each job runs the shared start
//! through the protocol of [`timing`] (accuracy snapshot after K steps, warm-up for a fixed
//! time, latency, throughput in blocks of K steps per sync); a run that overflowed, blew up or
//! failed is a record with its `status` and `reason` and no timing. The snapshot is compared
//! with the CPU f64 one-thread run (`cpu1.cells.f64`, whose own row is that same run) after the
//! same K steps; above `--cpu-max-n` there is no CPU run and the report compares the GPU rows
//! with the largest CPU size, scaled by N (marked `cpu_ref`). GPU pipelines are compiled once per
//! variant and reused at every size (`gpu::pipeline_cache`). Absolute GPU times mean something
//! only on a real GPU; on lavapipe read ratios and correctness only. Every backend is named by
//! its [`BackendId`], the id the CLI, the bench and `records.csv` use. [`preset`] is the one
//! command for a GPU loan; [`report`] writes (and merges) the outputs.

pub mod e23;
pub mod e2_residency;
pub mod e3_subdomains;
pub mod engine_ab;
pub mod plan;
pub mod preset;
pub mod record;
pub mod report;
pub mod thesis_figs;
pub mod timing;

use crate::backend::Frame;
use crate::backend_id::BackendId;
use crate::error::Error;
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::run::measure;
use crate::scene::build::{build_layout, Layout};
use crate::scene::initial::initial_velocities;
use crate::scene::{builtin::builtin, overrides::apply_overrides, Scene};
use crate::sweep::Shard;
use plan::Job;
pub use record::Record;
use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;
use timing::{median, Failure, Protocol, Timed};

/// Largest particle count at which the O(N²) `direct` GPU variants run by default.
pub const DIRECT_MAX_N: usize = 3000;

/// Every experiment `--experiments` accepts, in run order.
pub const EXPERIMENTS: &[&str] = &["e1", "e2", "e3", "e4", "scaling"];

/// What to run.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// Experiments (from [`EXPERIMENTS`]).
    pub experiments: Vec<String>,
    /// Scaling sizes (nx).
    pub sizes: Vec<u32>,
    /// The timing protocol.
    pub protocol: Protocol,
    /// GPU variants (empty: every supported one).
    pub variants: Vec<VariantSpec>,
    /// Extra scene overrides (`--set`), applied to every study scene.
    pub sets: Vec<String>,
    /// CPU rows only up to this many particles.
    pub cpu_max_n: Option<usize>,
    /// This run's part of the sweep.
    pub shard: Shard,
    /// Wall-time budget (s) of the whole study, probe included.
    pub budget_s: Option<f64>,
    /// Print the plan and stop.
    pub dry_run: bool,
    /// Output directory.
    pub out: std::path::PathBuf,
    /// E2 and E3 settings.
    pub e23: e23::E23Options,
    /// Resolution of the `engine` experiment ([`engine_ab`]).
    pub engine_nx: u32,
    /// E4 resolutions (45: the thesis's 2,025 fluid particles, Figs. 6.3/6.8; 100: 10,000).
    pub e4_sizes: Vec<u32>,
    /// The two resolutions the cost probe times ([`plan::Probe`]); near the sweep's own sizes so
    /// the largest are not extrapolated from N ≈ 10³.
    pub probe_sizes: [u32; 2],
}

impl Default for StudyOptions {
    fn default() -> Self {
        StudyOptions {
            // The sweep experiments; E2 and E3 (minutes at their thesis sizes) by name.
            experiments: plan::SWEEP_EXPERIMENTS.iter().map(|s| s.to_string()).collect(),
            sizes: vec![30, 60, 120],
            protocol: Protocol::default(),
            variants: Vec::new(),
            sets: Vec::new(),
            cpu_max_n: None,
            shard: Shard::default(),
            budget_s: None,
            dry_run: false,
            out: "reports/study".into(),
            e23: Default::default(),
            engine_nx: engine_ab::DEFAULT_NX,
            e4_sizes: vec![45, 100],
            probe_sizes: plan::PROBE_SIZES,
        }
    }
}

/// The study scene at resolution nx with extra overrides: the oscillating drop without
/// relaxation, its dt (1e-4 at nx = 30) rescaled by `time.dt_policy = "scale"` (∝ Δx while the
/// CFL limit binds, to nx ≈ 120).
pub fn study_scene_with(nx: u32, sets: &[String]) -> Result<Scene, String> {
    let mut all = vec![format!("domain.nx={nx}"), "relax.t=0".into(), "time.dt_policy=scale".into()];
    all.extend(sets.iter().cloned());
    let scene =
        apply_overrides(&builtin("oscillating-drop").expect("built-in"), &all).map_err(|e| format!("--set: {e}"))?;
    crate::scene::dt_policy::apply(&scene).map(|r| r.scene).map_err(|e| format!("--set: {e}"))
}

/// [`study_scene_with`] as the study's input: a scene that `--set` makes invalid is bad input.
fn scene_at(nx: u32, sets: &[String]) -> Result<Scene, Error> {
    study_scene_with(nx, sets).map_err(Error::Input)
}

/// The study scene at resolution nx (no extra overrides).
pub fn study_scene(nx: u32) -> Scene {
    study_scene_with(nx, &[]).expect("valid study scene")
}

/// One size's shared start.
struct Start {
    scene: Scene,
    layout: Layout,
    vel0: Vec<[f64; 2]>,
}

/// What every record of this run shares.
struct Common<'a> {
    gpu: Option<&'a Arc<GpuContext>>,
    commit: String,
    date: String,
    cpu_model: String,
    shard: String,
    protocol: Protocol,
}

impl Common<'_> {
    /// The record of `job`, run with `repeats` timed blocks: timed (`Ok`) or failed (status,
    /// reason, no timing).
    fn record(
        &self,
        job: &Job,
        repeats: usize,
        s: &Start,
        res: &Result<Timed, Failure>,
        reference: Option<&Frame>,
    ) -> Record {
        let (adapter, driver, device_type) = match (job.id, self.gpu) {
            (BackendId::Gpu(_), Some(g)) => {
                let i = &g.adapter_info;
                (i.name.clone(), format!("{} {}", i.driver, i.driver_info), format!("{:?}", i.device_type))
            }
            _ => ("CPU".into(), "-".into(), "Cpu".into()),
        };
        let mut r = Record {
            experiment: job.experiment.clone(),
            variant: job.id.to_string(),
            scene: s.scene.name.clone(),
            nx: s.scene.domain.nx,
            n: s.layout.pos.len(),
            n_fluid: s.layout.n_fluid,
            steps: self.protocol.steps,
            repeats,
            backend: job.id.kind().into(),
            adapter,
            driver,
            device_type,
            cpu_model: self.cpu_model.clone(),
            cpu_threads: job.threads,
            precision: job.id.precision().name().into(),
            shard: self.shard.clone(),
            commit: self.commit.clone(),
            date: self.date.clone(),
            ..Default::default()
        };
        let t = match res {
            Err(f) => {
                r.status = f.status.into();
                r.reason = f.reason.clone();
                return r;
            }
            Ok(t) => t,
        };
        r.status = "ok".into();
        let ms = median(&t.block_ms);
        let evals = if s.scene.time.integrator == crate::scene::Integrator::Midpoint { 2.0 } else { 1.0 };
        r.warmup_steps = t.warmup_steps;
        r.ms_per_step_median = Some(ms);
        r.ms_per_step_min = t.block_ms.first().copied();
        r.ms_per_step_max = t.block_ms.last().copied();
        r.latency_ms_median = (!t.latency_ms.is_empty()).then(|| median(&t.latency_ms));
        r.timing = if t.device_ms.is_empty() { "wall" } else { "wall+timestamps" }.into();
        r.gpu_ms_per_step = (!t.device_ms.is_empty()).then(|| median(&t.device_ms));
        r.particle_evals_per_s = Some(s.layout.pos.len() as f64 * evals / (ms * 1e-3));
        if let Some(c) = reference {
            let (a, c) = (measure(&s.scene, &t.snapshot), measure(&s.scene, c));
            let dx = s.scene.domain.dx();
            r.ke_rel_error = Some((a.kinetic_energy - c.kinetic_energy).abs() / c.kinetic_energy.abs().max(1e-300));
            r.centroid_error_dx = Some((a.centroid_x - c.centroid_x).hypot(a.centroid_y - c.centroid_y) / dx);
        }
        r.stage_ms = t.stage_ms.clone();
        r
    }
}

const REFERENCE: BackendId = BackendId::Cpu {
    exec: crate::exec::Exec::Serial,
    search: SearchKind::Cells,
    precision: crate::real::Precision::F64,
};

/// Builds and times one job from the shared start.
fn run_job(job: &Job, s: &Start, gpu: Option<&Arc<GpuContext>>, p: &Protocol) -> Result<Timed, Failure> {
    let mut b = job.id.build(&s.scene, &s.layout, gpu).map_err(Failure::build)?;
    b.restart_with_velocities(&s.vel0);
    timing::time_backend(b.as_mut(), p)
}

/// What the run of the plan adds to `summary.md`: the plan and how the budget went.
#[derive(Clone, Debug, Default)]
pub struct RunNotes {
    /// The plan as printed before the run (markdown list).
    pub plan: String,
    /// Lines on what happened (budget kept or not, jobs skipped while running).
    pub outcome: Vec<String>,
}

/// The probe's GPU variant: the default one if planned, else the first non-direct one.
fn probe_variant(jobs: &[Job]) -> Option<VariantSpec> {
    let planned: Vec<VariantSpec> = jobs
        .iter()
        .filter_map(|j| match j.id {
            BackendId::Gpu(s) => Some(s),
            _ => None,
        })
        .collect();
    planned
        .iter()
        .find(|s| **s == VariantSpec::default())
        .or_else(|| planned.iter().find(|s| s.search != SearchKind::Direct))
        .or(planned.first())
        .copied()
}

/// Runs the sweep experiments of `opts` (the plan first); appends records.
fn run_sweep(
    opts: &StudyOptions,
    gpu: Option<&Arc<GpuContext>>,
    t0: Instant,
    out: &mut Vec<Record>,
) -> Result<RunNotes, Error> {
    // The scenes the plan builds, checked first in its order: a bad `--set` is bad input, and
    // what fails in the plan after that is not.
    for e in opts.experiments.iter().filter(|e| plan::SWEEP_EXPERIMENTS.contains(&e.as_str())) {
        for nx in plan::sizes_of(e, opts) {
            scene_at(nx, &opts.sets)?;
        }
    }
    let (mut all, notes) = plan::jobs(opts, gpu).map_err(Error::Failed)?;
    let probe = if all.is_empty() {
        plan::Probe::default()
    } else {
        for &nx in &opts.probe_sizes {
            scene_at(nx, &opts.sets)?;
        }
        plan::Probe::run(opts, gpu, probe_variant(&all)).map_err(Error::Failed)?
    };
    probe.estimate(&mut all, &opts.protocol);
    let sel = plan::select(&all, opts, t0.elapsed().as_secs_f64());
    let mut text = plan::describe(opts, &sel, &notes, probe.seconds);
    text.push_str(&format!("* {}\n", probe.describe()));
    eprintln!("study plan:\n{text}");
    let mut run_notes = RunNotes { plan: text, outcome: Vec::new() };
    if opts.dry_run {
        return Ok(run_notes);
    }
    // The budget may raise the timed blocks (plan::select); every job and record uses the same.
    let protocol = Protocol { repeats: sel.repeats, ..opts.protocol };
    let common = Common {
        gpu,
        commit: crate::provenance::commit_label(),
        date: crate::output::now_utc_iso8601(),
        cpu_model: crate::provenance::cpu_model(),
        shard: opts.shard.label(),
        protocol,
    };
    let (mut est_done, mut spent_done) = (0.0f64, 0.0f64);
    let mut references: HashMap<u32, Option<Frame>> = HashMap::new();
    let mut start: Option<(String, u32, Start)> = None;
    let (mut skipped, mut cut) = (Vec::new(), Vec::new());
    for job in &sel.jobs {
        let elapsed = t0.elapsed().as_secs_f64();
        let correction = if est_done > 0.0 { (spent_done / est_done).clamp(0.2, 10.0) } else { 1.0 };
        let planned = protocol.repeats + job.extra_blocks;
        let blocks = match opts.budget_s {
            None => planned,
            Some(b) => match plan::blocks_that_fit(job, planned, opts.protocol.repeats, b - elapsed, correction) {
                Some(n) => n,
                None => {
                    skipped.push(format!("{} nx={} {}", job.experiment, job.nx, job.id));
                    continue;
                }
            },
        };
        if blocks < planned {
            cut.push(format!("{} nx={} {} ({planned} → {blocks})", job.experiment, job.nx, job.id));
        }
        let tj = Instant::now();
        if start.as_ref().is_none_or(|(e, nx, _)| *e != job.experiment || *nx != job.nx) {
            let scene = scene_at(job.nx, &opts.sets)?;
            let layout = build_layout(&scene).map_err(Error::failed)?;
            let vel0 = initial_velocities(&scene, &layout, None);
            start = Some((job.experiment.clone(), job.nx, Start { scene, layout, vel0 }));
        }
        let s = &start.as_ref().expect("set above").2;
        let res = run_job(job, s, gpu, &Protocol { repeats: blocks, ..protocol });
        if job.id == REFERENCE {
            references.entry(job.nx).or_insert_with(|| res.as_ref().ok().map(|t| t.snapshot.clone()));
        }
        let within_cap = opts.cpu_max_n.is_none_or(|m| s.layout.pos.len() <= m);
        if !references.contains_key(&job.nx) && within_cap {
            // This shard has no reference row at this size: its snapshot alone (not recorded).
            let r = REFERENCE.build(&s.scene, &s.layout, None).map_err(Failure::build).and_then(|mut b| {
                b.restart_with_velocities(&s.vel0);
                timing::snapshot(b.as_mut(), opts.protocol.steps)
            });
            references.insert(job.nx, r.ok());
        }
        let rec = common.record(job, blocks, s, &res, references.get(&job.nx).and_then(|r| r.as_ref()));
        match &res {
            Ok(_) => eprintln!(
                "{} nx={} {:<44} {:>10.3} ms/step (latency {:.3} ms)",
                job.experiment,
                job.nx,
                rec.variant,
                rec.ms_per_step_median.unwrap_or(f64::NAN),
                rec.latency_ms_median.unwrap_or(f64::NAN)
            ),
            Err(f) => eprintln!("{} nx={} {}: {}: {}", job.experiment, job.nx, rec.variant, f.status, f.reason),
        }
        report::journal(&opts.out, std::slice::from_ref(&rec)).map_err(Error::Failed)?;
        out.push(rec);
        est_done += job.est_s;
        spent_done += tj.elapsed().as_secs_f64();
    }
    run_notes.outcome = outcome(opts.budget_s, t0.elapsed().as_secs_f64(), &cut, &skipped);
    Ok(run_notes)
}

/// The lines of `summary.md` on how the budget went: the time it took, the timed blocks given
/// back (`cut`) and the jobs not run (`skipped`).
fn outcome(budget_s: Option<f64>, total: f64, cut: &[String], skipped: &[String]) -> Vec<String> {
    let mut lines = Vec::new();
    if let Some(b) = budget_s {
        lines.push(format!("Budget {b:.0} s: the study took {total:.1} s ({:.0} % of the budget).", 100.0 * total / b));
    }
    if !cut.is_empty() {
        lines.push(format!(
            "Timed blocks given back because the running estimate would have overrun the budget: {}.",
            cut.join("; ")
        ));
    }
    if !skipped.is_empty() {
        lines.push(format!(
            "Not run because the running estimate would have overrun the budget: {}.",
            skipped.join("; ")
        ));
    }
    lines
}

/// Runs the selected experiments and writes `records.csv`, `summary.md` and plots (nothing with
/// `dry_run`, which prints the plan only). An unknown experiment or a scene that `--set` makes
/// invalid is [`Error::Input`]; any other failure [`Error::Failed`].
pub fn run_study(opts: &StudyOptions) -> Result<Vec<Record>, Error> {
    let t0 = Instant::now();
    let gpu = GpuContext::new().map(Arc::new).map_err(|e| eprintln!("study: no GPU adapter ({e}); CPU only")).ok();
    run_study_on(opts, gpu.as_ref(), t0)
}

/// [`run_study`] on a given adapter (`None`: CPU only), the clock started at `t0`.
pub fn run_study_on(opts: &StudyOptions, gpu: Option<&Arc<GpuContext>>, t0: Instant) -> Result<Vec<Record>, Error> {
    let mut recs = Vec::new();
    for e in &opts.experiments {
        // `engine` runs only when named (not in `all` nor the preset: it is not budgeted).
        if !EXPERIMENTS.contains(&e.as_str()) && e != engine_ab::EXPERIMENT {
            let known = [EXPERIMENTS, &[engine_ab::EXPERIMENT]].concat();
            return Err(Error::Input(format!("--experiments: unknown experiment `{e}` ({})", known.join(", "))));
        }
    }
    if !opts.dry_run {
        // A journal left by an earlier study in this directory is not this run's.
        let _ = std::fs::remove_file(opts.out.join(report::JOURNAL));
    }
    // The job sweep (e1, e4, scaling); further experiments dispatch below by name.
    let notes = run_sweep(opts, gpu, t0, &mut recs)?;
    if opts.dry_run {
        return Ok(recs);
    }
    for e in opts.experiments.iter().filter(|e| !plan::SWEEP_EXPERIMENTS.contains(&e.as_str())) {
        let before = recs.len();
        match e.as_str() {
            "e2" | "e3" => match gpu {
                Some(g) if e == "e2" => {
                    e23::run_e2(&opts.e23, opts.protocol.steps, g, &mut recs).map_err(Error::Failed)?
                }
                Some(g) => e23::run_e3(&opts.e23, g, &mut recs).map_err(Error::Failed)?,
                None => eprintln!("{e}: skipped: it needs a GPU adapter"),
            },
            engine_ab::EXPERIMENT => {
                scene_at(opts.engine_nx, &opts.sets)?;
                engine_ab::run(opts, gpu, &mut recs).map_err(Error::Failed)?
            }
            other => return Err(Error::Input(format!("--experiments: `{other}` has no runner"))),
        }
        report::journal(&opts.out, &recs[before..]).map_err(Error::Failed)?;
    }
    report::write(&opts.out, &mut recs, gpu.map(|g| g.describe()), &notes).map_err(Error::Failed)?;
    Ok(recs)
}
