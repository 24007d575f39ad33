//! How the study times one backend, honestly (docs/STUDY.md §5):
//!
//! 1. **Accuracy snapshot**: `K` steps from the shared start, a device sync, the error check,
//!    and the state read back: it is compared with the CPU f64 one-thread reference after the
//!    same `K` steps.
//! 2. **Warm-up for a fixed time** (`warmup_s`, at least one block of `K` steps), not a fixed
//!    count: pipelines, caches and clocks settle whatever the size.
//! 3. **Latency**: `latency_samples` single steps, each followed by a device sync (what one step
//!    costs when the host waits for it).
//! 4. **Throughput**: `repeats` blocks of `K` steps with one device sync per block; ms/step of a
//!    block = its wall time ÷ `K`. Where the adapter has timestamps, each submission's steps are
//!    bracketed by one timestamp pair ([`DeviceTiming::Batch`]: the engine as it runs, fused, gaps
//!    between passes included), read once per block: the device ms/step of the block.
//! 5. **Where the time goes** (GPU with timestamps): one more block of `K` steps with every stage
//!    in a pass of its own ([`DeviceTiming::Stages`], the stage table's unfused debug mode), whose
//!    per-stage times and their sum are reported beside (never instead of) the fused times.
//!
//! The solver's error flags ([`Backend::take_error`]) are read after the snapshot, after the
//! warm-up and after timing: a run that overflowed, blew up or failed on the device is a
//! [`Failure`], never a measurement.

use crate::backend::{Backend, DeviceTiming, Frame, SolverError};
use std::time::Instant;

/// The timing protocol.
#[derive(Clone, Copy, Debug)]
pub struct Protocol {
    /// Steps per device sync (K): the accuracy snapshot and every throughput block.
    pub steps: u64,
    /// Throughput blocks of K steps.
    pub repeats: usize,
    /// Warm-up wall time (s).
    pub warmup_s: f64,
    /// Single synced steps timed for the latency.
    pub latency_samples: usize,
}

impl Default for Protocol {
    fn default() -> Self {
        Protocol { steps: 10, repeats: 5, warmup_s: 0.5, latency_samples: 3 }
    }
}

impl Protocol {
    /// Steps one timed backend takes besides the warm-up (a GPU backend one block more: the
    /// stage-timed block).
    pub fn steps_besides_warmup(&self, gpu: bool) -> u64 {
        self.steps * (1 + self.repeats as u64 + u64::from(gpu)) + self.latency_samples as u64
    }
}

/// Why a run is not a measurement: `status` is `overflow`, `blown-up`, `failed` or `skipped`.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// overflow | blown-up | failed | skipped.
    pub status: &'static str,
    /// The solver's or builder's message.
    pub reason: String,
}

impl Failure {
    /// The failure of a solver error.
    pub fn of(e: &SolverError) -> Failure {
        let status = match e {
            SolverError::BlowUp { .. } => "blown-up",
            SolverError::NeighbourOverflow { .. } | SolverError::ContactOverflow { .. } => "overflow",
            SolverError::Gpu(_) => "failed",
        };
        Failure { status, reason: e.to_string() }
    }

    /// A backend that could not be built: `skipped` when the adapter or the plan says no
    /// (unsupported feature, over a limit), else `failed`.
    pub fn build(msg: String) -> Failure {
        let refused = msg.contains("unsupported") || msg.contains("resource plan") || msg.contains("limit");
        Failure { status: if refused { "skipped" } else { "failed" }, reason: msg }
    }
}

/// What one timed backend gave.
pub struct Timed {
    /// The state after the first K steps (the accuracy snapshot).
    pub snapshot: Frame,
    /// ms per step of each throughput block, sorted.
    pub block_ms: Vec<f64>,
    /// ms of each synced single step, sorted.
    pub latency_ms: Vec<f64>,
    /// Device ms per step of each block (one GPU timestamp pair per submission), sorted; empty
    /// without timestamps.
    pub device_ms: Vec<f64>,
    /// Device ms per step of each stage in the stage-timed (unfused) block.
    pub stage_ms: Vec<(String, f64)>,
    /// Their sum (ms per step); `None` without timestamps.
    pub stage_sum_ms: Option<f64>,
    /// Steps the warm-up took.
    pub warmup_steps: u64,
}

/// Steps per `Backend::advance` call: one GPU submission each. 32 steps record well under the
/// timestamp pool's 2,048 queries (about 22 passes a step), so no pass goes untimed.
pub const STEPS_PER_SUBMIT: u64 = 32;

/// `k` steps through `Backend::advance` (one submission and one control readback per
/// [`STEPS_PER_SUBMIT`] steps on the GPU; k single steps on the CPU).
pub fn advance(b: &mut dyn Backend, k: u64) -> Result<(), SolverError> {
    let mut left = k;
    while left > 0 {
        let n = left.min(STEPS_PER_SUBMIT);
        b.advance(n)?;
        left -= n;
    }
    Ok(())
}

/// Reads the error flags: `Err` when the run so far failed.
fn check(b: &mut dyn Backend) -> Result<(), Failure> {
    match b.take_error() {
        Some(e) => Err(Failure::of(&e)),
        None => Ok(()),
    }
}

fn run(b: &mut dyn Backend, k: u64) -> Result<(), Failure> {
    advance(b, k).map_err(|e| Failure::of(&e))?;
    b.sync();
    check(b)
}

/// K steps from the current state, synced and checked, then the state read back (checked again:
/// the GPU reads its flags with the frame).
pub fn snapshot(b: &mut dyn Backend, k: u64) -> Result<Frame, Failure> {
    run(b, k)?;
    let f = b.frame();
    check(b)?;
    Ok(f)
}

/// The whole protocol on `b` (built and restarted by the caller).
pub fn time_backend(b: &mut dyn Backend, p: &Protocol) -> Result<Timed, Failure> {
    let snapshot = snapshot(b, p.steps)?;
    let device = b.enable_device_time(DeviceTiming::Batch);
    let t0 = Instant::now();
    let mut warmup_steps = 0;
    while warmup_steps == 0 || t0.elapsed().as_secs_f64() < p.warmup_s {
        run(b, p.steps)?;
        warmup_steps += p.steps;
    }
    let mut latency_ms = Vec::new();
    for _ in 0..p.latency_samples {
        let t = Instant::now();
        run(b, 1)?;
        latency_ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let _ = b.device_time();
    let (mut block_ms, mut device_ms) = (Vec::new(), Vec::new());
    for _ in 0..p.repeats.max(1) {
        let t = Instant::now();
        advance(b, p.steps).map_err(|e| Failure::of(&e))?;
        b.sync();
        block_ms.push(t.elapsed().as_secs_f64() * 1e3 / p.steps as f64);
        if let Some(d) = device.then(|| b.device_time()).flatten() {
            device_ms.push(d.batch_ms / d.steps.max(1) as f64);
        }
    }
    check(b)?;
    let (mut stage_ms, mut stage_sum_ms) = (Vec::new(), None);
    if device && b.enable_device_time(DeviceTiming::Stages) {
        run(b, p.steps)?;
        if let Some(d) = b.device_time() {
            let per_step = |ms: f64| ms / d.steps.max(1) as f64;
            stage_ms = d.stages.iter().map(|(s, ms)| (s.clone(), per_step(*ms))).collect();
            stage_sum_ms = Some(per_step(d.stage_sum_ms));
        }
    }
    b.enable_device_time(DeviceTiming::Off);
    for v in [&mut block_ms, &mut latency_ms, &mut device_ms] {
        v.sort_by(f64::total_cmp);
    }
    Ok(Timed { snapshot, block_ms, latency_ms, device_ms, stage_ms, stage_sum_ms, warmup_steps })
}

/// The median of a sorted, non-empty slice.
pub fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}
