//! How a run of `sphlab run` ends: the final snapshot and `summary.json` of a finished run with
//! its console lines, and of one stopped by a blow-up, an interrupt or a failed allocation or
//! output (every file written so far kept).

use super::step::Stepping;
use super::{EngineReport, RunError, Summary};
use crate::backend::{Backend, EngineCounters, Frame, SolverError};
use crate::output::{self, SeriesWriter, Snapshot};
use std::path::Path;

/// What the steps after t = 0 leave for the final summary.
pub(super) struct Stepped {
    /// Wall time of the steps (s).
    pub(super) wall: f64,
    /// The engine's counters before the first step (GPU only).
    pub(super) engine0: Option<EngineCounters>,
    /// The engine's counts of the `advance` calls alone.
    pub(super) stepping: EngineCounters,
    /// The series, still open.
    pub(super) series: SeriesWriter,
}

/// A run stopped by an allocation or output error: `summary.json` says `failed` and why (the
/// series and snapshot files are complete up to the last row and snapshot written). Other
/// errors wrote their own summary.
pub(super) fn failed(e: RunError, summary: &mut Summary, backend: &dyn Backend, path: &Path) -> RunError {
    if matches!(e, RunError::Alloc { .. } | RunError::Output(_)) {
        summary.status = "failed".into();
        summary.error = Some(e.to_string());
        summary.steps = backend.steps();
        summary.t_final = backend.time();
        let _ = output::write_json(path, &*summary);
    }
    e
}

/// The snapshot of a frame, its arrays moved (no copy).
fn snapshot(fr: Frame, h: f64) -> Snapshot {
    Snapshot {
        step: fr.step,
        t: fr.t,
        pos: fr.pos,
        vel: fr.vel,
        rho: fr.rho,
        p: fr.p,
        phase: fr.phase,
        grad_c: fr.grad_c,
        mass: fr.mass,
        h,
    }
}

impl Stepping<'_> {
    /// Writes the particle snapshot of a frame (and its VTK file with `--vtk`).
    pub(super) fn write_frame(&mut self, fr: Frame) -> Result<(), RunError> {
        let snap = snapshot(fr, self.scene.h());
        output::write_particles_csv(&self.opts.out, &snap)?;
        if let Some(p) = self.pvd.as_mut() {
            p.add_snapshot(&snap)?;
        }
        Ok(())
    }

    /// A failed or interrupted run keeps a final snapshot and a summary saying why it stopped.
    fn stop(&mut self, status: String) -> Result<(), RunError> {
        let fr = self.backend.frame();
        self.summary.dt_last = fr.dt;
        self.write_frame(fr)?;
        let summary = &mut *self.summary;
        summary.status = status;
        summary.steps = self.backend.steps();
        summary.t_final = self.backend.time();
        summary.ms_per_step = 1e3 * summary.wall_time_s / summary.steps.max(1) as f64;
        output::write_json(self.summary_path, &*summary)?;
        Ok(())
    }

    /// A blow-up after `wall` seconds of stepping: its message also quotes the largest CFL and
    /// viscous numbers reached before it; the summary keeps the wall time, steps and ms/step of
    /// the failed run.
    pub(super) fn fail(&mut self, mut e: SolverError, wall: f64) -> RunError {
        if let SolverError::BlowUp { what, .. } = &mut e {
            if !what.contains("CFL number") {
                what.push_str(&format!(
                    "; at the output rows before it: {}",
                    self.numbers.describe(self.scene.time.cfl)
                ));
            }
        }
        self.summary.stability_numbers = self.numbers;
        self.summary.peak_neighbours = self.backend.peak_neighbours();
        self.summary.wall_time_s = wall;
        let _ = self.stop(format!("blow-up: {e}"));
        RunError::BlowUp(e)
    }

    /// An interrupt: the final snapshot and summary, then [`RunError::Interrupted`].
    pub(super) fn interrupted(&mut self) -> RunError {
        match self.stop("interrupted".into()) {
            Ok(()) => RunError::Interrupted { step: self.backend.steps(), t: self.backend.time() },
            Err(e) => e,
        }
    }

    /// The final summary of a finished run: timing, status `ok`, the stability numbers, the
    /// GPU engine's counts, a warning when a fixed dt went past a limit; the series closed.
    pub(super) fn finish(self, stepped: Stepped) -> Result<(), RunError> {
        let Stepped { wall, engine0, stepping, series } = stepped;
        let (scene, opts) = (self.scene, self.opts);
        let numbers = self.numbers;
        let fr = self.backend.frame();
        let summary = &mut *self.summary;
        summary.dt_last = fr.dt;
        summary.steps = self.backend.steps();
        summary.t_final = self.backend.time();
        summary.wall_time_s = wall;
        summary.ms_per_step = 1e3 * wall / summary.steps.max(1) as f64;
        summary.status = "ok".into();
        summary.stability_numbers = numbers;
        summary.peak_neighbours = self.backend.peak_neighbours();
        if let Some(g) = summary.gpu_engine.as_mut() {
            g.roofline_fraction = g.fraction(wall / summary.steps.max(1) as f64);
        }
        if let (Some(c0), Some(c1)) = (engine0, self.backend.engine_counters()) {
            let with_output = c1.since(&c0);
            summary.engine = Some(EngineReport {
                steps_per_submit: self.k_max,
                counters: stepping,
                per_step: stepping.per_step(),
                with_output,
                per_step_with_output: with_output.per_step(),
            });
        }
        let (c, v, f) = (numbers.cfl_number, numbers.viscous_number, numbers.force_ratio);
        let viscous_max = crate::physics::timestep::VISCOUS_NUMBER_LIMIT;
        if scene.time.dt > 0.0 && (c > scene.time.cfl * (1.0 + 1e-9) || v > viscous_max * (1.0 + 1e-9) || f > 1.0) {
            let w = format!("while running, the fixed dt went past a limit: {}", numbers.describe(scene.time.cfl));
            if !opts.quiet {
                eprintln!("warning: {w}");
            }
            summary.dt_warnings.push(w);
        }
        series.finish()?;
        output::write_json(self.summary_path, &*summary)?;
        if !opts.quiet {
            say_done(summary, wall, &opts.out);
        }
        Ok(())
    }
}

/// The console lines of a finished run: steps, time, wall time, and the GPU engine's figures.
fn say_done(summary: &Summary, wall: f64, out: &Path) {
    eprintln!(
        "done: {} steps to t = {:.6e} in {:.2} s ({:.3} ms/step); outputs in {}",
        summary.steps,
        summary.t_final,
        wall,
        summary.ms_per_step,
        out.display()
    );
    if let Some(g) = &summary.gpu_engine {
        eprintln!("GPU engine (time per step from the wall clock, outputs included): {}", g.describe());
    }
    if let Some(e) = &summary.engine {
        let (p, o) = (e.per_step, e.per_step_with_output);
        eprintln!(
            "engine: {:.4} submits, {:.4} readbacks, {:.1} dispatches, {:.4} host writes, {:.1} device copies \
             per step ({} steps, at most {} per submit); with the output frames {:.3} submits, {:.3} readbacks per step",
            p.submits,
            p.readbacks,
            p.dispatches,
            p.writes,
            p.copies,
            e.counters.steps,
            e.steps_per_submit,
            o.submits,
            o.readbacks
        );
    }
}
