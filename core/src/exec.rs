//! How the CPU reference executes a per-particle loop: on all cores (rayon) or on exactly one
//! thread (the thesis's "single processor" baseline). Every loop is a gather (particle i only
//! writes its own outputs), so both give bit-identical results.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// CPU execution mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Exec {
    /// All cores (rayon); `--backend cpu`.
    Parallel,
    /// One thread; `--backend cpu1`.
    Serial,
}

impl Exec {
    /// Name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Exec::Parallel => "cpu",
            Exec::Serial => "cpu1",
        }
    }
}

/// `out[i] = f(i)` for every i.
#[inline]
pub fn fill<R: Send>(exec: Exec, out: &mut [R], f: impl Fn(usize) -> R + Sync + Send) {
    match exec {
        Exec::Parallel => out.par_iter_mut().enumerate().with_min_len(64).for_each(|(i, o)| *o = f(i)),
        Exec::Serial => out.iter_mut().enumerate().for_each(|(i, o)| *o = f(i)),
    }
}

/// Collects `f(i)` for `i in 0..n`.
#[inline]
pub fn map<R: Send>(exec: Exec, n: usize, f: impl Fn(usize) -> R + Sync + Send) -> Vec<R> {
    match exec {
        Exec::Parallel => (0..n).into_par_iter().with_min_len(64).map(f).collect(),
        Exec::Serial => (0..n).map(f).collect(),
    }
}
