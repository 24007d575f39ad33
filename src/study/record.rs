//! [`Record`], one row of the study's `records.csv` (STUDY.md §5): what ran, how it was timed,
//! and how its snapshot compares with the CPU reference.

use serde::{Deserialize, Serialize};

/// One benchmark record (STUDY.md §5). Timing and error columns are empty unless `status` is
/// `ok`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
// Columns a record file of an earlier version lacks read as their defaults (`sphlab report`).
#[serde(default)]
pub struct Record {
    /// Experiment (e1, e4, scaling).
    pub experiment: String,
    /// Backend id (`cpu1.cells.f64`, `cells.thread.recomputed.f32`, …; [`BackendId`](crate::backend_id::BackendId)).
    pub variant: String,
    /// ok | overflow | blow-up | error | refused.
    pub status: String,
    /// Why the run is not a measurement (empty when ok).
    pub reason: String,
    /// Scene name.
    pub scene: String,
    /// Particles across the box.
    pub nx: u32,
    /// Total particles (fluid + wall).
    pub n: usize,
    /// Fluid particles.
    pub n_fluid: usize,
    /// Steps per device sync (K): the accuracy snapshot and each throughput block.
    pub steps: u64,
    /// Throughput blocks of K steps.
    pub repeats: usize,
    /// Steps the warm-up (fixed wall time) took.
    pub warmup_steps: u64,
    /// cpu, cpu1 or gpu.
    pub backend: String,
    /// Adapter name (or "CPU").
    pub adapter: String,
    /// Driver and driver info.
    pub driver: String,
    /// Device type.
    pub device_type: String,
    /// CPU model.
    pub cpu_model: String,
    /// CPU threads used.
    pub cpu_threads: usize,
    /// f32 or f64.
    pub precision: String,
    /// Throughput: median over the blocks of wall time ÷ K (ms per step).
    pub ms_per_step_median: Option<f64>,
    /// Fastest block (ms per step).
    pub ms_per_step_min: Option<f64>,
    /// Slowest block (ms per step).
    pub ms_per_step_max: Option<f64>,
    /// Latency: median wall time of one step followed by a device sync (ms).
    pub latency_ms_median: Option<f64>,
    /// `wall`, or `wall+timestamps` when the backend also reported GPU timestamps.
    pub timing: String,
    /// Median over the blocks of device time per step (ms) from GPU timestamps.
    pub gpu_ms_per_step: Option<f64>,
    /// Particle-evaluations per second: N × force evaluations per step ÷ seconds per step.
    pub particle_evals_per_s: Option<f64>,
    /// Relative kinetic-energy difference from the CPU f64 reference after the same K steps.
    pub ke_rel_error: Option<f64>,
    /// Centroid difference from the reference, in Δx.
    pub centroid_error_dx: Option<f64>,
    /// Speedup over `cpu1.cells.f64` (filled by the report from the records).
    pub speedup_vs_cpu1: Option<f64>,
    /// `measured` (same N) or `scaled from N=…` (above `--cpu-max-n`); empty without a base.
    pub cpu_ref: String,
    /// Shard (`i/n`) of the run that wrote the record.
    pub shard: String,
    /// git commit.
    pub commit: String,
    /// UTC date.
    pub date: String,
    /// Mean device ms per step of each stage over the throughput blocks (GPU timestamps;
    /// written to `stage_times.csv`, not to `records.csv`).
    #[serde(skip)]
    pub stage_ms: Vec<(String, f64)>,
    /// E2: the stage groups on the CPU (`+`-joined, `-` for none); empty otherwise.
    pub residency_cpu: String,
    /// E2/E3: host → device bytes per step, counted at the copy calls.
    pub bytes_h2d_per_step: Option<f64>,
    /// E2/E3: device → host bytes per step, counted at the copy calls.
    pub bytes_d2h_per_step: Option<f64>,
    /// E3: particles per subdomain (empty: the unsplit run).
    pub budget: Option<usize>,
    /// E3: subdomains.
    pub subdomains: Option<usize>,
    /// E3: halo particles per force evaluation, summed over the subdomains.
    pub halo_particles: Option<f64>,
    /// E3: device bytes allocated by the (subdomain) solver.
    pub device_bytes: Option<u64>,
    /// E3: GPU busy fraction, device time (timestamps) ÷ wall time.
    pub gpu_busy: Option<f64>,
    /// E2: the GPU variant of the hybrids; E3: the thesis's configuration (○ ∆ □).
    pub config: String,
    /// E2/E3: verification verdict (against the CPU reference / the unsplit run).
    pub verified: String,
    /// engine: `before` (legacy engine) or `after` (current engine) (GPU), `cpu` ([`engine_ab`]).
    pub engine: String,
    /// engine: modelled bytes one force evaluation moves (`gpu::bandwidth`, a lower bound).
    pub modelled_bytes_per_eval: Option<f64>,
    /// engine: the adapter's measured streaming bandwidth (GB/s).
    pub bandwidth_gb_s: Option<f64>,
    /// engine: modelled bytes per step ÷ (ms/step × bandwidth).
    pub roofline_fraction: Option<f64>,
    /// engine: queue submissions per step (the engine's counters).
    pub submits_per_step: Option<f64>,
    /// engine: blocking readbacks per step.
    pub readbacks_per_step: Option<f64>,
    /// engine: compute dispatches per step.
    pub dispatches_per_step: Option<f64>,
}

impl Record {
    /// Throughput ms per step, NaN for a record without timing (a failed run).
    pub fn ms(&self) -> f64 {
        self.ms_per_step_median.unwrap_or(f64::NAN)
    }
}
