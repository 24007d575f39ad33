//! The `sphlab run` driver: builds the scene, relaxes it if asked, applies the initial velocity
//! field, steps a backend and writes `series.csv`, particle snapshots (CSV, optional VTK with a
//! `.pvd` series) and `summary.json`. Before anything big is allocated the scene's resource
//! plan ([`crate::plan`]) is checked against the limits (exit 2). A blow-up keeps every file
//! written so far, writes a final snapshot and a summary naming the step and particle, and maps
//! to exit code 3; an interrupt ([`request_interrupt`], Ctrl-C) stops at the next step with a
//! final snapshot and `status: "interrupted"` (exit 130). A buffer that cannot be allocated
//! after all (diagnostic grid, VTK text) or an output that cannot be written stops the run with
//! the files so far closed and `status: "failed"` plus the reason in `summary.json` (exit 3 for
//! the allocation, naming the buffer and its bytes; exit 1 for the output).
//!
//! Modules: [`prepare`] (the checks, the plan, the backend, the output folder), [`step`] (the
//! step loop), [`finish`] (the final snapshot and summary of every way a run ends),
//! [`measure`] (the series row) and [`summary`] (`summary.json`).

mod finish;
mod measure;
mod prepare;
mod step;
mod summary;

pub use measure::{initial_radius, measure, try_measure, SeriesRow};
pub use prepare::{make_backend, make_backend_with_gpu_info, make_gpu_backend, plan_for, run, GpuBackend};
pub use step::batch_len;
pub use summary::{EngineReport, Summary};

use crate::backend::SolverError;
use crate::backend_id::BackendId;
use crate::fallible::AllocError;
use crate::output;
use crate::plan::Limits;
use crate::scene::SceneError;
use serde::Serialize;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPT: AtomicBool = AtomicBool::new(false);

/// Asks a running [`run`] to stop after its current step (the Ctrl-C handler calls this).
/// Returns true when an interrupt had already been requested.
pub fn request_interrupt() -> bool {
    INTERRUPT.swap(true, Ordering::SeqCst)
}

/// True once an interrupt was requested.
pub fn interrupt_requested() -> bool {
    INTERRUPT.load(Ordering::SeqCst)
}

/// Errors of a run, with their exit codes.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Bad input (exit 2).
    #[error("{0}")]
    Input(String),
    /// The run blew up (exit 3); outputs so far are kept.
    #[error("{0}")]
    BlowUp(SolverError),
    /// Writing an output failed (exit 1).
    #[error("{0}")]
    Output(output::OutputError),
    /// A buffer could not be allocated mid-run (exit 3); outputs so far are kept.
    #[error(
        "{source}{}; the outputs written before it are kept and summary.json says status \"failed\"",
        .file.as_ref().map_or(String::new(), |f| format!(", writing {}", f.display()))
    )]
    Alloc {
        /// What was being allocated, and how many bytes.
        source: AllocError,
        /// The output file it was for, if any.
        file: Option<PathBuf>,
    },
    /// Stopped by an interrupt (exit 130) after `step` steps; outputs so far are kept.
    #[error("interrupted at step {step} (t = {t:.6e}); a final snapshot and summary.json were written")]
    Interrupted {
        /// Steps taken.
        step: u64,
        /// Time reached.
        t: f64,
    },
}

impl From<output::OutputError> for RunError {
    fn from(e: output::OutputError) -> Self {
        match e {
            output::OutputError::Alloc { path, source } => RunError::Alloc { source, file: Some(path) },
            e => RunError::Output(e),
        }
    }
}

impl From<AllocError> for RunError {
    fn from(source: AllocError) -> Self {
        RunError::Alloc { source, file: None }
    }
}

impl From<SceneError> for RunError {
    fn from(e: SceneError) -> Self {
        RunError::Input(e.to_string())
    }
}

impl RunError {
    /// Process exit code.
    pub fn exit_code(&self) -> i32 {
        match self {
            RunError::Input(_) => 2,
            RunError::BlowUp(_) | RunError::Alloc { .. } => 3,
            RunError::Output(_) => 1,
            RunError::Interrupted { .. } => 130,
        }
    }
}

/// Options of `sphlab run`.
#[derive(Clone, Debug, Serialize)]
pub struct RunOptions {
    /// The backend (`cpu.cells.f64`, a GPU variant id, …).
    pub backend: BackendId,
    /// Overrides the scene's end time.
    pub t_end: Option<f64>,
    /// Run exactly this many steps instead.
    pub steps: Option<u64>,
    /// Output directory.
    pub out: PathBuf,
    /// A particle snapshot at every step that is a multiple of this (0: only the first and the
    /// last); the first (step 0) and the last step always get one.
    pub every: u64,
    /// Also write VTK.
    pub vtk: bool,
    /// No progress bar, no console lines.
    pub quiet: bool,
    /// Particle and memory limits of the resource plan.
    pub limits: Limits,
    /// At most this many steps per GPU submission (one readback each); the driver hands the
    /// backend [`BATCHES_PER_ADVANCE`] of them per `Backend::advance`, cut at output rows,
    /// snapshots and the end, so that a GPU keeps them in flight; 0: [`DEFAULT_STEPS_PER_SUBMIT`].
    pub steps_per_submit: u64,
}

/// Steps per submission when `--steps-per-submit` is 0 (output steps cut batches shorter).
pub const DEFAULT_STEPS_PER_SUBMIT: u64 = 64;
/// Submissions' worth of steps the driver hands the backend in one `Backend::advance` (the GPU
/// keeps them in flight, reading each one's control words one batch late).
pub const BATCHES_PER_ADVANCE: u64 = 4;
/// Largest accepted `--steps-per-submit` (a submission records ≈ 20 dispatches per step).
pub const MAX_STEPS_PER_SUBMIT: u64 = 4096;

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            backend: BackendId::default(),
            t_end: None,
            steps: None,
            out: PathBuf::from("out"),
            every: 10,
            vtk: false,
            quiet: true,
            limits: Limits::default(),
            steps_per_submit: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::RunError;
    use crate::fallible::AllocError;
    use crate::output::OutputError;

    #[test]
    fn an_allocation_failure_mid_run_exits_3_naming_the_buffer_and_bytes() {
        let source = AllocError { what: "the VTK text of one data array", bytes: 240_000_256 };
        let e = RunError::from(OutputError::Alloc { path: "out/particles_00000010.vtu".into(), source });
        assert_eq!(e.exit_code(), 3);
        let m = e.to_string();
        assert!(
            m.contains("could not allocate 240000256 bytes (228.88 MiB) for the VTK text of one data array")
                && m.contains("particles_00000010.vtu")
                && m.contains("status \"failed\""),
            "{m}"
        );
        let grid = RunError::from(AllocError { what: "the contact-angle gas grid", bytes: 1 << 30 });
        assert!(grid.exit_code() == 3 && grid.to_string().contains("gas grid"), "{grid}");
        let io = RunError::from(OutputError::Data { path: "x".into(), message: "m".into() });
        assert_eq!(io.exit_code(), 1);
    }
}
