//! What the engine does to the device, counted where it happens: queue submissions, blocking
//! readbacks (a buffer mapped and waited for), compute dispatches, host writes
//! (`Queue::write_buffer`) and copies between device buffers. One [`Traffic`] lives in each [`super::GpuContext`]; a solver reports
//! the difference since it was built ([`super::solver::GpuSolver::engine_counters`]).
//!
//! The contract: those figures are the solver's own only while it is the one solver alive on its
//! context (as in `sphlab run` and the study, which build one solver at a time); work of another
//! solver, or of anything else on the context (the bandwidth probe), in between would be counted
//! too. Each solver holds a [`Claim`]; [`Claim::exclusive`] says whether the contract has held
//! since the solver was built (no other solver alive at its birth, none built since), and
//! `Backend::engine_counters` reports no counters rather than shared ones when it has not.

use crate::backend::EngineCounters;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

/// Running totals of a context.
#[derive(Debug, Default)]
pub struct Traffic {
    submits: AtomicU64,
    readbacks: AtomicU64,
    dispatches: AtomicU64,
    writes: AtomicU64,
    copies: AtomicU64,
    /// Solvers alive on the context.
    live: AtomicU64,
    /// Solvers built on the context so far.
    built: AtomicU64,
}

/// A solver's hold on its context's counters (released when dropped).
pub struct Claim {
    ctx: Arc<super::GpuContext>,
    /// `built` after this claim was made.
    born: u64,
    /// Another solver was alive when this one was built.
    shared_at_birth: bool,
}

impl Claim {
    /// Registers one more solver on `ctx`.
    pub fn new(ctx: Arc<super::GpuContext>) -> Self {
        let shared_at_birth = ctx.traffic.live.fetch_add(1, Relaxed) > 0;
        let born = ctx.traffic.built.fetch_add(1, Relaxed) + 1;
        Claim { ctx, born, shared_at_birth }
    }

    /// True while this solver has been the only one alive on its context since it was built, so
    /// that the context's counters since then are its own.
    pub fn exclusive(&self) -> bool {
        !self.shared_at_birth && self.ctx.traffic.built.load(Relaxed) == self.born
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        self.ctx.traffic.live.fetch_sub(1, Relaxed);
    }
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
    /// One buffer-to-buffer copy recorded on the device.
    pub fn copy(&self) {
        self.copies.fetch_add(1, Relaxed);
    }
    /// The totals so far (`steps` left 0: the solver fills it).
    pub fn totals(&self) -> EngineCounters {
        EngineCounters {
            submits: self.submits.load(Relaxed),
            readbacks: self.readbacks.load(Relaxed),
            dispatches: self.dispatches.load(Relaxed),
            writes: self.writes.load(Relaxed),
            copies: self.copies.load(Relaxed),
            steps: 0,
        }
    }
}
