//! [`Record`], one row of the study's `records.csv` (STUDY.md §5): what ran, how it was timed,
//! and how its snapshot compares with the CPU reference.

use serde::{Deserialize, Serialize};

/// One benchmark record (STUDY.md §5). Timing and error columns are empty unless the run was
/// measured (`ok`, `inaccurate`, `loaded`); only `ok` records are ranked.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
// Columns a record file of an earlier version lacks read as their defaults (`sphlab report`).
#[serde(default)]
pub struct Record {
    /// Experiment (e1, e4, scaling).
    pub experiment: String,
    /// Backend id (`cpu1.cells.f64`, `cells.thread.recomputed.f32`, …; [`BackendId`](crate::backend_id::BackendId)).
    pub variant: String,
    /// One of [`STATUSES`].
    pub status: String,
    /// Why the record is not `ok` (empty when ok).
    pub reason: String,
    /// The run that wrote the record (its start date and shard): speedups compare records of
    /// one run only.
    pub run: String,
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
    /// 10th percentile of the blocks (ms per step).
    pub ms_per_step_p10: Option<f64>,
    /// 90th percentile of the blocks (ms per step).
    pub ms_per_step_p90: Option<f64>,
    /// Lower end of the bootstrap 95 % interval of the median (ms per step).
    pub ms_per_step_ci_lo: Option<f64>,
    /// Upper end of the bootstrap 95 % interval of the median (ms per step).
    pub ms_per_step_ci_hi: Option<f64>,
    /// 1-minute load average before the record was measured.
    pub load_before: Option<f64>,
    /// 1-minute load average after it.
    pub load_after: Option<f64>,
    /// Cores available to the study.
    pub cores: usize,
    /// Cores' worth of CPU other processes used on average while the record was measured (from
    /// `/proc/stat` less this process's own time); above a quarter of `cores` it is `loaded`.
    pub others_cores: Option<f64>,
    /// Latency: median wall time of one step followed by a device sync (ms).
    pub latency_ms_median: Option<f64>,
    /// `wall`, or `wall+timestamps` when the backend also reported GPU timestamps.
    pub timing: String,
    /// Median over the blocks of device time per step (ms): one GPU timestamp pair around each
    /// submission's steps (the engine as it runs, gaps between passes included).
    pub gpu_ms_per_step: Option<f64>,
    /// Sum of the per-stage device times per step (ms) in the stage-timed block, where every
    /// stage runs in a pass of its own (the unfused debug mode; `stage_times.csv` has the stages).
    pub stage_sum_ms_per_step: Option<f64>,
    /// Particle-evaluations per second: N × force evaluations per step ÷ seconds per step.
    pub particle_evals_per_s: Option<f64>,
    /// Neighbour-list entries per particle on the initial layout (the particle itself included).
    pub mean_neighbours: Option<f64>,
    /// Pair interactions per second: `particle_evals_per_s` × `mean_neighbours` (the figure
    /// DualSPHysics and SPHinXsys report as interactions per second).
    pub pair_interactions_per_s: Option<f64>,
    /// Relative kinetic-energy difference from the CPU f64 reference after the same K steps.
    pub ke_rel_error: Option<f64>,
    /// Centroid difference from the reference, in Δx.
    pub centroid_error_dx: Option<f64>,
    /// The baseline of `speedup_vs_baseline`: the fastest one-thread CPU search (`cpu1.cells` or
    /// `cpu1.tracking`) of this record's precision at its N in the same run.
    pub baseline: String,
    /// The baseline's ms/step ÷ this record's.
    pub speedup_vs_baseline: Option<f64>,
    /// The all-threads CPU of this precision (`cpu.cells.<precision>`, same run, same N): its
    /// ms/step ÷ this record's.
    pub speedup_vs_cpu_all: Option<f64>,
    /// `cpu1.cells.f64` of the same run at the same N (or scaled, see `cpu_ref`): its ms/step ÷
    /// this record's; kept for continuity with earlier reports.
    #[serde(alias = "speedup_vs_cpu1")]
    pub speedup_vs_cpu1_cells_f64: Option<f64>,
    /// `measured` (same N) or `scaled from N=…` (above `--cpu-max-n`), for
    /// `speedup_vs_cpu1_cells_f64`; empty without a base.
    pub cpu_ref: String,
    /// Shard (`i/n`) of the run that wrote the record.
    pub shard: String,
    /// git commit.
    pub commit: String,
    /// UTC date.
    pub date: String,
    /// Device ms per step of each stage in the stage-timed block (GPU timestamps, unfused;
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
    /// E3: device bytes allocated by the (subdomain) solver; sweep GPU records: the planned
    /// device bytes of the variant at this N.
    pub device_bytes: Option<u64>,
    /// E3: GPU busy fraction, device time (timestamps) ÷ wall time.
    pub gpu_busy: Option<f64>,
    /// E2: the GPU variant of the hybrids; E3: the thesis's configuration (○ ∆ □).
    pub config: String,
    /// E2/E3: verification verdict (against the CPU reference / the unsplit run).
    pub verified: String,
    /// Sweep GPU records: the largest N whose planned buffers fit this adapter's limits.
    pub max_n_fits: Option<u64>,
    /// engine: `before` (legacy engine) or `after` (current engine) (GPU), `cpu` ([`engine_ab`]).
    pub engine: String,
    /// GPU records: modelled bytes one force evaluation moves (`gpu::bandwidth`, a lower bound).
    pub modelled_bytes_per_eval: Option<f64>,
    /// GPU records: modelled bytes per step (per evaluation × evaluations per step).
    pub modelled_bytes_per_step: Option<f64>,
    /// GPU records: the adapter's streaming bandwidth measured once in this run (GB/s).
    pub bandwidth_gb_s: Option<f64>,
    /// GPU records: modelled bytes per step ÷ ms/step (GB/s): the bandwidth the step at least used.
    pub achieved_gb_s: Option<f64>,
    /// GPU records: `achieved_gb_s` ÷ `bandwidth_gb_s`, the fraction of the memory roofline.
    pub roofline_fraction: Option<f64>,
    /// engine: queue submissions per step (the engine's counters).
    pub submits_per_step: Option<f64>,
    /// engine: blocking readbacks per step.
    pub readbacks_per_step: Option<f64>,
    /// engine: compute dispatches per step.
    pub dispatches_per_step: Option<f64>,
}

/// Every status a record may have: measured and accurate (`ok`, the only one ranked); measured
/// but beyond `verify`'s tolerances (`inaccurate`) or while other processes used more than a quarter of
/// the cores (`loaded`); not measured because the run overflowed a neighbour layout (`overflow`), blew up
/// (`blown-up`), failed on the device or host (`failed`), or was not run (`skipped`: unsupported,
/// over a limit, out of budget).
pub const STATUSES: [&str; 7] = ["ok", "inaccurate", "loaded", "overflow", "blown-up", "failed", "skipped"];

impl Record {
    /// Ranked, plotted as a timing and eligible as "fastest": measured and accurate, unloaded.
    pub fn is_ok(&self) -> bool {
        self.status == "ok" && self.ms_per_step_median.is_some()
    }

    /// Throughput ms per step, NaN for a record without timing (a failed run).
    pub fn ms(&self) -> f64 {
        self.ms_per_step_median.unwrap_or(f64::NAN)
    }
}
