//! The cost side of a speed-against-error study, measured again now: each configuration's
//! scene is stepped for a short while in this process, one configuration after the other, so
//! that the study's times come from one machine state whatever machine and load its long runs
//! (reused or not) had. The error still comes from the long run; its time to solution is the
//! ms/step measured here times the long run's step count.

use super::report::RunRecord;
use super::{RunSpec, ValidateError};
use crate::run::{RunError, RunOptions};

/// Steps timed per configuration (after the scene's set-up; relaxation switched off).
pub const RETIME_STEPS: u64 = 200;

/// A configuration's cost measured now.
#[derive(Clone, Copy, Debug)]
pub struct Retimed {
    /// ms per step over [`RETIME_STEPS`] steps.
    pub ms_per_step: f64,
    /// The long run's steps times that: its time to solution on this machine now (s).
    pub time_to_solution_s: f64,
}

/// Times `spec`'s scene on `backend` for [`RETIME_STEPS`] steps into a scratch directory
/// (removed afterwards) and scales by the steps of `long`.
pub fn retime(
    spec: &RunSpec,
    long: &RunRecord,
    backend: crate::backend_id::BackendId,
) -> Result<Retimed, ValidateError> {
    let mut scene = spec.scene()?;
    scene.relax = None;
    let dir = std::env::temp_dir().join(format!("sphlab-retime-{}-{}", std::process::id(), spec.id));
    let opts = RunOptions {
        backend,
        t_end: None,
        steps: Some(RETIME_STEPS),
        out: dir.clone(),
        every: 0,
        vtk: false,
        quiet: true,
        ..RunOptions::default()
    };
    let result = crate::run::run(&scene, &opts);
    let _ = std::fs::remove_dir_all(&dir);
    let summary = result.map_err(|err: RunError| ValidateError::Run { id: format!("{} (timing)", spec.id), err })?;
    Ok(Retimed { ms_per_step: summary.ms_per_step, time_to_solution_s: 1e-3 * summary.ms_per_step * long.steps as f64 })
}
