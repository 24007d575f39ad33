//! What every backend (CPU reference, GPU variants) offers the run driver: stepping, a frame of
//! the particle state in f64 for output and diagnostics, errors that name the step and particle
//! when a run blows up, and device counters. The executors implement [`Backend`]; the typed id
//! that names and builds one is [`crate::backend_id::BackendId`].

use crate::fields::Fields;
use crate::real::{Real, V2};
use serde::Serialize;

/// A read-back of the particle state, in f64, fluids first.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Frame {
    /// Step count.
    pub step: u64,
    /// Simulated time.
    pub t: f64,
    /// Last dt.
    pub dt: f64,
    /// Number of fluid particles.
    pub n_fluid: usize,
    /// Positions.
    pub pos: Vec<[f64; 2]>,
    /// Velocities.
    pub vel: Vec<[f64; 2]>,
    /// Densities.
    pub rho: Vec<f64>,
    /// Pressures.
    pub p: Vec<f64>,
    /// Masses.
    pub mass: Vec<f64>,
    /// Fluid phase, or `WALL`.
    pub phase: Vec<u32>,
    /// Colour index (−1 none).
    pub colour: Vec<i32>,
    /// Colour gradient (sum over the other colours).
    pub grad_c: Vec<[f64; 2]>,
    /// Surface stress (xx, xy).
    pub pi: Vec<[f64; 2]>,
    /// Acceleration of the last evaluation.
    pub acc: Vec<[f64; 2]>,
    /// Number density σ.
    pub sigma: Vec<f64>,
    /// Contact points (x, y, s) of the last evaluation.
    pub contacts: Vec<[f64; 3]>,
}

impl Frame {
    /// Bytes per particle of a frame: pos, vel, grad_c, pi, acc (16 B each), rho, p, mass,
    /// sigma (8 B each), phase and colour (4 B each).
    pub const BYTES_PER_PARTICLE: f64 = (5 * 16 + 4 * 8 + 2 * 4) as f64;

    /// A frame from a solver's state and the fields of its last evaluation (CPU and GPU alike).
    #[allow(
        clippy::too_many_arguments,
        reason = "a frame gathers the solver's separate state arrays, the same on CPU and GPU"
    )]
    pub fn from_fields<T: Real>(
        step: u64,
        t: f64,
        dt: f64,
        n_fluid: usize,
        pos: &[V2<T>],
        vel: &[V2<T>],
        phase: &[u32],
        f: &Fields<T>,
    ) -> Frame {
        let c = |x: &T| x.f64();
        let v2 = |v: &V2<T>| [v.x.f64(), v.y.f64()];
        Frame {
            step,
            t,
            dt,
            n_fluid,
            pos: pos.iter().map(v2).collect(),
            vel: vel.iter().map(v2).collect(),
            rho: f.rho.iter().map(c).collect(),
            p: f.p.iter().map(c).collect(),
            mass: f.mass.iter().map(c).collect(),
            phase: phase.to_vec(),
            colour: f.colour.clone(),
            grad_c: (0..f.grad.len()).map(|i| v2(&f.grad_c(i))).collect(),
            pi: f.pi.iter().map(|t| [t.xx.f64(), t.xy.f64()]).collect(),
            acc: f.acc.iter().map(v2).collect(),
            sigma: f.sigma.iter().map(c).collect(),
            contacts: f.contacts.iter().map(|k| [k.r.x.f64(), k.r.y.f64(), k.s.f64()]).collect(),
        }
    }
}

/// Why a run stopped.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// NaN/inf or a particle outside the domain (exit code 3).
    #[error("blow-up at step {step} (t = {t:.6e}): particle {particle} {what}")]
    BlowUp {
        /// Step at which it was detected.
        step: u64,
        /// Time.
        t: f64,
        /// Particle id.
        particle: usize,
        /// What happened.
        what: String,
    },
    /// More contact points than the fixed capacity.
    #[error("step {step}: {count} contact points exceed the capacity of {cap}")]
    ContactOverflow {
        /// Step.
        step: u64,
        /// Points found.
        count: usize,
        /// Capacity.
        cap: usize,
    },
    /// A particle has more neighbours than the variant's slots (GPU block layouts).
    #[error(
        "step {step}: {particles} particles have more than {slots} neighbours (max {max}), the first {}; variant {variant} cannot hold them",
        .particle.map_or("not recorded".to_string(), |p| format!("particle {p}"))
    )]
    NeighbourOverflow {
        /// Step.
        step: u64,
        /// The overflowing particle with the lowest (device) index in that step, as an original
        /// particle id (`None`: not recorded).
        particle: Option<usize>,
        /// Number of overflowing particles.
        particles: usize,
        /// Slot capacity.
        slots: usize,
        /// Largest count seen.
        max: usize,
        /// Variant id.
        variant: String,
    },
    /// A GPU failure.
    #[error("GPU: {0}")]
    Gpu(String),
}

/// What device timing records (GPU timestamp queries).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DeviceTiming {
    /// Nothing is timed (the default).
    #[default]
    Off,
    /// One timestamp pair around the steps of each submission: the device time of the engine as
    /// it runs (fused passes), gaps between passes included.
    Batch,
    /// The batch pairs, and every stage in a pass of its own with its own pair (the unfused
    /// debug mode of the stage table): where the time goes, at the cost of more passes.
    Stages,
}

/// Device time measured by GPU timestamps since the last [`Backend::device_time`] call.
#[derive(Clone, Debug, Default, Serialize)]
pub struct DeviceTimes {
    /// Device time of the submitted steps from one timestamp pair around each batch (ms).
    pub batch_ms: f64,
    /// Sum of the stage pass times (ms); 0 unless stage timing ([`DeviceTiming::Stages`]) was on.
    pub stage_sum_ms: f64,
    /// (stage name, ms) in order of first appearance: `neighbour_search`, …, `midpoint_predict`, ….
    pub stages: Vec<(String, f64)>,
    /// Solver steps taken in the interval.
    pub steps: u64,
}

/// What a backend did to its device (GPU: `gpu::counters`), summed since it was built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct EngineCounters {
    /// Queue submissions (each readback of a buffer is one too; a batch's control readback rides
    /// in the batch's own submission).
    pub submits: u64,
    /// Blocking readbacks (a buffer mapped and waited for).
    pub readbacks: u64,
    /// Compute dispatches.
    pub dispatches: u64,
    /// Host writes into device buffers (uploads, the clock at a restart).
    pub writes: u64,
    /// Buffer-to-buffer copies on the device (a renumbering's copy-back, ṽ = v).
    pub copies: u64,
    /// Time steps taken (relaxation included; restarts do not reset it).
    pub steps: u64,
}

impl EngineCounters {
    /// `self − earlier`, field by field (the work between two readings).
    pub fn since(&self, earlier: &EngineCounters) -> EngineCounters {
        EngineCounters {
            submits: self.submits - earlier.submits,
            readbacks: self.readbacks - earlier.readbacks,
            dispatches: self.dispatches - earlier.dispatches,
            writes: self.writes - earlier.writes,
            copies: self.copies - earlier.copies,
            steps: self.steps - earlier.steps,
        }
    }

    /// `self + more`, field by field.
    pub fn plus(&self, more: &EngineCounters) -> EngineCounters {
        EngineCounters {
            submits: self.submits + more.submits,
            readbacks: self.readbacks + more.readbacks,
            dispatches: self.dispatches + more.dispatches,
            writes: self.writes + more.writes,
            copies: self.copies + more.copies,
            steps: self.steps + more.steps,
        }
    }

    /// Submits, readbacks, dispatches, writes and copies per step (0 without steps).
    pub fn per_step(&self) -> EnginePerStep {
        let s = self.steps.max(1) as f64;
        let f = |x: u64| if self.steps == 0 { 0.0 } else { x as f64 / s };
        EnginePerStep {
            submits: f(self.submits),
            readbacks: f(self.readbacks),
            dispatches: f(self.dispatches),
            writes: f(self.writes),
            copies: f(self.copies),
        }
    }
}

/// [`EngineCounters`] divided by the steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct EnginePerStep {
    /// Submissions per step.
    pub submits: f64,
    /// Readbacks per step.
    pub readbacks: f64,
    /// Dispatches per step.
    pub dispatches: f64,
    /// Host writes per step.
    pub writes: f64,
    /// Device buffer copies per step.
    pub copies: f64,
}

/// A solver the run driver can step.
pub trait Backend {
    /// "cpu", "cpu1" or a GPU variant id.
    fn name(&self) -> String;
    /// Precision "f32" or "f64".
    fn precision(&self) -> &'static str;
    /// One time step.
    fn step(&mut self) -> Result<(), SolverError>;
    /// `k` time steps. The GPU records them into one submission with no host write in between
    /// and reads its flags and clock back once at the end (or, past
    /// [`Backend::set_steps_per_submit`], in several submissions kept in flight, each read back
    /// one batch late); the default (CPU) is `k` × `step()`. An error names the failing step;
    /// [`Backend::steps`] is then that step.
    fn advance(&mut self, k: u64) -> Result<(), SolverError> {
        for _ in 0..k {
            self.step()?;
        }
        Ok(())
    }
    /// Most steps one submission of [`Backend::advance`] records (0: all of them); the CPU has
    /// no submissions and ignores it.
    fn set_steps_per_submit(&mut self, _k: u64) {}
    /// Submissions, readbacks, dispatches and writes since the backend was built (GPU); `None`
    /// on the CPU.
    fn engine_counters(&self) -> Option<EngineCounters> {
        None
    }
    /// The most neighbours (itself and images included) one particle had in one evaluation
    /// since the backend was built: the CPU's lists; `None` on the GPU, whose list slots
    /// report only an overflow.
    fn peak_neighbours(&self) -> Option<usize> {
        None
    }
    /// Simulated time.
    fn time(&self) -> f64;
    /// Steps taken.
    fn steps(&self) -> u64;
    /// Reads the state back (fields of the last evaluation).
    fn frame(&mut self) -> Frame;
    /// Replaces the fluid velocities (relaxation end) and resets time and step to zero.
    fn restart_with_velocities(&mut self, vel: &[[f64; 2]]);
    /// Waits until all submitted work is done (GPU); a no-op on the CPU.
    fn sync(&mut self) {}
    /// A blow-up or overflow detected after the last `step()` returned (the GPU checks its
    /// device-side flags at output steps and in `frame()`); `None` on the CPU, which checks
    /// every step.
    fn take_error(&mut self) -> Option<SolverError> {
        None
    }
    /// Sets what device timing records (GPU timestamp queries); true when something is timed.
    /// The default (CPU, adapters without timestamps) is false: nothing is timed.
    fn enable_device_time(&mut self, what: DeviceTiming) -> bool {
        let _ = what;
        false
    }
    /// Device time since the last call when device timing is on; `None` otherwise (never an
    /// estimate).
    fn device_time(&mut self) -> Option<DeviceTimes> {
        None
    }
}
