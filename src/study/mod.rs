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
//! overrun gives back the budget's extra timed blocks before it is skipped). Every size times the
//! one-thread CPU with cells and tracking in f64 and f32 and the all-threads CPU: the same-run
//! baselines of [`baseline`]. Each job runs the shared start through the protocol of [`timing`]
//! (accuracy snapshot after K steps, K a whole number of tracking-list rebuild periods; warm-up
//! for a fixed time; latency; throughput in R blocks of K steps per sync) with the load average
//! and the other processes' CPU use read around it; [`stats`] gives the blocks' percentiles and bootstrap interval. A run
//! that overflowed, blew up or failed is a record with its `status` and `reason` and no timing;
//! a measured one is gated (`measured`): `inaccurate` beyond `verify`'s tolerances against the
//! CPU run of its precision, `loaded` when other processes used more than a quarter of the cores, else `ok`, the only status ranked. Errors
//! are against the CPU f64 one-thread run (`cpu1.cells.f64`) after the same K steps. GPU
//! pipelines are compiled once per variant and reused at every size (`gpu::pipeline_cache`).
//! Absolute GPU times mean something only on a real GPU; on lavapipe read ratios and correctness
//! only. Every backend is named by its [`BackendId`], the id the CLI, the bench and `records.csv`
//! use. [`preset`] is the one command for a GPU loan; [`report`] writes (and merges) the outputs,
//! opening with the answer table.

mod answer;
pub mod baseline;
pub mod e23;
pub mod e2_residency;
pub mod e3_subdomains;
pub mod engine_ab;
pub mod look;
mod measured;
mod overview_plots;
pub mod plan;
pub mod preset;
pub mod record;
pub mod report;
pub mod stats;
pub mod thesis_figs;
pub mod timing;

use crate::backend_id::BackendId;
use crate::error::Error;
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::scene::build::{build_layout, Layout};
use crate::scene::initial::initial_velocities;
use crate::scene::{builtin::builtin, overrides::apply_overrides, Scene};
use crate::sweep::Shard;
use crate::verify::Verifier;
use measured::{Common, Judge, References};
use plan::Job;
pub use record::Record;
use std::cell::OnceCell;
use std::sync::Arc;
use std::time::Instant;
use timing::{Failure, Protocol, Timed};

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
    /// Scene overrides applied to one backend's run only, by id: a variant made wrong on purpose,
    /// judged against the unperturbed references (the accuracy gate must call it `inaccurate`).
    pub perturb: Vec<(String, Vec<String>)>,
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
            perturb: Vec::new(),
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

/// One size's shared start, and the field check of its GPU variants (built on first use).
struct Start {
    scene: Scene,
    layout: Layout,
    vel0: Vec<[f64; 2]>,
    verifier: OnceCell<Verifier>,
    /// Neighbour-list entries per particle on the initial layout (the particle itself included,
    /// as the kernel sums include it): the pair interactions of one particle's evaluation.
    mean_neighbours: f64,
}

impl Start {
    /// The start of a size: `scene`, its layout and initial velocities, and its mean neighbour
    /// count (one cell search on the CPU, all threads).
    fn new(scene: Scene, layout: Layout, vel0: Vec<[f64; 2]>) -> Start {
        let model = crate::model::Model::<f64>::new(&scene);
        let pos: Vec<crate::real::V2<f64>> = layout.pos.iter().map(|p| crate::real::V2::new(p[0], p[1])).collect();
        let list = crate::neighbours::cells(crate::exec::Exec::Parallel, &model.images, &pos, model.support());
        Start { scene, layout, vel0, verifier: OnceCell::new(), mean_neighbours: list.mean_count() }
    }
}

/// The scene of `job` with the overrides [`StudyOptions::perturb`] gives its id, if any.
fn perturbed_scene(opts: &StudyOptions, job: &Job) -> Result<Option<Scene>, Error> {
    let id = job.id.to_string();
    let extra: Vec<String> = opts.perturb.iter().filter(|p| p.0 == id).flat_map(|p| p.1.iter().cloned()).collect();
    if extra.is_empty() {
        return Ok(None);
    }
    scene_at(job.nx, &[opts.sets.clone(), extra].concat()).map(Some)
}

/// Builds and times one job from the shared start (its scene `perturbed` where a test made the
/// job wrong on purpose).
fn run_job(
    job: &Job,
    s: &Start,
    perturbed: Option<&Scene>,
    gpu: Option<&Arc<GpuContext>>,
    p: &Protocol,
) -> Result<Timed, Failure> {
    let mut b = job.id.build(perturbed.unwrap_or(&s.scene), &s.layout, gpu).map_err(Failure::build)?;
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

/// The adapter's streaming bandwidth, measured once per run (when GPU jobs will run), before the
/// budget is shared out; under a budget the probe is sized to a small share of it.
fn run_bandwidth(
    opts: &StudyOptions,
    gpu: Option<&Arc<GpuContext>>,
    jobs: &[Job],
) -> Result<Option<crate::gpu::bandwidth::Bandwidth>, Error> {
    match gpu {
        Some(g) if !opts.dry_run && jobs.iter().any(|j| matches!(j.id, BackendId::Gpu(_))) => {
            let b =
                crate::gpu::bandwidth::measure_bandwidth_within(g, crate::gpu::bandwidth::PROBE_BYTES, opts.budget_s);
            b.map_err(|e| Error::Failed(format!("bandwidth probe: {e}")))
        }
        _ => Ok(None),
    }
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
    let bandwidth = run_bandwidth(opts, gpu, &all)?;
    let sel = plan::select(&all, opts, t0.elapsed().as_secs_f64());
    let mut text = plan::describe(opts, &sel, &notes, probe.seconds);
    text.push_str(&format!("* {}\n", probe.describe()));
    if let Some(b) = &bandwidth {
        text.push_str(&format!("* measured streaming bandwidth {:.2} GB/s ({})\n", b.gb_per_s, b.method));
    }
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
        bandwidth,
    };
    let (mut est_done, mut spent_done) = (0.0f64, 0.0f64);
    let mut references = References::default();
    let mut start: Option<(String, u32, Start)> = None;
    let (mut skipped, mut cut) = (Vec::new(), Vec::new());
    // Jobs the plan dropped for the budget are `skipped` records, so no table loses its row.
    let kept = |j: &Job| sel.jobs.iter().any(|k| k.experiment == j.experiment && k.nx == j.nx && k.id == j.id);
    for job in all.iter().filter(|j| !kept(j)) {
        out.push(common.skipped(job, "dropped by the plan: over the --budget"));
    }
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
                    let rec = common.skipped(job, "not run: the running estimate would have overrun the budget");
                    report::journal(&opts.out, std::slice::from_ref(&rec)).map_err(Error::Failed)?;
                    out.push(rec);
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
            start = Some((job.experiment.clone(), job.nx, Start::new(scene, layout, vel0)));
        }
        let s = &start.as_ref().expect("set above").2;
        let perturbed = perturbed_scene(opts, job)?;
        let watch = stats::Watch::start();
        let res = run_job(job, s, perturbed.as_ref(), gpu, &Protocol { repeats: blocks, ..protocol });
        let (load, others) = watch.stop();
        references.note(job, &res);
        let within_cap = opts.cpu_max_n.is_none_or(|m| s.layout.pos.len() <= m);
        let precision = job.id.precision();
        if within_cap {
            references.ensure(job.nx, Precision::F64, s, protocol.steps);
            references.ensure(job.nx, precision, s, protocol.steps);
        }
        let fields = match (job.id, gpu, &res) {
            (BackendId::Gpu(spec), Some(g), Ok(_)) if within_cap => Some(
                s.verifier.get_or_init(|| Verifier::new(&s.scene, 0, false)).variant_on(g, spec, perturbed.as_ref()),
            ),
            _ => None,
        };
        let judge = Judge {
            f64_ref: references.frame(job.nx, Precision::F64),
            same_ref: references.frame(job.nx, precision),
            fields: fields.as_ref(),
            load,
            others,
            cores: stats::cores(),
        };
        let rec = common.record(job, blocks, s, &res, &judge);
        print_outcome(job, &rec, &res);
        report::journal(&opts.out, std::slice::from_ref(&rec)).map_err(Error::Failed)?;
        out.push(rec);
        est_done += job.est_s;
        spent_done += tj.elapsed().as_secs_f64();
    }
    run_notes.outcome = outcome(opts.budget_s, t0.elapsed().as_secs_f64(), &cut, &skipped);
    Ok(run_notes)
}

/// One line on stderr per job: its time per step, or why it was not measured.
fn print_outcome(job: &Job, rec: &Record, res: &Result<Timed, Failure>) {
    match res {
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

/// Steps of one tracking-list rebuild period of `scene`: `TrackingCfg::every` force evaluations,
/// two per step with the midpoint integrator.
pub fn rebuild_period_steps(scene: &Scene) -> u64 {
    let evals = if scene.time.integrator == crate::scene::Integrator::Midpoint { 2 } else { 1 };
    u64::from(crate::neighbours::TrackingCfg::default().every).div_ceil(evals)
}

/// `opts` with K raised to a whole number of rebuild periods (a block with one rebuild more than
/// another is not a sample of the same thing), and the note saying so when it was raised.
fn whole_rebuild_periods(opts: &StudyOptions) -> (StudyOptions, Option<String>) {
    let mut o = opts.clone();
    let Ok(scene) = study_scene_with(o.e4_sizes.first().copied().unwrap_or(45), &o.sets) else { return (o, None) };
    let period = rebuild_period_steps(&scene);
    let k = o.protocol.steps.div_ceil(period) * period;
    if k == o.protocol.steps {
        return (o, None);
    }
    let note = format!(
        "K raised from {} to {k} steps: a whole number of tracking-list rebuild periods ({period} steps).",
        o.protocol.steps
    );
    eprintln!("study: {note}");
    o.protocol.steps = k;
    (o, Some(note))
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
    let run = format!("{} {}", crate::output::now_utc_iso8601(), opts.shard.label());
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
    let (whole, k_note) = whole_rebuild_periods(opts);
    let opts = &whole;
    // The job sweep (e1, e4, scaling); further experiments dispatch below by name.
    let mut notes = run_sweep(opts, gpu, t0, &mut recs)?;
    notes.outcome.extend(k_note);
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
    for r in recs.iter_mut() {
        r.run = run.clone();
    }
    baseline::annotate(&mut recs);
    report::write(&opts.out, &mut recs, gpu.map(|g| g.describe()), &notes).map_err(Error::Failed)?;
    Ok(recs)
}
