//! The cost side of a speed-against-error study, measured again now: each configuration's
//! scene is stepped for a short while in this process, one configuration after the other, so
//! that the study's times come from one machine state whatever machine and load its long runs
//! (reused or not) had. The error still comes from the long run; its time to solution is the
//! ms/step measured here times the long run's step count. A configuration timed once is not
//! timed again in the same process (`validate all` reaches relax-60's resolutions from both the
//! convergence case and speed-vs-error): both cases then quote the same measurement.

use super::report::RunRecord;
use super::{RunSpec, ValidateError};
use crate::run::{RunError, RunOptions};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

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

/// One configuration's timing: the median ms/step and the fastest and slowest repeat.
type Timing = (f64, (f64, f64));

/// This process's timings by configuration (the timed scene and backend).
fn timed() -> &'static Mutex<HashMap<String, Timing>> {
    static TIMED: OnceLock<Mutex<HashMap<String, Timing>>> = OnceLock::new();
    TIMED.get_or_init(Default::default)
}

/// Times `spec`'s scene on `backend`, [`RETIME_REPEATS`] runs of [`RETIME_STEPS`] steps into a
/// scratch directory (removed afterwards), and scales the median by the steps of `long`. A
/// configuration already timed in this process is not timed again.
pub fn retime(
    spec: &RunSpec,
    long: &RunRecord,
    backend: crate::backend_id::BackendId,
) -> Result<Retimed, ValidateError> {
    let (median, range) = ms_per_step(spec, backend)?;
    Ok(Retimed { ms_per_step: median, range, time_to_solution_s: 1e-3 * median * long.steps as f64 })
}

/// `spec`'s ms/step on `backend` (median, range), from this process's earlier timing of the
/// same scene and backend where there is one.
fn ms_per_step(spec: &RunSpec, backend: crate::backend_id::BackendId) -> Result<Timing, ValidateError> {
    let mut scene = spec.scene()?;
    scene.relax = None;
    let key = format!("{backend:?}\n{}", scene.to_toml());
    if let Some(t) = timed().lock().ok().and_then(|m| m.get(&key).copied()) {
        return Ok(t);
    }
    let t = time_now(spec, &scene, backend)?;
    if let Ok(mut m) = timed().lock() {
        m.insert(key, t);
    }
    Ok(t)
}

/// The median and range of [`RETIME_REPEATS`] timings of `scene` (ms/step).
fn time_now(
    spec: &RunSpec,
    scene: &crate::scene::Scene,
    backend: crate::backend_id::BackendId,
) -> Result<Timing, ValidateError> {
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
        let result = crate::run::run(scene, &opts);
        let _ = std::fs::remove_dir_all(&dir);
        let summary =
            result.map_err(|err: RunError| ValidateError::Run { id: format!("{} (timing)", spec.id), err })?;
        ms.push(summary.ms_per_step);
    }
    ms.sort_by(f64::total_cmp);
    Ok((ms[ms.len() / 2], (ms[0], ms[ms.len() - 1])))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend_id::BackendId;

    fn spec(nx: u32) -> RunSpec<'static> {
        RunSpec::new(format!("retime-test-{nx}"), "oscillating-drop", &[format!("domain.nx={nx}")], None, 0)
    }

    #[test]
    fn a_configuration_is_timed_once_per_process() {
        let first = ms_per_step(&spec(10), "cpu1.cells.f64".parse::<BackendId>().unwrap()).unwrap();
        let again = ms_per_step(&spec(10), "cpu1.cells.f64".parse::<BackendId>().unwrap()).unwrap();
        assert_eq!(first, again, "the same configuration must quote the same timing");
        let other = ms_per_step(&spec(12), "cpu1.cells.f64".parse::<BackendId>().unwrap()).unwrap();
        assert_ne!(first, other, "another scene is timed on its own");
        assert!(first.0 > 0.0 && first.1 .0 <= first.0 && first.0 <= first.1 .1);
    }
}
