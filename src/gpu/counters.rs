//! What the engine does to the device, counted where it happens: queue submissions, blocking
//! readbacks (a buffer mapped and waited for), compute dispatches and host writes
//! (`Queue::write_buffer`). One [`Traffic`] lives in each [`super::GpuContext`]; a solver reports
//! the difference since it was built ([`super::solver::GpuSolver::engine_counters`]), so the
//! figures are exact while one solver at a time works on a context (as `sphlab run` and the
//! study do).

use crate::backend::EngineCounters;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// Running totals of a context.
#[derive(Debug, Default)]
pub struct Traffic {
    submits: AtomicU64,
    readbacks: AtomicU64,
    dispatches: AtomicU64,
    writes: AtomicU64,
}

impl Traffic {
    /// One queue submission.
    pub fn submit(&self) {
        self.submits.fetch_add(1, Relaxed);
    }
    /// One blocking readback.
    pub fn readback(&self) {
        self.readbacks.fetch_add(1, Relaxed);
    }
    /// `n` compute dispatches recorded.
    pub fn dispatch(&self, n: u64) {
        self.dispatches.fetch_add(n, Relaxed);
    }
    /// One host write into a device buffer.
    pub fn write(&self) {
        self.writes.fetch_add(1, Relaxed);
    }
    /// The totals so far (`steps` left 0: the solver fills it).
    pub fn totals(&self) -> EngineCounters {
        EngineCounters {
            submits: self.submits.load(Relaxed),
            readbacks: self.readbacks.load(Relaxed),
            dispatches: self.dispatches.load(Relaxed),
            writes: self.writes.load(Relaxed),
            steps: 0,
        }
    }
}
