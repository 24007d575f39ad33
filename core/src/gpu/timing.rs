//! Device-side timing: [`Timestamps`], a self-contained timestamp-query pool that the GPU solver
//! holds, off by default (ordinary runs record no query at all), switched on by
//! `GpuSolver::enable_timestamps` when the device has `Features::TIMESTAMP_QUERY`, in one of two
//! modes ([`DeviceTiming`]).
//!
//! **Batch time.** Each submission's steps sit between two empty compute passes, the first
//! writing a beginning-of-pass timestamp and the last an end-of-pass one ([`Timestamps::batch`]):
//! their difference is the device time of the engine as it runs, gaps between passes and the
//! clears included, one pair per submission.
//!
//! **How a stage is bracketed** (stage mode only). `GpuSolver::record` already records each stage's dispatches
//! in one compute pass of its own; with timing on, that pass gets `timestamp_writes` (a
//! beginning-of-pass and an end-of-pass timestamp, two consecutive slots of one query set). That
//! needs only `TIMESTAMP_QUERY`, not `TIMESTAMP_QUERY_INSIDE_PASSES` (`ComputePass::write_timestamp`)
//! nor `TIMESTAMP_QUERY_INSIDE_ENCODERS` (`CommandEncoder::write_timestamp`), so it works on every
//! adapter that has timestamps at all. What is timed is the compute pass: the buffer clears that
//! precede some stages (cell counts, accumulators, control words) and the ṽ copy of a step
//! without XSPH lie outside the passes and are not counted; a stage whose pass dispatches
//! nothing (empty domain) is not bracketed.
//!
//! **Collection.** Slot pairs are handed out in recording order with the stage name noted on the
//! host. The pool ([`CAPACITY`] queries, the wgpu maximum) is resolved only when it is nearly full
//! (checked before each submission, never inside one) and at each take ([`Timestamps::stage_times`]):
//! one `resolve_query_set` of the used range, a copy to a mappable buffer, a wait, and the
//! differences end − start times `Queue::get_timestamp_period()` (ns per tick) are summed per
//! stage name. Timing never touches the solver's buffers, so results are bit-identical with it
//! on or off (`tests/gpu_timing.rs`).

use super::{GpuContext, GpuError};
use crate::backend::{DeviceTimes, DeviceTiming};
use std::sync::Mutex;

/// Queries in the pool (the wgpu maximum per query set): 2,048 stage passes between resolves.
pub const CAPACITY: u32 = wgpu::QUERY_SET_MAX_QUERIES;
/// The label of a batch's timestamp pair (never a stage name).
const BATCH: &str = "(batch)";
/// Free queries wanted before a submission (one step records well under 100 passes).
const HEADROOM: u32 = 512;

/// Host-side bookkeeping of the pool.
#[derive(Default)]
struct State {
    /// Stage name of each slot pair written since the last resolve.
    labels: Vec<String>,
    /// Accumulated (stage, ns, passes) since the last take, in order of first appearance.
    acc: Vec<(String, f64, u64)>,
    /// Accumulated batch ns since the last take.
    batch_ns: f64,
    /// Passes left untimed because the pool was full (never expected; reported by a warning).
    missed: u64,
    /// Solver step at the last take.
    last_step: u64,
}

/// Per-stage (name, ns, passes) sums, the batch ns and the steps they cover.
type Taken = (Vec<(String, f64, u64)>, f64, u64);

/// The query set and its buffers, present only while timing is on.
struct Pool {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    period_ns: f64,
    /// Every stage in a pass of its own, bracketed (else only the batches).
    stages: bool,
    state: Mutex<State>,
}

impl Pool {
    /// The next free slot pair, labelled; `None` (and a miss counted) when the pool is full.
    fn slot(&self, label: &str) -> Option<u32> {
        let mut s = self.state.lock().unwrap_or_else(|p| p.into_inner());
        let k = s.labels.len() as u32;
        if 2 * k + 2 > CAPACITY {
            s.missed += 1;
            return None;
        }
        s.labels.push(label.to_string());
        Some(k)
    }
}

/// The solver's timestamp pool (`None` inside: timing off).
#[derive(Default)]
pub struct Timestamps(Option<Pool>);

impl Timestamps {
    /// Timestamp writes for the next stage pass, or `None` when stage timing is off or the pool
    /// is full.
    pub(super) fn writes(&self, stage: &str) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let pool = self.0.as_ref().filter(|p| p.stages)?;
        let k = pool.slot(stage)?;
        Some(wgpu::ComputePassTimestampWrites {
            query_set: &pool.set,
            beginning_of_pass_write_index: Some(2 * k),
            end_of_pass_write_index: Some(2 * k + 1),
        })
    }

    /// The writes of a batch's opening and closing empty passes (one slot pair), or `None` when
    /// timing is off or the pool is full.
    pub(super) fn batch(&self) -> Option<[wgpu::ComputePassTimestampWrites<'_>; 2]> {
        let pool = self.0.as_ref()?;
        let k = pool.slot(BATCH)?;
        let at = |begin: Option<u32>, end: Option<u32>| wgpu::ComputePassTimestampWrites {
            query_set: &pool.set,
            beginning_of_pass_write_index: begin,
            end_of_pass_write_index: end,
        };
        Some([at(Some(2 * k), None), at(None, Some(2 * k + 1))])
    }

    /// True while every stage is timed in a pass of its own (the solver then records unfused).
    pub fn stages_on(&self) -> bool {
        self.0.as_ref().is_some_and(|p| p.stages)
    }

    /// Resolves the pool when fewer than [`HEADROOM`] queries are left (call before recording a
    /// submission; the queries of earlier submissions are all submitted by then).
    pub(super) fn before_submit(&self, ctx: &GpuContext) -> Result<(), GpuError> {
        let Some(pool) = &self.0 else { return Ok(()) };
        let used = 2 * pool.state.lock().unwrap_or_else(|p| p.into_inner()).labels.len() as u32;
        if used + HEADROOM > CAPACITY {
            self.resolve(ctx)?;
        }
        Ok(())
    }

    /// Resolves every used query, reads the ticks back and adds them to the per-stage sums.
    fn resolve(&self, ctx: &GpuContext) -> Result<(), GpuError> {
        let Some(pool) = &self.0 else { return Ok(()) };
        let mut s = pool.state.lock().unwrap_or_else(|p| p.into_inner());
        let used = 2 * s.labels.len() as u32;
        if used == 0 {
            return Ok(());
        }
        let bytes = used as u64 * wgpu::QUERY_SIZE as u64;
        ctx.scoped(|d| {
            let mut enc =
                d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sphlab.timestamps") });
            enc.resolve_query_set(&pool.set, 0..used, &pool.resolve, 0);
            enc.copy_buffer_to_buffer(&pool.resolve, 0, &pool.staging, 0, bytes);
            ctx.queue.submit([enc.finish()]);
        })?;
        ctx.traffic.submit();
        let ticks: Vec<u64> = super::staging::map_read(ctx, &pool.staging, bytes)?;
        let labels = std::mem::take(&mut s.labels);
        for (k, label) in labels.into_iter().enumerate() {
            let ns = ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * pool.period_ns;
            if label == BATCH {
                s.batch_ns += ns;
                continue;
            }
            match s.acc.iter_mut().find(|(l, _, _)| *l == label) {
                Some(e) => {
                    e.1 += ns;
                    e.2 += 1;
                }
                None => s.acc.push((label, ns, 1)),
            }
        }
        Ok(())
    }

    /// Accumulated (stage, ns, passes), batch ns since the last take and the steps between the
    /// takes.
    fn take(&self, ctx: &GpuContext, step: u64) -> Result<Option<Taken>, GpuError> {
        let Some(pool) = &self.0 else { return Ok(None) };
        self.resolve(ctx)?;
        let mut s = pool.state.lock().unwrap_or_else(|p| p.into_inner());
        if s.missed > 0 {
            eprintln!("warning: {} passes were not timed (timestamp pool full)", s.missed);
            s.missed = 0;
        }
        let steps = step.saturating_sub(s.last_step);
        s.last_step = step;
        Ok(Some((std::mem::take(&mut s.acc), std::mem::take(&mut s.batch_ns), steps)))
    }
}

impl Timestamps {
    /// A pool on `ctx` timing `what`, whose first take covers the steps after `step`; off
    /// (nothing is timed) for [`DeviceTiming::Off`] or when the device lacks `TIMESTAMP_QUERY`.
    pub fn new(ctx: &GpuContext, step: u64, what: DeviceTiming) -> Self {
        if what == DeviceTiming::Off || !ctx.has(wgpu::Features::TIMESTAMP_QUERY) {
            return Timestamps(None);
        }
        let bytes = CAPACITY as u64 * wgpu::QUERY_SIZE as u64;
        let buffer = |label, usage| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as U;
        Timestamps(Some(Pool {
            set: ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("sphlab.timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: CAPACITY,
            }),
            resolve: buffer("sphlab.timestamps.resolve", U::QUERY_RESOLVE | U::COPY_SRC),
            staging: super::staging::staging_buffer(ctx, "sphlab.timestamps.staging", bytes),
            period_ns: ctx.queue.get_timestamp_period() as f64,
            stages: what == DeviceTiming::Stages,
            state: Mutex::new(State { last_step: step, ..State::default() }),
        }))
    }

    /// True while timing is on.
    pub fn is_on(&self) -> bool {
        self.0.is_some()
    }

    /// Device nanoseconds per stage name summed over every pass recorded since the last take,
    /// in order of first appearance; `None` when timing is off (never estimated).
    pub fn stage_times(&self, ctx: &GpuContext, step: u64) -> Result<Option<Vec<(String, f64)>>, GpuError> {
        let taken = self.take(ctx, step)?;
        Ok(taken.map(|(acc, _, _)| acc.into_iter().map(|(l, ns, _)| (l, ns)).collect()))
    }

    /// [`crate::backend::Backend::device_time`]: the batch time and the stage sums in ms and the
    /// steps they cover.
    pub fn device_times(&self, ctx: &GpuContext, step: u64) -> Option<DeviceTimes> {
        match self.take(ctx, step) {
            Ok(Some((acc, batch_ns, steps))) => {
                let stages: Vec<(String, f64)> = acc.into_iter().map(|(l, ns, _)| (l, ns * 1e-6)).collect();
                let stage_sum_ms = stages.iter().map(|s| s.1).sum();
                Some(DeviceTimes { batch_ms: batch_ns * 1e-6, stage_sum_ms, stages, steps })
            }
            Ok(None) => None,
            Err(e) => {
                eprintln!("warning: reading the GPU timestamps failed: {e}");
                None
            }
        }
    }
}

/// The shortest of `passes − 1` timestamped compute passes (the first is a warm-up), each
/// recorded by `record` and bracketed by beginning/end-of-pass timestamps, all in one
/// submission after which `after` may record more (a copy to read back); ns, `None` when no
/// pass measured above zero. The caller checks `TIMESTAMP_QUERY`.
pub(crate) fn best_pass_ns(
    ctx: &GpuContext,
    label: &str,
    passes: u32,
    mut record: impl FnMut(&mut wgpu::ComputePass<'_>),
    after: impl FnOnce(&mut wgpu::CommandEncoder),
) -> Result<Option<f64>, GpuError> {
    let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some(label),
        ty: wgpu::QueryType::Timestamp,
        count: 2 * passes,
    });
    let qbytes = 2 * passes as u64 * wgpu::QUERY_SIZE as u64;
    let resolve = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: qbytes,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = super::staging::staging_buffer(ctx, label, qbytes);
    ctx.scoped(|d| {
        let mut enc = d.create_command_encoder(&Default::default());
        for k in 0..passes {
            let writes = wgpu::ComputePassTimestampWrites {
                query_set: &set,
                beginning_of_pass_write_index: Some(2 * k),
                end_of_pass_write_index: Some(2 * k + 1),
            };
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: Some(writes),
            });
            record(&mut pass);
        }
        enc.resolve_query_set(&set, 0..2 * passes, &resolve, 0);
        enc.copy_buffer_to_buffer(&resolve, 0, &staging, 0, qbytes);
        after(&mut enc);
        ctx.queue.submit([enc.finish()]);
    })?;
    ctx.traffic.submit();
    let ticks: Vec<u64> = super::staging::map_read(ctx, &staging, qbytes)?;
    let period = ctx.queue.get_timestamp_period() as f64;
    let best = (1..passes as usize)
        .map(|k| ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * period)
        .filter(|&ns| ns > 0.0)
        .fold(f64::INFINITY, f64::min);
    Ok(best.is_finite().then_some(best))
}
