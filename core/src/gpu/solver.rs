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

use super::clock::{write_clock, Control, ControlReader};
use super::params::Params;
use super::reorder::{self, RBufs};
use super::solver_buffers::{ctl, Bufs};
use super::stages::{Domain, Pipelines};
use super::timing::Timestamps;
use super::variant::VariantSpec;
use super::variant_buffers::{self as vbufs, VBufs};
use super::{GpuContext, GpuError};
use crate::backend::{Backend, DeviceTimes, EngineCounters, Frame, SolverError};
use crate::fields::Fields;
use crate::gpu::plan::{DeviceLimits, GpuPlan};
use crate::model::{Model, COLOUR_WALL, MAX_CONTACTS, NO_COLOUR};
use crate::neighbours::cells::CellBox;
use crate::real::{Real, V2};
use crate::scene::build::Layout;
use crate::scene::{ContactMode, Integrator, Scene};
use crate::stage::{Clear, Stage};
use std::sync::Arc;

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
    pub(super) bg: wgpu::BindGroup,
    pub(super) vbg: wgpu::BindGroup,
    pub(super) rbg: wgpu::BindGroup,
    /// Renumber the particles in cell order every this many steps (0: never).
    pub(super) reorder_every: u64,
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
}

impl EngineMode {
    /// The legacy engine, without `advance(k)` and renumbering: lattice order, one step per
    /// submission with a blocking control readback after every step.
    pub const BEFORE: EngineMode = EngineMode { reorder_every: 0, max_steps_per_submit: 1 };
    /// The current engine (the solver's default): renumbering every [`DEFAULT_REORDER_EVERY`]
    /// steps, k steps per submission and one readback per `advance(k)`.
    pub const AFTER: EngineMode = EngineMode { reorder_every: DEFAULT_REORDER_EVERY, max_steps_per_submit: 0 };

    /// `before`, `after`, or the settings.
    pub fn name(&self) -> String {
        match *self {
            Self::BEFORE => "before".into(),
            Self::AFTER => "after".into(),
            m => format!("reorder {} / {} steps per submit", m.reorder_every, m.max_steps_per_submit),
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
        spec.implemented().map_err(GpuError::Unsupported)?;
        spec.support(&ctx).map_err(GpuError::Unsupported)?;
        if spec.precision.name() != T::NAME {
            return Err(GpuError::Unsupported(format!("{spec}: solver built for {}", T::NAME)));
        }
        let model = Model::<T>::new(scene);
        if model.single_field_colour {
            return Err(GpuError::Unsupported(
                "surface_tension.colour_gradient = \"single-field\" is CPU only (the WGSL stages sum the \
                 thesis's T71 form); use --backend cpu or colour_gradient = \"thesis\""
                    .into(),
            ));
        }
        if model.transport_p_b.is_some() {
            return Err(GpuError::Unsupported(
                "time.background = \"transport\" (transport-velocity formulation) is CPU only (the WGSL \
                 stages add p_b to the EOS pressure); use --backend cpu or background = \"momentum\""
                    .into(),
            ));
        }
        if scene.time.integrator == Integrator::VerletPec {
            return Err(GpuError::Unsupported(
                "time.integrator = \"verlet-pec\" is CPU only (the WGSL Verlet evaluates at the predicted \
                 velocity); use --backend cpu or integrator = \"verlet\""
                    .into(),
            ));
        }
        let n = layout.pos.len();
        let n_fluid = layout.n_fluid;
        let pos: Vec<V2<T>> = layout.pos.iter().map(v2).collect();
        let vel: Vec<V2<T>> = layout.vel.iter().map(v2).collect();
        let grid = CellBox::over(&pos, model.support());
        // The memory plan before any buffer exists: each buffer within the adapter's caps, the
        // dispatch grid within its workgroup limit (device memory is the caller's: `sphlab run`).
        let plan = GpuPlan::new(&spec, n as u64, grid.cells() as u64);
        plan.check(&DeviceLimits { memory: None, ..DeviceLimits::of(&ctx, None) }).map_err(GpuError::Unsupported)?;
        let codes = model.images.codes().len() as u64;
        let driver = format!("{} {}", ctx.adapter_info.name, ctx.adapter_info.driver);
        crate::gpu::plan::direct_loop_check(&spec, n as u64, codes, &driver).map_err(GpuError::Unsupported)?;
        let params = Params::new(&model, n, n_fluid, &grid);
        let b = Bufs::new(&ctx, &params, n, grid.cells())?;
        let vb = VBufs::new(&ctx, spec, &model, n)?;
        let evals = Self::evaluations_per_step(scene.time.integrator);
        let renumbers = spec.search != crate::neighbours::SearchKind::Direct;
        let rb = RBufs::new(&ctx, n, grid.cells(), (DEFAULT_REORDER_EVERY * evals) as u32, renumbers)?;
        let compiled = ctx.pipelines.get(&ctx, &spec)?;
        let pipes = compiled.pipes.clone();
        let bg = b.bind_group(&ctx, &compiled.state_layout)?;
        let vbg = vb.bind_group(&ctx, &compiled.variant_layout)?;
        let rbg = rb.bind_group(&ctx, &compiled.reorder_layout)?;
        b.pos.upload(&ctx, &pos)?;
        b.vel.upload(&ctx, &vel)?;
        b.phase.upload(&ctx, &layout.phase)?;
        let ctx_groups = ctx.limits.max_compute_workgroups_per_dimension;
        let control = ControlReader::new::<T>(&ctx);
        let traffic0 = ctx.traffic.totals();
        let claim = super::counters::Claim::new(ctx.clone());
        let s = Self {
            ctx,
            spec,
            model,
            grid,
            b,
            vb,
            rb,
            pipes,
            bg,
            vbg,
            rbg,
            reorder_every: DEFAULT_REORDER_EVERY,
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
            claim,
        };
        s.upload_static_colours()?;
        s.reset_ctl()?;
        Ok(s)
    }

    /// The variant.
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

    /// Renumbers the fluid particles in cell order on the device every `k` steps from the next
    /// evaluation on (0: never; the `direct` search never does). Tracking variants renumber
    /// exactly when their candidate lists are rebuilt (the lists hold indices), whenever `k > 0`.
    pub fn set_reorder_every(&mut self, k: u64) -> Result<(), GpuError> {
        let every = k.saturating_mul(Self::evaluations_per_step(self.integrator)).min(u32::MAX as u64);
        self.rb.set_every(&self.ctx, every as u32)?;
        self.reorder_every = k;
        Ok(())
    }

    /// Drives the device as `mode` says from the next step on (renumbering period, steps per
    /// submission).
    pub fn set_engine_mode(&mut self, mode: EngineMode) -> Result<(), GpuError> {
        self.set_reorder_every(mode.reorder_every)?;
        self.max_steps_per_submit = mode.max_steps_per_submit;
        Ok(())
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
        self.b.mass.upload(&self.ctx, &mass)
    }

    /// Clears the control words and sets the clock to step 0, t = 0 (dt: the fixed one).
    pub(super) fn reset_ctl(&self) -> Result<(), GpuError> {
        let mut c = vec![0u32; ctl::LEN];
        c[ctl::BAD_STEP] = u32::MAX;
        c[ctl::BAD] = u32::MAX;
        c[ctl::OVER_STEP] = u32::MAX;
        write_clock(&self.ctx, &self.vb, self.model.dt_fixed.max(0.0), 0.0);
        self.b.ctl.upload(&self.ctx, &c)
    }

    /// The workgroup grid of a kernel over `d`: the groups a 1-D dispatch would need, spread
    /// over x and y (x and z for the block layout, whose y holds the 4 list blocks) when x alone
    /// would pass [`Self::max_groups_per_dim`]; the kernels rebuild the linear index with
    /// `linear_id` / `linear_group_xz` (kernels-variants/common/dispatch.wgsl).
    pub fn groups(&self, d: Domain) -> [u32; 3] {
        let threads = match d {
            Domain::All => self.n,
            Domain::Fluid => self.n_fluid,
            Domain::Wall => self.n - self.n_fluid,
            Domain::One | Domain::Group => return [1, 1, 1],
            Domain::Cells => self.grid.cells(),
            Domain::ScanBlocks => {
                let (gx, gy) = spread(crate::gpu::plan::scan_blocks(self.grid.cells()), self.max_groups_per_dim);
                return [gx, gy, 1];
            }
            Domain::Subgroups => {
                let per_group = 64 / self.ctx.adapter_info.subgroup_max_size.clamp(1, 64) as usize;
                let (gx, gy) = spread(self.n.div_ceil(per_group), self.max_groups_per_dim);
                return [gx, gy, 1];
            }
            Domain::Block => {
                let (gx, gz) = spread(self.n.div_ceil(32), self.max_groups_per_dim);
                return [gx, (vbufs::NBR_SLOTS / 16) as u32, gz];
            }
        };
        let (gx, gy) = spread(threads.div_ceil(64), self.max_groups_per_dim);
        [gx, gy, 1]
    }

    /// Bytes of every device buffer this solver allocated (state, variant buffers, the parameter
    /// uniform; not the timestamp queries), the figure the memory plan predicts.
    pub fn device_bytes(&self) -> u64 {
        let storage = self
            .b
            .storage()
            .into_iter()
            .chain(self.vb.storage())
            .chain(self.rb.storage())
            .map(|b| b.size())
            .sum::<u64>();
        storage + self.b.params.buffer.size()
    }

    /// Cells of the search grid.
    pub fn cells(&self) -> usize {
        self.grid.cells()
    }

    /// The variant constants (fixed-point quanta, tracking radii; `gpu::variant_buffers`).
    pub fn variant_constants(&self) -> Result<Vec<T>, GpuError> {
        self.vb.vparams.read_back(&self.ctx)
    }

    /// Tracking-list builds so far (0 for the other searches).
    pub fn tracking_rebuilds(&self) -> Result<u64, GpuError> {
        self.vb.rebuilds(&self.ctx)
    }

    /// Records the kernels of one stage into `enc`: the table's clears (when the stage has
    /// kernels), the block accumulator clear (block kernels), then one compute pass.
    pub(super) fn record(&self, enc: &mut wgpu::CommandEncoder, stage: Stage) {
        let Some(kernels) = self.pipes.stages.get(&stage) else { return };
        if kernels.is_empty() {
            return;
        }
        for clear in stage.def().clears {
            let (buffer, offset, size) = match clear {
                Clear::CellCounts => (&self.b.cell_count.buffer, 0, None),
                Clear::ContactsFound => (&self.b.ctl.buffer, 4 * ctl::CONTACTS_FOUND as u64, Some(4)),
                Clear::Maxima => (&self.b.ctl.buffer, 4 * ctl::VMAX as u64, Some(8)),
            };
            enc.clear_buffer(buffer, offset, size);
        }
        if kernels.iter().any(|(kd, _)| kd.domain == Domain::Block) {
            enc.clear_buffer(&self.vb.accum.buffer, 0, None);
        }
        let dispatches = kernels.iter().any(|(kd, _)| self.groups(kd.domain)[0] > 0);
        let timestamp_writes = if dispatches { self.ts.writes(stage.name()) } else { None };
        let desc = wgpu::ComputePassDescriptor { label: Some(stage.name()), timestamp_writes };
        let mut pass = enc.begin_compute_pass(&desc);
        pass.set_bind_group(0, &self.bg, &[]);
        pass.set_bind_group(1, &self.vbg, &[]);
        if kernels.iter().any(|(kd, _)| kd.file == reorder::FILE) {
            pass.set_bind_group(2, &self.rbg, &[]);
        }
        for (kd, p) in kernels {
            if kd.file == reorder::FILE && self.reorder_every == 0 {
                continue;
            }
            let [gx, gy, gz] = self.groups(kd.domain);
            if gx > 0 {
                pass.set_pipeline(p);
                pass.dispatch_workgroups(gx, gy, gz);
                self.ctx.traffic.dispatch(1);
            }
        }
    }

    /// Records one force evaluation: every active stage in the CPU order, then ṽ.
    fn record_evaluate(&self, enc: &mut wgpu::CommandEncoder) {
        for stage in self.model.stages.evaluation() {
            self.record(enc, stage);
        }
        if !self.model.stages.xsph {
            let bytes = (self.n_fluid * size_of::<V2<T>>()) as u64;
            if bytes > 0 {
                enc.copy_buffer_to_buffer(&self.b.vel.buffer, 0, &self.b.vt.buffer, 0, bytes);
            }
        }
    }

    pub(super) fn submit(&self, f: impl FnOnce(&mut wgpu::CommandEncoder)) -> Result<(), GpuError> {
        self.ts.before_submit(&self.ctx)?;
        self.ctx.scoped(|d| {
            let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sphlab.step") });
            f(&mut enc);
            self.ctx.queue.submit([enc.finish()]);
            self.ctx.traffic.submit();
        })
    }

    /// One force evaluation at the current state (no integration), waited for; a neighbour
    /// overflow is an error (`GpuError::Solver(NeighbourOverflow)`).
    pub fn evaluate_once(&mut self) -> Result<(), GpuError> {
        self.submit(|enc| self.record_evaluate(enc))?;
        self.ctx.wait_idle()?;
        self.vb.overflow(&self.ctx, self.step).map_err(|e| self.to_original(e))?;
        Ok(())
    }

    /// `e` with the overflowing particle's device index (`VBufs::overflow`) mapped through the
    /// renumbering to its original id.
    pub(super) fn to_original(&self, mut e: SolverError) -> SolverError {
        if let SolverError::NeighbourOverflow { particle: Some(p), .. } = &mut e {
            if let Some(o) = self.device_order().ok().and_then(|order| order.get(*p).copied()) {
                *p = o as usize;
            }
        }
        e
    }

    /// Records one whole step: (first evaluation,) with an adaptive dt `reduce_max` and
    /// `dt_compute`, the integrator's opening stage, the evaluation, its closing stage, then
    /// `check` (`clock_tick` first). Reads nothing from the host: dt and the step number come from
    /// the device clock.
    fn record_step(&self, enc: &mut wgpu::CommandEncoder, first_eval: bool) {
        if first_eval {
            self.record_evaluate(enc);
        }
        if self.model.dt_fixed <= 0.0 {
            self.record(enc, Stage::ReduceMax);
        }
        let (pre, post) = Stage::step_pair(self.integrator);
        self.record(enc, pre);
        self.record_evaluate(enc);
        self.record(enc, post);
        self.record(enc, Stage::Check);
    }

    /// Takes the control words read back after a batch: the host clock follows the device's
    /// (adaptive dt, or a halted device), and the first failure becomes the error.
    fn take_control(&mut self, c: Control) -> Result<(), SolverError> {
        let (bad, over) = (c.ctl[ctl::BAD_STEP], c.ctl[ctl::OVER_STEP]);
        let failed = bad != u32::MAX || over != u32::MAX;
        if self.model.dt_fixed <= 0.0 || failed {
            self.step = c.step();
            self.t = c.t;
            if c.dt > 0.0 {
                self.dt = c.dt;
            }
        }
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        if over != u32::MAX && over <= bad {
            self.vb.overflow_in(&self.ctx, c.vctl, over as u64).map_err(|e| self.to_original(e))?;
        }
        if c.ctl[ctl::CONTACTS_MAX] as usize > MAX_CONTACTS {
            let count = c.ctl[ctl::CONTACTS_MAX] as usize;
            return Err(SolverError::ContactOverflow { step: self.step, count, cap: MAX_CONTACTS });
        }
        if bad != u32::MAX {
            let (device, kind) = ((c.ctl[ctl::BAD] / 2) as usize, c.ctl[ctl::BAD] % 2);
            let particle = self.device_order().map_err(gpu)?.get(device).map_or(device, |&o| o as usize);
            let (pos, vel) = self.read_state().map_err(gpu)?;
            let (p, v) = (pos[particle], vel[particle]);
            let what = if kind == 0 {
                format!(
                    "has a non-finite state: x = ({:.4e}, {:.4e}), v = ({:.4e}, {:.4e})",
                    p.x.f64(),
                    p.y.f64(),
                    v.x.f64(),
                    v.y.f64()
                )
            } else {
                format!("left the domain: x = ({:.4e}, {:.4e})", p.x.f64(), p.y.f64())
            };
            return Err(SolverError::BlowUp { step: bad as u64, t: self.t, particle, what });
        }
        Ok(())
    }

    /// Reads the control words and the clock back (one submit, one readback) and takes them.
    fn check_flags(&mut self) -> Result<(), SolverError> {
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        self.submit(|enc| self.control.record(enc, &self.b, &self.vb)).map_err(gpu)?;
        let c = self.control.read::<T>(&self.ctx).map_err(gpu)?;
        self.take_control(c)
    }

    /// `k` steps in ONE submission; the control words and the clock are copied at its end and,
    /// when `read`, mapped (the one readback) and checked.
    fn run_steps(&mut self, k: u64, read: bool) -> Result<(), SolverError> {
        if let Some(e) = self.pending.take() {
            return Err(e);
        }
        if k == 0 {
            return Ok(());
        }
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        let midpoint = self.integrator == Integrator::Midpoint;
        let have_acc = self.have_acc;
        self.submit(|enc| {
            for s in 0..k {
                self.record_step(enc, midpoint || (s == 0 && !have_acc));
            }
            if read {
                self.control.record(enc, &self.b, &self.vb);
            }
        })
        .map_err(gpu)?;
        self.have_acc = true;
        self.steps_total += k;
        if self.model.dt_fixed > 0.0 {
            for _ in 0..k {
                self.t += self.model.dt_fixed;
            }
            self.dt = self.model.dt_fixed;
        }
        self.step += k;
        if read {
            let c = self.control.read::<T>(&self.ctx).map_err(gpu)?;
            self.take_control(c)?;
        } else {
            let _ = self.ctx.device.poll(wgpu::PollType::Poll);
        }
        Ok(())
    }

    /// What was done to the solver's context since the solver was built (`gpu::counters`): the
    /// solver's own work while [`Self::engine_counters_exclusive`].
    pub fn engine_counters(&self) -> EngineCounters {
        EngineCounters { steps: self.steps_total, ..self.ctx.traffic.totals().since(&self.traffic0) }
    }

    /// True while this has been the only solver alive on its context since it was built, so
    /// that [`Self::engine_counters`] counts its work alone.
    pub fn engine_counters_exclusive(&self) -> bool {
        self.claim.exclusive()
    }
}

impl<T: Real> Backend for GpuSolver<T> {
    fn name(&self) -> String {
        self.spec.to_string()
    }
    fn precision(&self) -> &'static str {
        T::NAME
    }
    fn step(&mut self) -> Result<(), SolverError> {
        let adaptive = self.model.dt_fixed <= 0.0;
        let read = adaptive || (self.check_every > 0 && (self.step + 1).is_multiple_of(self.check_every));
        self.run_steps(1, read)
    }
    fn advance(&mut self, k: u64) -> Result<(), SolverError> {
        if k == 0 {
            return self.run_steps(0, true);
        }
        let most = if self.max_steps_per_submit == 0 { k } else { self.max_steps_per_submit };
        let mut left = k;
        while left > 0 {
            let n = left.min(most);
            self.run_steps(n, true)?;
            left -= n;
        }
        Ok(())
    }
    fn engine_counters(&self) -> Option<EngineCounters> {
        // Another solver on the context since this one was built: its work would be counted too.
        self.engine_counters_exclusive().then(|| GpuSolver::engine_counters(self))
    }
    fn time(&self) -> f64 {
        self.t
    }
    fn steps(&self) -> u64 {
        self.step
    }
    fn frame(&mut self) -> Frame {
        if self.pending.is_none() {
            self.pending = self.check_flags().err();
        }
        let (pos, vel) = self.read_state().unwrap_or_default();
        let f = self.read_fields().unwrap_or_else(|_| Fields::new(0));
        Frame::from_fields(self.step, self.t, self.dt, self.n_fluid, &pos, &vel, &self.phase, &f)
    }
    fn restart_with_velocities(&mut self, vel: &[[f64; 2]]) {
        if let Ok((_, mut v)) = self.read_state() {
            for (i, x) in vel.iter().enumerate().take(self.n_fluid) {
                v[i] = v2(x);
            }
            if let Ok(orig_of) = self.device_order() {
                let _ = self.b.vel.upload(&self.ctx, &reorder::to_device(&v, 1, &orig_of));
            }
        }
        self.t = 0.0;
        self.step = 0;
        self.have_acc = false;
        let _ = self.reset_ctl();
    }
    fn sync(&mut self) {
        let _ = self.ctx.wait_idle();
    }
    fn take_error(&mut self) -> Option<SolverError> {
        if self.pending.is_none() {
            self.pending = self.check_flags().err();
        }
        self.pending.take()
    }
    fn enable_device_time(&mut self, on: bool) -> bool {
        self.enable_timestamps(on)
    }
    fn device_time(&mut self) -> Option<DeviceTimes> {
        self.ts.device_times(&self.ctx, self.step)
    }
}

impl<T: Real> GpuSolver<T> {
    /// Switches stage timing on or off; returns whether it is on (false when the device lacks
    /// `TIMESTAMP_QUERY`: then nothing is timed and [`Self::take_stage_times`] returns `None`).
    /// Switching on (again) starts from empty sums.
    pub fn enable_timestamps(&mut self, on: bool) -> bool {
        self.ts = if on { Timestamps::new(&self.ctx, self.step) } else { Timestamps::default() };
        self.ts.is_on()
    }

    /// True while stage timing is on.
    pub fn timestamps_enabled(&self) -> bool {
        self.ts.is_on()
    }

    /// Device nanoseconds per stage name (`neighbour_search`, …, `midpoint_predict`, `check`),
    /// summed over every pass recorded since the last call, in order of first appearance;
    /// `None` when timing is off or unavailable (never estimated).
    pub fn take_stage_times(&mut self) -> Result<Option<Vec<(String, f64)>>, GpuError> {
        self.ts.stage_times(&self.ctx, self.step)
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
