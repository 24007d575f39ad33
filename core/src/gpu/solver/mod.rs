//! The GPU solver: the whole step on the device for one [`VariantSpec`]. Particle data stay on
//! the device between steps, and so does the clock (step, t, dt: [`super::clock`]):
//! `Backend::advance(k)` records k whole steps (adaptive dt computed on the device) into ONE
//! submission and reads the control words and the clock back once at its end; `step()` is one
//! such step, read back every [`GpuSolver::check_every`] steps (every step with an adaptive dt,
//! whose time the host does not know otherwise) and at every `frame()`. A failing step (NaN,
//! escape, neighbour overflow) halts the device's integrators and clock, so the state read back
//! is the failing step's. Stage order, names and physics are those of `cpu::CpuSolver`.
//! [`GpuSolver::evaluate_once`] and [`GpuSolver::run_stage_from`] serve the stage-by-stage
//! verification against the CPU reference. Group 0 binds the particle state
//! ([`super::solver_buffers`]), group 1 the strategy buffers ([`super::variant_buffers`]:
//! lists, caches, tracking candidates, accumulators); neighbour overflow of the list-based
//! variants is read with the blow-up flag and reported as [`SolverError::NeighbourOverflow`].
//! The cell searches keep the fluid particles in cell order on the device (renumbered every
//! [`GpuSolver::set_reorder_every`] steps, group 2: [`super::reorder`]); everything the host
//! sees is in the original order.
//!
//! A step, as the stage table composes it (fused): the opening integrator stage with the cell
//! count and, on grids of at most `plan::FUSED_SCAN_CELLS` cells, the cell scan as epilogues
//! (the last workgroup scans); the evaluation, whose search then only merges the previous
//! search's lists into the new ones (`cell_merge`), then its neighbour passes with their
//! epilogues; the closing stage with the check, the clock tick, the count and the scan. The
//! debug mode ([`GpuSolver::set_fused`]) records every stage of the same table as a pass of its
//! own.

use super::clock::{write_clock, Control, ControlReader, BATCHES_IN_FLIGHT};
use super::params::Params;
use super::reorder::{self, RBufs};
use super::solver_buffers::{ctl, wall_cells, Bufs};
use super::stages::{Compiled, Domain, Pipelines};
use super::timing::Timestamps;
use super::variant::VariantSpec;
use super::variant_buffers::{self as vbufs, VBufs};
use super::{GpuContext, GpuError};
use crate::backend::{Backend, DeviceTimes, DeviceTiming, EngineCounters, Frame, SolverError};
use crate::fields::Fields;
use crate::gpu::plan::{DeviceLimits, GpuPlan};
use crate::model::{Model, COLOUR_WALL, MAX_CONTACTS, NO_COLOUR};
use crate::neighbours::cells::CellBox;
use crate::real::{Real, V2};
use crate::scene::build::Layout;
use crate::scene::{ContactMode, Integrator, Scene};
use crate::stage::{CellEpilogues, Clear, Stage};
use std::sync::Arc;

mod cpu_only;
mod record;
mod stepping;

/// The GPU solver in storage precision `T` (f32 or f64, as the variant says).
pub struct GpuSolver<T: Real> {
    pub(super) ctx: Arc<GpuContext>,
    pub(super) spec: VariantSpec,
    /// Constants (the same struct the CPU uses).
    pub model: Model<T>,
    pub(super) grid: CellBox<T>,
    pub(super) b: Bufs<T>,
    pub(super) vb: VBufs<T>,
    pub(super) rb: RBufs<T>,
    pub(super) pipes: Arc<Pipelines>,
    /// Group 0 with the twin arrays in their first roles, then swapped (`Bufs::roles_swapped`).
    pub(super) bgs: [wgpu::BindGroup; 2],
    /// Group 1, one per list chunk (`gpu::list_chunks`; the first for every unchunked kernel).
    pub(super) vbgs: Vec<wgpu::BindGroup>,
    pub(super) rbg: wgpu::BindGroup,
    /// The evaluation's passes (`stage::passes`), each with its fused kernels when it has
    /// epilogues.
    pub(super) passes: Vec<(Vec<Stage>, Option<Arc<Compiled>>)>,
    /// The opening integrator stage (`Stage::opening_passes`: with the cell count and scan of
    /// the cell searches), each pass with its fused kernels when it has epilogues.
    pub(super) opening: Vec<(Vec<Stage>, Option<Arc<Compiled>>)>,
    /// The end of a step (`Stage::closing_passes`: the closing integrator stage with the check
    /// and the cell count and scan), each pass with its fused kernels when it has epilogues.
    pub(super) closing: Vec<(Vec<Stage>, Option<Arc<Compiled>>)>,
    /// The cell counts on the device are those of the current positions (a `cell_count` stage
    /// was recorded after the particles last moved), so the next search skips its count.
    pub(super) counts_fresh: std::cell::Cell<bool>,
    /// The cell starts on the device are those of these counts (a `cell_scan` stage was
    /// recorded with them), so the next search skips its scan too.
    pub(super) starts_fresh: std::cell::Cell<bool>,
    /// A search has built the cell lists of the particles as now numbered (kept, with their
    /// starts, as the previous lists by the next count and scan), so a search after a fresh
    /// count merges them instead of scattering and sorting.
    pub(super) lists_kept: std::cell::Cell<bool>,
    /// Record the fused passes (false: every stage its own pass, the debug mode).
    pub(super) fused: bool,
    /// Renumber the particles in cell order every this many steps (0: never).
    pub(super) reorder_every: u64,
    /// Evaluations recorded since the last renumbering was recorded (the host's cadence: the
    /// reorder kernels are recorded only in the evaluations they are due).
    pub(super) reorder_since: std::cell::Cell<u64>,
    pub(super) n: usize,
    pub(super) n_fluid: usize,
    pub(super) phase: Vec<u32>,
    pub(super) integrator: Integrator,
    pub(super) t: f64,
    pub(super) step: u64,
    pub(super) dt: f64,
    pub(super) have_acc: bool,
    pub(super) pending: Option<SolverError>,
    /// Read the blow-up flag back every this many steps (besides every `frame()`).
    pub check_every: u64,
    /// Stage timestamps (off unless [`Self::enable_timestamps`]; `gpu::timing`).
    pub(super) ts: Timestamps,
    /// Most workgroups per dispatch dimension: the adapter's
    /// `max_compute_workgroups_per_dimension`; lower it to exercise the x/y spreading at small N.
    pub max_groups_per_dim: u32,
    /// The staging buffer of the once-per-batch control readback.
    control: ControlReader,
    /// The context's traffic when the solver was built (`engine_counters` reports the difference).
    traffic0: EngineCounters,
    /// Steps taken since construction (restarts included).
    steps_total: u64,
    /// Most steps one `advance` submission records (0: all k; [`EngineMode`]).
    max_steps_per_submit: u64,
    /// Keep up to `BATCHES_IN_FLIGHT` batches of a long `advance` submitted, each batch's
    /// control words read one batch late ([`EngineMode`]; else each is read before the next).
    batches_in_flight: bool,
    /// This solver's hold on the context's counters (`gpu::counters`: exact only while alone).
    claim: super::counters::Claim,
}

/// How the engine drives the device: the study's before/after comparison (`study::engine_ab`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EngineMode {
    /// Renumber the particles in cell order every this many steps (0: never).
    pub reorder_every: u64,
    /// Most steps per submission, each followed by its blocking control readback (0: all the
    /// steps of an `advance(k)` in one submission).
    pub max_steps_per_submit: u64,
    /// Fused passes (each neighbour pass with its per-particle epilogues, `stage::passes`);
    /// false: every stage its own pass.
    pub fused: bool,
    /// Batches of a long `advance` kept in flight, their control words read one batch late
    /// (false: each batch's read before the next is submitted).
    pub in_flight: bool,
}

impl EngineMode {
    /// The legacy engine, without `advance(k)` and renumbering: lattice order, one step per
    /// submission with a blocking control readback after every step.
    pub const BEFORE: EngineMode =
        EngineMode { reorder_every: 0, max_steps_per_submit: 1, fused: false, in_flight: false };
    /// The current engine (the solver's default): renumbering every [`DEFAULT_REORDER_EVERY`]
    /// steps, k steps per submission and one readback per `advance(k)`, fused passes, batches
    /// in flight when the steps are split.
    pub const AFTER: EngineMode =
        EngineMode { reorder_every: DEFAULT_REORDER_EVERY, max_steps_per_submit: 0, fused: true, in_flight: true };
    /// The current engine in its debug mode: every stage of the table its own pass (no
    /// epilogues), all else as [`Self::AFTER`]; timed against it, the cost of the extra passes.
    pub const UNFUSED: EngineMode = EngineMode { fused: false, ..Self::AFTER };

    /// `before`, `after`, or the settings.
    pub fn name(&self) -> String {
        match *self {
            Self::BEFORE => "before".into(),
            Self::AFTER => "after".into(),
            Self::UNFUSED => "unfused".into(),
            m => format!(
                "reorder {} / {} steps per submit / {}{}",
                m.reorder_every,
                m.max_steps_per_submit,
                if m.fused { "fused" } else { "unfused" },
                if m.in_flight { format!(" / {BATCHES_IN_FLIGHT} batches in flight") } else { String::new() }
            ),
        }
    }
}

/// `groups` workgroups as (x, y) with x ≤ `max` (as even as possible; (0, 1) for none).
pub fn spread(groups: usize, max: u32) -> (u32, u32) {
    let max = max.max(1) as usize;
    if groups <= max {
        return (groups as u32, 1);
    }
    let y = groups.div_ceil(max);
    (groups.div_ceil(y) as u32, y as u32)
}

/// Default of [`GpuSolver::set_reorder_every`] (WarpX found re-sorting every ~4 steps about
/// optimal on GPUs; 16 is a prior, not yet measured on a real GPU).
pub const DEFAULT_REORDER_EVERY: u64 = 16;

fn v2<T: Real>(p: &[f64; 2]) -> V2<T> {
    V2::from_f64(p[0], p[1])
}

impl<T: Real> GpuSolver<T> {
    /// Uploads the scene; the variant's pipelines come from the context's cache (compiled on
    /// first use).
    pub fn new(ctx: Arc<GpuContext>, scene: &Scene, layout: &Layout, spec: VariantSpec) -> Result<Self, GpuError> {
        Self::with_subgroup_lanes(ctx, scene, layout, spec, crate::gpu::variant::SUBGROUP_LANES)
    }

    /// [`Self::new`] with the subgroup mapping's kernels composed for `lanes` lanes per particle
    /// (2, 4, 8 or the default [`crate::gpu::variant::SUBGROUP_LANES`]; the other mappings
    /// ignore it). A test knob: fewer lanes than the adapter's subgroup puts several particles
    /// in one subgroup even on a CPU device whose subgroups are small.
    pub fn with_subgroup_lanes(
        ctx: Arc<GpuContext>,
        scene: &Scene,
        layout: &Layout,
        spec: VariantSpec,
        lanes: u32,
    ) -> Result<Self, GpuError> {
        spec.implemented().map_err(GpuError::Unsupported)?;
        spec.support(&ctx).map_err(GpuError::Unsupported)?;
        if spec.precision.name() != T::NAME {
            return Err(GpuError::Unsupported(format!("{spec}: solver built for {}", T::NAME)));
        }
        let model = Model::<T>::new(scene);
        cpu_only::refuse_cpu_only(&model, scene)?;
        let n = layout.pos.len();
        let n_fluid = layout.n_fluid;
        let pos: Vec<V2<T>> = layout.pos.iter().map(v2).collect();
        let vel: Vec<V2<T>> = layout.vel.iter().map(v2).collect();
        let grid = CellBox::over(&pos, model.support());
        // The memory plan before any buffer exists: each buffer within the adapter's caps, the
        // dispatch grid within its workgroup limit (device memory is the caller's: `sphlab run`).
        // The list format is chosen here, by N, for everything below (`plan::resolve_lists`).
        let lim = DeviceLimits { memory: None, ..DeviceLimits::of(&ctx, None) };
        let spec = crate::gpu::plan::resolve_lists(&spec, n as u64, grid.cells() as u64, &lim);
        let plan = GpuPlan::new(&spec, n as u64, grid.cells() as u64);
        plan.check(&lim).map_err(GpuError::Unsupported)?;
        let codes = model.images.codes().len() as u64;
        let driver = format!("{} {}", ctx.adapter_info.name, ctx.adapter_info.driver);
        crate::gpu::plan::direct_loop_check(&spec, n as u64, codes, &driver).map_err(GpuError::Unsupported)?;
        let params = Params::new(&model, n, n_fluid, &grid);
        let b = Bufs::new(&ctx, &params, n, grid.cells())?;
        let vb = VBufs::new(&ctx, spec, &model, n, grid.cells())?;
        let evals = Self::evaluations_per_step(scene.time.integrator);
        let renumbers = spec.search != crate::neighbours::SearchKind::Direct;
        let rb = RBufs::new(&ctx, n, (DEFAULT_REORDER_EVERY * evals) as u32, renumbers)?;
        let compiled = ctx.pipelines.get(&ctx, &spec, lanes)?;
        let pipes = compiled.pipes.clone();
        let with_kernels = |list: Vec<Vec<Stage>>| -> Result<Vec<_>, GpuError> {
            let mut out = Vec::new();
            for pass in list {
                let fused = if pass.len() > 1 { Some(pipes.fused(&ctx, &pass)?) } else { None };
                out.push((pass, fused));
            }
            Ok(out)
        };
        let passes = with_kernels(model.stages.evaluation_passes())?;
        let cells = match spec.search {
            crate::neighbours::SearchKind::Direct if !spec.sorts_cells() => CellEpilogues::None,
            _ if grid.cells() <= crate::gpu::plan::FUSED_SCAN_CELLS => CellEpilogues::CountAndScan,
            _ => CellEpilogues::Count,
        };
        let opening = with_kernels(Stage::opening_passes(scene.time.integrator, cells))?;
        let closing = with_kernels(Stage::closing_passes(scene.time.integrator, cells))?;
        let bgs = b.bind_groups(&ctx, &compiled.state_layout)?;
        let vbgs = vb.bind_groups(&ctx, &compiled.variant_layout)?;
        let rbg = rb.bind_group(&ctx, &compiled.reorder_layout)?;
        b.pos().upload(&ctx, &pos)?;
        b.vel().upload(&ctx, &vel)?;
        b.phase.upload(&ctx, &layout.phase)?;
        b.upload_walls(&ctx, &wall_cells(&grid, &pos, n_fluid), grid.cells(), n_fluid);
        let ctx_groups = ctx.limits.max_compute_workgroups_per_dimension;
        let control = ControlReader::new::<T>(&ctx);
        let traffic0 = ctx.traffic.totals();
        let claim = super::counters::Claim::new(ctx.clone());
        let mut s = Self {
            ctx,
            spec,
            model,
            grid,
            b,
            vb,
            rb,
            pipes,
            bgs,
            vbgs,
            rbg,
            passes,
            opening,
            closing,
            counts_fresh: std::cell::Cell::new(false),
            starts_fresh: std::cell::Cell::new(false),
            lists_kept: std::cell::Cell::new(false),
            fused: true,
            reorder_every: DEFAULT_REORDER_EVERY,
            reorder_since: std::cell::Cell::new(u64::MAX),
            n,
            n_fluid,
            phase: layout.phase.clone(),
            integrator: scene.time.integrator,
            t: 0.0,
            step: 0,
            dt: scene.time.dt,
            have_acc: false,
            pending: None,
            check_every: 100,
            ts: Timestamps::default(),
            max_groups_per_dim: ctx_groups,
            control,
            traffic0,
            steps_total: 0,
            max_steps_per_submit: 0,
            batches_in_flight: true,
            claim,
        };
        s.upload_static_colours()?;
        s.reset_ctl()?;
        s.set_reorder_every(DEFAULT_REORDER_EVERY)?;
        Ok(s)
    }

    /// The variant as it runs (its list format resolved by N: `plan::resolve_lists`).
    pub fn spec(&self) -> VariantSpec {
        self.spec
    }

    fn evaluations_per_step(integrator: Integrator) -> u64 {
        if integrator == Integrator::Midpoint {
            2
        } else {
            1
        }
    }

    /// Renumbers the particles in cell order on the device from the next evaluation on (0:
    /// never; the `direct` search never does). A `cells` search renumbers at every evaluation
    /// whatever k > 0 says, so the particles stay in physical cell order (slot s of the sort is
    /// particle s, `vparam::PHYSICAL`): the search sorts at every evaluation anyway, and the
    /// renumbering costs no kernel. Tracking variants renumber every `k` steps and rebuild
    /// their candidate lists then (the lists hold indices).
    pub fn set_reorder_every(&mut self, k: u64) -> Result<(), GpuError> {
        let every = self.reorder_evaluations(k);
        self.rb.set_every(&self.ctx, every.min(u32::MAX as u64) as u32)?;
        self.reorder_every = k;
        self.vb.set_physical(&self.ctx, self.physical_order());
        self.reorder_since.set(u64::MAX);
        Ok(())
    }

    /// Evaluations between renumberings for a period of `k` steps (0: never).
    fn reorder_evaluations(&self, k: u64) -> u64 {
        match self.spec.search {
            _ if k == 0 => 0,
            crate::neighbours::SearchKind::Cells => 1,
            _ => k.saturating_mul(Self::evaluations_per_step(self.integrator)),
        }
    }

    /// True when the evaluation being recorded renumbers (the host's cadence, every
    /// `reorder_every` steps' evaluations from the first recorded after
    /// [`Self::set_reorder_every`]); advances the count of recorded evaluations.
    pub(super) fn reorder_due(&self) -> bool {
        if self.reorder_every == 0 || self.spec.search == crate::neighbours::SearchKind::Direct {
            return false;
        }
        let every = self.reorder_evaluations(self.reorder_every);
        let due = self.reorder_since.get() >= every;
        self.reorder_since.set(if due { 1 } else { self.reorder_since.get() + 1 });
        due
    }

    /// Drives the device as `mode` says from the next step on (renumbering period, steps per
    /// submission).
    pub fn set_engine_mode(&mut self, mode: EngineMode) -> Result<(), GpuError> {
        self.set_reorder_every(mode.reorder_every)?;
        self.max_steps_per_submit = mode.max_steps_per_submit;
        self.fused = mode.fused;
        self.batches_in_flight = mode.in_flight;
        Ok(())
    }

    /// Records each neighbour pass with its per-particle epilogues in one kernel (`true`, the
    /// default; unfused while stage timing is on) or every stage as its own pass (the debug
    /// mode; `stage::passes`).
    pub fn set_fused(&mut self, on: bool) {
        self.fused = on;
    }

    /// True while the particles are kept in physical cell order (a `cells` search renumbering
    /// at every evaluation: slot s of the sort is particle s).
    pub fn physical_order(&self) -> bool {
        self.reorder_every != 0 && self.spec.search == crate::neighbours::SearchKind::Cells
    }

    /// The renumbering period in steps (0: off).
    pub fn reorder_every(&self) -> u64 {
        self.reorder_every
    }

    /// Renumberings so far.
    pub fn reorder_count(&self) -> Result<u64, GpuError> {
        self.rb.count(&self.ctx)
    }

    /// The original index of each device index (the identity until the first renumbering).
    pub fn device_order(&self) -> Result<Vec<u32>, GpuError> {
        self.rb.orig_of(&self.ctx)
    }

    /// Static colours and masses (`cpu::stages::assign_colours`).
    fn upload_static_colours(&self) -> Result<(), GpuError> {
        let m = &self.model;
        let wall_colour = if m.contact_mode == ContactMode::A { COLOUR_WALL } else { NO_COLOUR };
        let colour: Vec<i32> =
            (0..self.n).map(|i| if i < self.n_fluid { self.phase[i] as i32 } else { wall_colour }).collect();
        let mass: Vec<T> = (0..self.n)
            .map(|i| m.phases[if i < self.n_fluid { self.phase[i] as usize } else { m.wall_phase }].mass)
            .collect();
        self.b.colour.upload(&self.ctx, &colour)?;
        self.b.mass().upload(&self.ctx, &mass)
    }

    /// Clears the control words and sets the clock to step 0, t = 0 (dt: the fixed one).
    pub(super) fn reset_ctl(&self) -> Result<(), GpuError> {
        let mut c = vec![0u32; ctl::LEN];
        c[ctl::BAD_STEP] = u32::MAX;
        c[ctl::BAD] = u32::MAX;
        c[ctl::OVER_STEP] = u32::MAX;
        c[ctl::SCAN_MISS] = u32::MAX;
        write_clock(&self.ctx, &self.vb, self.model.dt_fixed.max(0.0), 0.0);
        self.b.ctl.upload(&self.ctx, &c)
    }

    /// Bytes of every device buffer this solver allocated (state, variant buffers, the parameter
    /// uniform; not the timestamp queries), the figure the memory plan predicts.
    pub fn device_bytes(&self) -> u64 {
        let storage = self
            .b
            .storage()
            .into_iter()
            .chain(self.vb.all_storage())
            .chain(self.rb.storage())
            .map(|b| b.size())
            .sum::<u64>();
        storage + self.b.params.buffer.size()
    }

    /// Cells of the search grid.
    pub fn cells(&self) -> usize {
        self.grid.cells()
    }

    /// The cell of `p` on the search grid, as the device computes it.
    pub fn cell_of(&self, p: V2<T>) -> u32 {
        super::solver_buffers::cell_of_pos(&self.grid, p)
    }

    /// The variant constants (fixed-point quanta, tracking radii; `gpu::variant_buffers`).
    pub fn variant_constants(&self) -> Result<Vec<T>, GpuError> {
        self.vb.vparams.read_back(&self.ctx)
    }

    /// Tracking-list builds so far (0 for the other searches).
    pub fn tracking_rebuilds(&self) -> Result<u64, GpuError> {
        self.vb.rebuilds(&self.ctx)
    }
}

/// A boxed GPU backend for `spec` in its precision.
pub fn new_backend(
    ctx: Arc<GpuContext>,
    scene: &Scene,
    layout: &Layout,
    spec: VariantSpec,
) -> Result<Box<dyn Backend>, GpuError> {
    Ok(match spec.precision {
        crate::real::Precision::F32 => Box::new(GpuSolver::<f32>::new(ctx, scene, layout, spec)?),
        crate::real::Precision::F64 => Box::new(GpuSolver::<f64>::new(ctx, scene, layout, spec)?),
    })
}
