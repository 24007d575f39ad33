//! The `--budget` cut of the study's plan ([`select`]): the largest sizes dropped first, a
//! size that alone overruns trimmed by rank (references, GPU rows, other CPU rows), the budget
//! then filled with timed blocks; and [`blocks_that_fit`], the running check that gives a late
//! job's extra blocks back.

use super::Job;
use crate::backend_id::BackendId;
use crate::exec::Exec;
use crate::neighbours::SearchKind;
use crate::study::StudyOptions;

/// The plan after the shard and the budget: the jobs to run and what was dropped.
#[derive(Clone, Debug, Default)]
pub struct Selected {
    /// Jobs to run, in order.
    pub jobs: Vec<Job>,
    /// Sizes (nx) dropped whole for the budget, largest first.
    pub dropped_sizes: Vec<u32>,
    /// Jobs of the one size left that were dropped because that size alone overran the budget
    /// (in run order, each job that no longer fitted).
    pub dropped_jobs: usize,
    /// Estimated seconds of the kept jobs.
    pub est_s: f64,
    /// Estimated seconds of every job of the shard.
    pub est_all_s: f64,
    /// Estimated seconds of the shard's jobs by size (nx), before the budget cut.
    pub by_size: Vec<(u32, f64)>,
    /// Timed blocks per backend: `--repeats`, raised when the budget dropped sizes and the kept
    /// jobs leave slack (see [`BUDGET_FILL`]).
    pub repeats: usize,
}

/// When the budget binds (sizes were dropped), the kept jobs' timed blocks are raised until the
/// estimate reaches this fraction of the budget: first every job alike (`repeats`, at most
/// [`MAX_REPEAT_FACTOR`] × `--repeats`), then one block at a time to the cheapest jobs (the smallest
/// sizes, whose short blocks are the noisiest), so the fill is not quantised by a whole round of
/// blocks (a round of a 24-job scaling sweep on lavapipe costs 2.3 s, 12 % of a 20 s budget). The
/// budget buys tighter medians instead of idling, and the study ends within ±20 % of it. Aimed near
/// the budget: a slower run than estimated cannot overrun by much, since the running check in
/// `study::run_sweep` gives back a late job's extra blocks ([`blocks_that_fit`]) and skips a job
/// whose corrected estimate would overrun even without them.
pub const BUDGET_FILL: f64 = 0.95;
/// The most `--repeats` is multiplied by to fill a budget.
pub const MAX_REPEAT_FACTOR: usize = 4;

/// Keeps the jobs of `shard` and, under `budget_s` (counting `spent_s` already used), drops the
/// largest sizes first until the estimate fits, then fills the budget with timed blocks.
pub fn select(all: &[Job], opts: &StudyOptions, spent_s: f64) -> Selected {
    let mut jobs: Vec<Job> =
        all.iter().enumerate().filter(|(k, _)| opts.shard.owns(*k)).map(|(_, j)| j.clone()).collect();
    let est_all_s: f64 = jobs.iter().map(|j| j.est_s).sum();
    let mut by_size: Vec<(u32, f64)> = Vec::new();
    for j in &jobs {
        match by_size.iter_mut().find(|b| b.0 == j.nx) {
            Some(b) => b.1 += j.est_s,
            None => by_size.push((j.nx, j.est_s)),
        }
    }
    by_size.sort_by_key(|b| b.0);
    let mut dropped_sizes = Vec::new();
    let mut dropped_jobs = 0;
    if let Some(budget) = opts.budget_s {
        while spent_s + jobs.iter().map(|j| j.est_s).sum::<f64>() > budget {
            let (Some(largest), Some(smallest)) = (jobs.iter().map(|j| j.nx).max(), jobs.iter().map(|j| j.nx).min())
            else {
                break;
            };
            if largest == smallest {
                let before = jobs.len();
                jobs = keep_by_rank(jobs, budget - spent_s);
                dropped_jobs = before - jobs.len();
                break;
            }
            jobs.retain(|j| j.nx != largest);
            dropped_sizes.push(largest);
        }
    }
    let mut repeats = opts.protocol.repeats;
    if let (Some(budget), false) = (opts.budget_s, dropped_sizes.is_empty()) {
        let cap = MAX_REPEAT_FACTOR * repeats.max(1);
        let per_round: f64 = jobs.iter().map(|j| j.rep_s).sum();
        let mut room = BUDGET_FILL * budget - spent_s - jobs.iter().map(|j| j.est_s).sum::<f64>();
        if per_round > 0.0 && room > per_round {
            let extra = ((room / per_round).floor() as usize).min(cap.saturating_sub(repeats));
            for j in &mut jobs {
                j.est_s += extra as f64 * j.rep_s;
            }
            repeats += extra;
            room -= extra as f64 * per_round;
        }
        // The remainder, one block at a time, cheapest job first, while it fits.
        let mut order: Vec<usize> = (0..jobs.len()).filter(|&k| jobs[k].rep_s > 0.0).collect();
        order.sort_by(|&a, &b| jobs[a].rep_s.total_cmp(&jobs[b].rep_s));
        let mut added = true;
        while added {
            added = false;
            for &k in &order {
                if repeats + jobs[k].extra_blocks < cap && jobs[k].rep_s <= room {
                    jobs[k].extra_blocks += 1;
                    jobs[k].est_s += jobs[k].rep_s;
                    room -= jobs[k].rep_s;
                    added = true;
                }
            }
        }
    }
    let est_s = jobs.iter().map(|j| j.est_s).sum();
    Selected { jobs, dropped_sizes, dropped_jobs, est_s, est_all_s, by_size, repeats }
}

/// Where a job stands when one size alone overruns the budget: the references (one-thread CPU
/// cells, what every row is judged and sped up against) first, then the GPU rows (the study's
/// subject), then the other CPU rows (comparisons a starved study can do without).
fn rank(j: &Job) -> u8 {
    match j.id {
        BackendId::Cpu { exec: Exec::Serial, search: SearchKind::Cells, .. } => 0,
        BackendId::Gpu(_) => 1,
        BackendId::Cpu { .. } => 2,
    }
}

/// The jobs of one size that fit `left_s`: taken rank by rank ([`rank`]), each job in run order
/// that still fits (a costly job does not shut out cheaper ones after it), and run in that rank
/// order, so a study running later than estimated skips the least needed rows, not the GPU's.
fn keep_by_rank(mut jobs: Vec<Job>, left_s: f64) -> Vec<Job> {
    jobs.sort_by_key(rank);
    let mut t = 0.0;
    jobs.retain(|j| {
        let fits = t + j.est_s <= left_s;
        if fits {
            t += j.est_s;
        }
        fits
    });
    jobs
}

/// How many timed blocks `job` runs when it comes up with `left_s` of the budget left: its
/// planned `planned` blocks, or fewer (one at a time, down to the `min` that `--repeats` asked
/// for) when the running estimate (`est_s` scaled by `correction`, the spent/estimated ratio of
/// the jobs so far) would overrun. The fill's extra blocks are given back before a job is dropped
/// whole, so a study that runs late still ends near its budget. `None`: it does not fit even at
/// `min` (the job is skipped).
pub fn blocks_that_fit(job: &Job, planned: usize, min: usize, left_s: f64, correction: f64) -> Option<usize> {
    let min = min.max(1).min(planned);
    (min..=planned).rev().find(|&b| (job.est_s - (planned - b) as f64 * job.rep_s) * correction <= left_s)
}
