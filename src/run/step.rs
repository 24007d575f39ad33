//! The step loop of `sphlab run`: the relaxation before t = 0, the initial velocity field, then
//! the steps in batches ([`batch_len`]) cut at the series rows, the snapshots and the end, with
//! the rows and snapshots written between them. How a run ends (final summary, a blow-up, an
//! interrupt) is [`super::finish`].

use super::finish::Stepped;
use super::{
    interrupt_requested, try_measure, RunError, RunOptions, SeriesRow, Summary, BATCHES_PER_ADVANCE,
    DEFAULT_STEPS_PER_SUBMIT,
};
use crate::backend::{Backend, EngineCounters, Frame};
use crate::output::{self, PvdWriter, SeriesWriter};
use crate::physics::timestep::StabilityNumbers;
use crate::scene::build::Layout;
use crate::scene::initial::initial_velocities;
use crate::scene::Scene;
use std::path::Path;
use std::time::Instant;

/// Steps of the next batch from `step` at time `t`: at most `k_max`, ending at the next output
/// row (`rows`), snapshot (`snaps`, 0: none) and the end (`steps` if given); a time-driven run
/// leaves its last steps to single steps so it never passes `t_end` (estimating dt as `dt_est`:
/// up to the step before the end with a fixed dt, half the remaining steps with an adaptive one).
#[allow(clippy::too_many_arguments, reason = "the step loop's state, outputs and limits are named at the one call")]
pub fn batch_len(
    k_max: u64,
    step: u64,
    rows: u64,
    snaps: u64,
    steps: Option<u64>,
    t: f64,
    t_end: f64,
    dt_est: Option<(f64, bool)>,
) -> u64 {
    let next = |every: u64| step.checked_div(every).map_or(u64::MAX, |q| (q + 1) * every - step);
    let mut k = k_max.min(next(rows)).min(next(snaps));
    match (steps, dt_est) {
        (Some(n), _) => k = k.min(n.saturating_sub(step)),
        (None, Some((dt, fixed))) if dt > 0.0 => {
            let left = ((t_end - t) / dt).floor().clamp(0.0, 1e12) as u64;
            k = k.min(if fixed { left.saturating_sub(1) } else { left / 2 });
        }
        (None, _) => k = 1,
    }
    k.max(1)
}

/// A started run between its steps: what the step loop and the ends of the run share.
pub(super) struct Stepping<'a> {
    pub(super) scene: &'a Scene,
    pub(super) opts: &'a RunOptions,
    pub(super) backend: &'a mut Box<dyn Backend>,
    pub(super) summary: &'a mut Summary,
    pub(super) summary_path: &'a Path,
    /// CFL / viscous numbers at the output rows: the GPU's blow-up messages quote them (the CPU
    /// solver records them at every step itself).
    pub(super) numbers: StabilityNumbers,
    /// The VTK series once the steps after t = 0 begin (`--vtk`).
    pub(super) pvd: Option<PvdWriter>,
    /// At most this many steps per `Backend::advance`.
    pub(super) k_max: u64,
}

impl<'a> Stepping<'a> {
    /// The state of a run whose first summary is written.
    pub(super) fn new(
        scene: &'a Scene,
        opts: &'a RunOptions,
        backend: &'a mut Box<dyn Backend>,
        summary: &'a mut Summary,
        summary_path: &'a Path,
    ) -> Self {
        let k_max = if opts.steps_per_submit == 0 { DEFAULT_STEPS_PER_SUBMIT } else { opts.steps_per_submit };
        backend.set_steps_per_submit(k_max);
        Stepping { scene, opts, backend, summary, summary_path, numbers: StabilityNumbers::default(), pvd: None, k_max }
    }

    /// The stepping after the summary of a started run is written: relaxation, the initial
    /// velocity field, the steps with their series rows and snapshots, the final summary.
    pub(super) fn run(mut self, layout: &Layout) -> Result<(), RunError> {
        self.relax(layout)?;
        let stepped = self.steps()?;
        self.finish(stepped)
    }

    /// The series row of a frame, its CFL / viscous numbers recorded.
    fn note(&mut self, fr: &Frame) -> Result<SeriesRow, RunError> {
        let scene = self.scene;
        let row = try_measure(scene, fr)?;
        let a = fr.acc.get(..fr.n_fluid).map_or(0.0, |a| a.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max));
        let l = crate::scene::dt_policy::state_limits(scene, row.max_speed, a);
        self.numbers.record(fr.step, if fr.dt > 0.0 { fr.dt } else { l.min() }, scene.time.cfl, &l);
        Ok(row)
    }

    /// Relaxation (in batches of steps, never past its end), then the initial velocity field.
    fn relax(&mut self, layout: &Layout) -> Result<(), RunError> {
        let (scene, opts) = (self.scene, self.opts);
        let started = Instant::now();
        if let Some(r) = scene.relax.as_ref().filter(|r| r.t > 0.0) {
            let bar = if opts.quiet {
                output::Progress::hidden()
            } else {
                output::Progress::new((r.t / scene.time.dt.max(1e-300)).min(1e12) as u64, "relax")
            };
            let mut dt_est = (scene.time.dt > 0.0).then_some((scene.time.dt, true));
            while self.backend.time() < r.t * (1.0 - 1e-12) {
                let (step0, t0) = (self.backend.steps(), self.backend.time());
                if let Err(e) = self.backend.advance(batch_len(
                    self.k_max * BATCHES_PER_ADVANCE,
                    step0,
                    0,
                    0,
                    None,
                    t0,
                    r.t,
                    dt_est,
                )) {
                    return Err(self.fail(e, started.elapsed().as_secs_f64()));
                }
                if interrupt_requested() {
                    self.summary.relax_steps = self.backend.steps();
                    return Err(self.interrupted());
                }
                let step = self.backend.steps();
                if scene.time.dt <= 0.0 && step > step0 {
                    dt_est = Some(((self.backend.time() - t0) / (step - step0) as f64, false));
                }
                bar.inc(step - step0);
            }
            bar.finish();
            self.summary.relax_steps = self.backend.steps();
            let fr = self.backend.frame();
            self.backend.restart_with_velocities(&initial_velocities(scene, layout, Some(&fr)));
        } else if scene.initial_velocity.is_some() {
            self.backend.restart_with_velocities(&initial_velocities(scene, layout, None));
        }
        Ok(())
    }

    /// The steps after t = 0 to the end (`--steps` or the end time), the series rows and
    /// snapshots written as they fall due; an interrupt stops at the next batch's end.
    fn steps(&mut self) -> Result<Stepped, RunError> {
        let (scene, opts) = (self.scene, self.opts);
        let t_end = opts.t_end.unwrap_or(scene.time.t_end);
        let total = opts.steps.unwrap_or_else(|| {
            if scene.time.dt > 0.0 {
                (t_end / scene.time.dt).round().min(1e12) as u64
            } else {
                0
            }
        });
        let bar = if opts.quiet { output::Progress::hidden() } else { output::Progress::new(total, &scene.name) };
        let mut series = SeriesWriter::create(opts.out.join("series.csv"))?;
        self.pvd = if opts.vtk { Some(PvdWriter::new(&opts.out)) } else { None };
        let fr = self.backend.frame();
        series.write(&self.note(&fr)?)?;
        self.write_frame(fr)?;
        let start = Instant::now();
        let engine0 = self.backend.engine_counters();
        let mut stepping = EngineCounters::default();
        let done = |b: &dyn Backend| match opts.steps {
            Some(n) => b.steps() >= n,
            None => b.time() >= t_end * (1.0 - 1e-12),
        };
        // dt of the next steps, for the batch length of a time-driven run: the fixed dt, or the
        // mean of the last batch.
        let mut dt_est = (scene.time.dt > 0.0).then_some((scene.time.dt, true));
        while !done(self.backend.as_ref()) {
            let (step0, t0) = (self.backend.steps(), self.backend.time());
            let k = batch_len(
                self.k_max * BATCHES_PER_ADVANCE,
                step0,
                scene.output.every,
                opts.every,
                opts.steps,
                t0,
                t_end,
                dt_est,
            );
            let before = self.backend.engine_counters();
            if let Err(e) = self.backend.advance(k) {
                return Err(self.fail(e, start.elapsed().as_secs_f64()));
            }
            if let (Some(b), Some(a)) = (before, self.backend.engine_counters()) {
                stepping = stepping.plus(&a.since(&b));
            }
            let step = self.backend.steps();
            bar.inc(step - step0);
            if scene.time.dt <= 0.0 && step > step0 {
                dt_est = Some(((self.backend.time() - t0) / (step - step0) as f64, false));
            }
            let last = done(self.backend.as_ref());
            let row_due = step.is_multiple_of(scene.output.every) || last;
            let snap_due = last || (opts.every > 0 && step.is_multiple_of(opts.every));
            if row_due || snap_due {
                let fr = self.backend.frame();
                if let Some(e) = self.backend.take_error() {
                    return Err(self.fail(e, start.elapsed().as_secs_f64()));
                }
                if row_due {
                    series.write(&self.note(&fr)?)?;
                }
                if snap_due {
                    self.write_frame(fr)?;
                }
            }
            if interrupt_requested() && !last {
                self.summary.wall_time_s = start.elapsed().as_secs_f64();
                let fr = self.backend.frame();
                if !row_due {
                    series.write(&try_measure(scene, &fr)?)?;
                }
                series.finish()?;
                return Err(self.interrupted());
            }
        }
        bar.finish();
        let wall = start.elapsed().as_secs_f64();
        if let Some(e) = self.backend.take_error() {
            return Err(self.fail(e, wall));
        }
        Ok(Stepped { wall, engine0, stepping, series })
    }
}

#[cfg(test)]
mod tests {
    use super::batch_len;

    #[test]
    fn batches_end_at_outputs_and_never_pass_the_end() {
        // Step counts: the next row (every 10), snapshot (every 25) or the last step cuts.
        assert_eq!(batch_len(64, 0, 10, 0, Some(100), 0.0, 1.0, None), 10);
        assert_eq!(batch_len(64, 20, 10, 25, Some(100), 0.0, 1.0, None), 5);
        assert_eq!(batch_len(4, 0, 10, 0, Some(100), 0.0, 1.0, None), 4);
        assert_eq!(batch_len(64, 95, 1000, 0, Some(100), 0.0, 1.0, None), 5);
        // Time-driven, fixed dt 1/8 to t_end 4 (exact in binary): stop one step short, then
        // single steps.
        assert_eq!(batch_len(64, 0, 1000, 0, None, 0.0, 4.0, Some((0.125, true))), 31);
        assert_eq!(batch_len(64, 0, 1000, 0, None, 2.0, 4.0, Some((0.125, true))), 15);
        assert_eq!(batch_len(64, 0, 1000, 0, None, 3.875, 4.0, Some((0.125, true))), 1);
        // Adaptive: half the estimated remainder; no estimate yet: one step.
        assert_eq!(batch_len(64, 0, 1000, 0, None, 2.0, 4.0, Some((0.125, false))), 8);
        assert_eq!(batch_len(64, 0, 1000, 0, None, 0.0, 1.0, None), 1);
    }
}
