//! The cost side of a speed-against-error study, measured again now: each configuration's
//! scene is stepped for a short while in this process, one configuration after the other, so
//! that the study's times come from one machine state whatever machine and load its long runs
//! (reused or not) had. The error still comes from the long run; its time to solution is the
//! ms/step measured here times the long run's step count.

use super::report::RunRecord;
use super::{RunSpec, ValidateError};
use crate::run::{RunError, RunOptions};

/// Steps timed per repeat (after the scene's set-up; relaxation switched off).
pub const RETIME_STEPS: u64 = 200;
/// Repeats per configuration; the median is kept.
pub const RETIME_REPEATS: usize = 3;

/// A configuration's cost measured now.
#[derive(Clone, Copy, Debug)]
pub struct Retimed {
    /// ms per step: the median over [`RETIME_REPEATS`] repeats of [`RETIME_STEPS`] steps.
    pub ms_per_step: f64,
    /// The fastest and slowest repeat (ms per step).
    pub range: (f64, f64),
    /// The long run's steps times the median: its time to solution on this machine now (s).
    pub time_to_solution_s: f64,
}

impl Retimed {
    /// "X ms/step (median of n, lo–hi)".
    pub fn text(&self) -> String {
        format!("{:.2} ms/step (median of {RETIME_REPEATS}, {:.2}–{:.2})", self.ms_per_step, self.range.0, self.range.1)
    }
}

/// Times `spec`'s scene on `backend`, [`RETIME_REPEATS`] runs of [`RETIME_STEPS`] steps into a
/// scratch directory (removed afterwards), and scales the median by the steps of `long`.
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
    let mut ms = Vec::with_capacity(RETIME_REPEATS);
    for _ in 0..RETIME_REPEATS {
        let result = crate::run::run(&scene, &opts);
        let _ = std::fs::remove_dir_all(&dir);
        let summary =
            result.map_err(|err: RunError| ValidateError::Run { id: format!("{} (timing)", spec.id), err })?;
        ms.push(summary.ms_per_step);
    }
    ms.sort_by(f64::total_cmp);
    let median = ms[ms.len() / 2];
    Ok(Retimed {
        ms_per_step: median,
        range: (ms[0], ms[ms.len() - 1]),
        time_to_solution_s: 1e-3 * median * long.steps as f64,
    })
}
