//! What `summary.json` of `sphlab run` holds: the scene and options as run, the particle
//! counts, the timing, the status, the resource plan, the provenance and the GPU engine's
//! counts.

use super::RunOptions;
use crate::backend::{EngineCounters, EnginePerStep};
use crate::gpu::bandwidth::EngineTraffic;
use crate::plan::Plan;
use crate::provenance::Provenance;
use crate::scene::Scene;
use serde::Serialize;

/// What `summary.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// The scene as run (all parameters).
    pub parameters: Scene,
    /// The options.
    pub options: RunOptions,
    /// Active stages in order.
    pub active_stages: Vec<&'static str>,
    /// Fluid particles per phase (by name).
    pub particles_per_phase: Vec<(String, usize)>,
    /// Wall particles.
    pub wall_particles: usize,
    /// Backend name (cpu, cpu1, or variant id).
    pub backend: String,
    /// The backend as it ran: a GPU variant with its list format resolved by N (`….slots`,
    /// `….masks` where the format is a choice), else the backend's own name.
    pub ran: String,
    /// Precision the backend computes in (f64, f32; a GPU variant's own).
    pub precision: String,
    /// dt of the last step.
    pub dt_last: f64,
    /// Steps taken after t = 0.
    pub steps: u64,
    /// Relaxation steps before t = 0.
    pub relax_steps: u64,
    /// Final time.
    pub t_final: f64,
    /// Wall time of the stepping after t = 0 (s).
    pub wall_time_s: f64,
    /// Wall time per step (ms).
    pub ms_per_step: f64,
    /// "running", "ok", "interrupted", "blow-up: …" or "failed" (an allocation or an output
    /// failed mid-run: [`Summary::error`] says which).
    pub status: String,
    /// Why a `failed` run stopped (the buffer and its bytes, or the output file).
    pub error: Option<String>,
    /// The resource plan the run was admitted with.
    pub plan: Plan,
    /// GPU runs: device bytes, modelled bytes per evaluation, measured bandwidth and the
    /// fraction of the memory roofline (`gpu::bandwidth`).
    pub gpu_engine: Option<EngineTraffic>,
    /// Commit, date, host, GPU and units.
    pub provenance: Provenance,
    /// Stability limits the fixed dt is above at load (`time.dt_policy = "warn"` only), and
    /// while running (from the output rows' measured |v| and |a|).
    pub dt_warnings: Vec<String>,
    /// The largest CFL / viscous numbers and dt over the force limit at the output rows.
    pub stability_numbers: crate::physics::timestep::StabilityNumbers,
    /// What the GPU engine did during the stepping after t = 0 (`None` on the CPU).
    pub engine: Option<EngineReport>,
    /// The most neighbours (itself and images included) one particle had in one evaluation
    /// over the whole run, relaxation included: what a GPU list's slots must hold (CPU
    /// backends; `None` on the GPU).
    pub peak_neighbours: Option<usize>,
}

/// The GPU engine's own counts over a run's stepping after t = 0 (`Backend::engine_counters`).
#[derive(Clone, Debug, Serialize)]
pub struct EngineReport {
    /// Largest batch of steps per submission.
    pub steps_per_submit: u64,
    /// Totals of the `advance` calls alone (the stepping).
    pub counters: EngineCounters,
    /// Submits, readbacks, dispatches and host writes per step of the stepping alone.
    pub per_step: EnginePerStep,
    /// Totals including the output frames (series rows and snapshots read every field back).
    pub with_output: EngineCounters,
    /// Per step including the output frames.
    pub per_step_with_output: EnginePerStep,
}
