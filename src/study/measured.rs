//! A job's [`Record`] from its run (docs/STUDY.md §5): what ran and where, the statistics of its
//! timed blocks (median, p10/p90, bootstrap 95 % interval), its errors against the CPU f64
//! reference, and its status. The status is gated: a measured run whose K-step observables
//! (against the one-thread CPU cells run of its precision) or whose first evaluation's fields
//! (GPU variants, `verify::Verifier`) are beyond `verify`'s tolerances is `inaccurate`; one
//! measured while other processes used more than a quarter of the cores is `loaded`; neither
//! is ranked.

use super::plan::Job;
use super::stats::{bootstrap_median_ci, percentile};
use super::timing::{median, Failure, Protocol, Timed};
use super::{Record, Start};
use crate::backend::Frame;
use crate::backend_id::BackendId;
use crate::exec::Exec;
use crate::gpu::bandwidth::{Bandwidth, EngineTraffic};
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::run::measure;
use crate::verify::{observables, VariantReport};
use std::collections::HashMap;
use std::sync::Arc;

/// What every record of this run shares.
pub(super) struct Common<'a> {
    pub gpu: Option<&'a Arc<GpuContext>>,
    pub commit: String,
    pub date: String,
    pub cpu_model: String,
    pub shard: String,
    pub protocol: Protocol,
    /// The adapter's streaming bandwidth, measured once per run (`gpu::bandwidth`).
    pub bandwidth: Option<Bandwidth>,
}

/// What a job's record is judged against.
#[derive(Default)]
pub(super) struct Judge<'a> {
    /// `cpu1.cells.f64` after the same K steps: the reference of the error columns.
    pub f64_ref: Option<&'a Frame>,
    /// `cpu1.cells` of the record's precision after the same K steps: the observables' gate.
    pub same_ref: Option<&'a Frame>,
    /// `verify`'s report on the GPU variant's first evaluation (per-field tolerances).
    pub fields: Option<&'a VariantReport>,
    /// Load average before and after the job.
    pub load: (Option<f64>, Option<f64>),
    /// Cores' worth of CPU other processes used while the job ran (`None`: not measurable).
    pub others: Option<f64>,
    /// Cores available to the study.
    pub cores: usize,
}

impl Common<'_> {
    /// What every record of `job` says of where and what ran, before any measurement.
    fn base(&self, job: &Job) -> Record {
        let (adapter, driver, device_type) = match (job.id, self.gpu) {
            (BackendId::Gpu(_), Some(g)) => {
                let i = &g.adapter_info;
                (i.name.clone(), format!("{} {}", i.driver, i.driver_info), format!("{:?}", i.device_type))
            }
            _ => ("CPU".into(), "-".into(), "Cpu".into()),
        };
        Record {
            experiment: job.experiment.clone(),
            variant: job.id.to_string(),
            nx: job.nx,
            n: job.n,
            steps: self.protocol.steps,
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
        }
    }

    /// The record of a job that was not run (the budget dropped it): `skipped`, with `reason`.
    pub fn skipped(&self, job: &Job, reason: &str) -> Record {
        Record { status: "skipped".into(), reason: reason.into(), ..self.base(job) }
    }

    /// The record of `job`, run with `repeats` timed blocks: timed and judged (`Ok`), or failed
    /// (status, reason, no timing).
    pub fn record(&self, job: &Job, repeats: usize, s: &Start, res: &Result<Timed, Failure>, j: &Judge) -> Record {
        let mut r = Record {
            scene: s.scene.name.clone(),
            nx: s.scene.domain.nx,
            n: s.layout.pos.len(),
            n_fluid: s.layout.n_fluid,
            repeats,
            load_before: j.load.0,
            load_after: j.load.1,
            others_cores: j.others,
            cores: j.cores,
            ..self.base(job)
        };
        if let (BackendId::Gpu(spec), Some(g)) = (job.id, self.gpu) {
            let plan = crate::resources::run_plan(&s.scene, 4, true);
            let cpp = plan.cells / plan.n_total.max(1.0);
            r.device_bytes = plan.for_variant(&spec).gpu.map(|p| p.total_bytes);
            let lim = crate::gpu::plan::DeviceLimits::of(g, None);
            r.max_n_fits = Some(crate::gpu::plan::max_particles(&spec, cpp, &lim, crate::plan::HARD_MAX_PARTICLES));
        }
        let traffic = match job.id {
            BackendId::Gpu(spec) => {
                let (n, nf, bytes) = (s.layout.pos.len(), s.layout.n_fluid, r.device_bytes.unwrap_or(0));
                Some(EngineTraffic::new(&spec, &s.scene, n, nf, bytes, self.bandwidth.clone()))
            }
            _ => None,
        };
        if let Some(t) = &traffic {
            r.modelled_bytes_per_eval = Some(t.modelled_bytes_per_evaluation);
            r.modelled_bytes_per_step = Some(t.modelled_bytes_per_evaluation * t.evaluations_per_step);
            r.bandwidth_gb_s = t.bandwidth.as_ref().map(|b| b.gb_per_s);
        }
        let t = match res {
            Err(f) => {
                r.status = f.status.into();
                r.reason = f.reason.clone();
                return r;
            }
            Ok(t) => t,
        };
        let evals = if s.scene.time.integrator == crate::scene::Integrator::Midpoint { 2.0 } else { 1.0 };
        fill_timing(&mut r, t, evals);
        if let (Some(tr), Some(ms)) = (&traffic, r.ms_per_step_median) {
            r.roofline_fraction = tr.fraction(ms * 1e-3);
            r.achieved_gb_s = r.modelled_bytes_per_step.map(|b| b / (ms * 1e-3) * 1e-9);
        }
        r.mean_neighbours = Some(s.mean_neighbours);
        r.pair_interactions_per_s = r.particle_evals_per_s.map(|e| e * s.mean_neighbours);
        if let Some(c) = j.f64_ref {
            let (a, c) = (measure(&s.scene, &t.snapshot), measure(&s.scene, c));
            let dx = s.scene.domain.dx();
            r.ke_rel_error = Some((a.kinetic_energy - c.kinetic_energy).abs() / c.kinetic_energy.abs().max(1e-300));
            r.centroid_error_dx = Some((a.centroid_x - c.centroid_x).hypot(a.centroid_y - c.centroid_y) / dx);
        }
        let (status, reason) = judge(&s.scene, &t.snapshot, &r.precision, j);
        r.status = status.into();
        r.reason = reason;
        r
    }
}

/// The timing columns of a measured run: median, fastest and slowest block, p10/p90, the
/// bootstrap interval of the median, latency, device time and throughput.
pub(super) fn fill_timing(r: &mut Record, t: &Timed, evals: f64) {
    let ms = median(&t.block_ms);
    r.warmup_steps = t.warmup_steps;
    r.ms_per_step_median = Some(ms);
    r.ms_per_step_min = t.block_ms.first().copied();
    r.ms_per_step_max = t.block_ms.last().copied();
    r.ms_per_step_p10 = Some(percentile(&t.block_ms, 0.1));
    r.ms_per_step_p90 = Some(percentile(&t.block_ms, 0.9));
    let (lo, hi) = bootstrap_median_ci(&t.block_ms);
    r.ms_per_step_ci_lo = Some(lo);
    r.ms_per_step_ci_hi = Some(hi);
    r.latency_ms_median = (!t.latency_ms.is_empty()).then(|| median(&t.latency_ms));
    r.timing = if t.device_ms.is_empty() { "wall" } else { "wall+timestamps" }.into();
    r.gpu_ms_per_step = (!t.device_ms.is_empty()).then(|| median(&t.device_ms));
    r.stage_sum_ms_per_step = t.stage_sum_ms;
    r.particle_evals_per_s = Some(r.n as f64 * evals / (ms * 1e-3));
    r.stage_ms = t.stage_ms.clone();
}

/// A record is `loaded` when other processes used more than this fraction of the cores on
/// average while it was measured (this process's own threads, a CPU-emulated GPU's included,
/// do not count).
pub const LOADED_CORES: f64 = 0.25;

/// The status of a measured run and its reason: `failed` when the field check could not run,
/// `inaccurate` when a check is beyond its tolerance, `loaded` when other processes used more
/// than [`LOADED_CORES`] of the cores, else `ok` (with a note when no reference was there to check against).
fn judge(scene: &crate::scene::Scene, snapshot: &Frame, precision: &str, j: &Judge) -> (&'static str, String) {
    let mut beyond = Vec::new();
    if let Some(c) = j.same_ref {
        for k in observables(scene, snapshot, c).into_iter().filter(|k| !k.pass) {
            beyond.push(format!("{} {:.2e} (tolerance {:.0e})", k.name, k.max_rel, k.tolerance));
        }
    }
    if let Some(v) = j.fields {
        match v.status.as_str() {
            "pass" => {}
            "FAIL" => {
                for k in v.checks.iter().filter(|k| !k.pass) {
                    beyond.push(format!("{} {:.2e} (tolerance {:.0e})", k.name, k.max_rel, k.tolerance));
                }
            }
            other => return ("failed", format!("field check {other}: {}", v.reason)),
        }
    }
    if !beyond.is_empty() {
        let what = "beyond verify's tolerances against the CPU run of the same precision";
        return ("inaccurate", format!("{what} ({precision}): {}", beyond.join("; ")));
    }
    if let Some(o) = j.others.filter(|&o| o > LOADED_CORES * j.cores as f64) {
        let share = 100.0 * LOADED_CORES;
        return ("loaded", format!("other processes used {o:.2} of the {} cores (above {share:.0} %)", j.cores));
    }
    if j.same_ref.is_none() {
        return ("ok", "accuracy not checked: no CPU run of this precision at this N".into());
    }
    ("ok", String::new())
}

/// The one-thread CPU cells run of `precision`: the reference of that precision's gate.
pub(super) fn reference(precision: Precision) -> BackendId {
    BackendId::Cpu { exec: Exec::Serial, search: SearchKind::Cells, precision }
}

/// The CPU snapshots after K steps that records are judged against, per size and precision:
/// the `cpu1.cells.<precision>` job's own when this shard ran it first, else one taken for the
/// purpose (not recorded).
#[derive(Default)]
pub(super) struct References(HashMap<(u32, Precision), Option<Frame>>);

impl References {
    /// Keeps the snapshot of `job` if it is a reference run.
    pub fn note(&mut self, job: &Job, res: &Result<Timed, Failure>) {
        if let BackendId::Cpu { exec: Exec::Serial, search: SearchKind::Cells, precision } = job.id {
            self.0.entry((job.nx, precision)).or_insert_with(|| res.as_ref().ok().map(|t| t.snapshot.clone()));
        }
    }

    /// Takes the reference snapshot of `precision` at `nx` unless it is there.
    pub fn ensure(&mut self, nx: u32, precision: Precision, s: &Start, steps: u64) {
        self.0.entry((nx, precision)).or_insert_with(|| {
            let mut b = reference(precision).build(&s.scene, &s.layout, None).ok()?;
            b.restart_with_velocities(&s.vel0);
            super::timing::snapshot(b.as_mut(), steps).ok()
        });
    }

    /// The snapshot of `precision` at `nx`, if taken and the run did not fail.
    pub fn frame(&self, nx: u32, precision: Precision) -> Option<&Frame> {
        self.0.get(&(nx, precision)).and_then(|f| f.as_ref())
    }
}
