//! The buffers of the strategy variants, bind group 1 (twin of
//! `kernels-variants/common/variant_bindings.wgsl` and `common/accum.wgsl`: binding k here is
//! binding k there): control words, per-variant constants (fixed-point quanta, tracking radii),
//! list and candidate counts, the explicit neighbour lists (64 slots, or bitmasks over the cell
//! walk: `gpu::mask_lists`, which sizes every list buffer), cached kernel values, the tracking
//! candidates with their reference positions, and the block accumulator. A variant
//! allocates only what it uses (one-element stand-ins otherwise), and [`VBufs::overflow`]
//! turns the overflow counters into [`SolverError::NeighbourOverflow`].
//!
//! Fixed-point scales: each accumulated field group f (density, colour gradient, acceleration)
//! gets a quantum q_f = 2^(⌊log₂ S_f⌋ − 48), S_f an upper estimate of the sum of |terms| from
//! the model: S_density = 1/Δx² (σ of a lattice), S_grad = 64·F'max·Δx⁴ (64 slots of ∇W/σ²),
//! S_acc = S_grad·P (P = EOS scale B + σ_s/h + η·c/h). Terms are rounded to multiples of q_f
//! and summed exactly in 64 bits: each sum carries at most 64·q_f/2 = 2⁻⁴³·S_f of
//! quantisation error (1.1e-13 of the scale, so still ~1e-9 of a field 10⁴× smaller than its
//! estimate, as the nearly cancelling pressure sums of a drop at rest are), and is exact up to
//! 2⁶² quanta = 2¹⁴·S_f; a term beyond that is counted and the evaluation reported invalid.

use super::list_chunks::{chunk_len, chunks};
use super::mask_lists::{cand_masks, list_words, nbr_bits, uses_masks, ListWords, CAND_WORDS};
use super::pooled_lists::{POOL_BLOCK, POOL_MEAN, POOL_REGION};
use super::variant::VariantSpec;
use super::{GpuContext, GpuError, GpuVec, Uniform};
use crate::backend::SolverError;
use crate::model::Model;
use crate::neighbours::SearchKind;
use crate::neighbours::TrackingCfg;
use crate::real::{Real, V2};

/// Slots of the explicit lists (thesis §6.4.1).
pub const NBR_SLOTS: usize = 64;
/// Slots of the tracking candidate lists.
pub const CAND_SLOTS: usize = 96;
/// Storage buffers of group 1.
pub const N_VSTORAGE: u32 = 9;
/// The uniform of group 1: the list chunk's range (`gpu::list_chunks`).
pub const CHUNK_BINDING: u32 = 9;

/// Words of `vctl` (`V_*` in variant_bindings.wgsl).
pub mod vctl {
    /// The most particles with more than 64 neighbours in one evaluation since the last read
    /// (particles, not particle-evaluations: `nbr_fold` keeps the maximum of [`NBR_EVAL`]).
    pub const NBR_OVER: usize = 0;
    /// Largest neighbour count.
    pub const NBR_MAX: usize = 1;
    /// The most particles with more than 96 candidates in one evaluation since the last read
    /// (`track_clear` keeps the maximum of [`CAND_STALE`]).
    pub const CAND_OVER: usize = 2;
    /// Largest candidate count.
    pub const CAND_MAX: usize = 3;
    /// Rebuild flag.
    pub const REBUILD: usize = 4;
    /// Evaluations since the last build.
    pub const SINCE: usize = 5;
    /// f32 bits of the max displacement².
    pub const DISP2: usize = 6;
    /// Builds so far.
    pub const REBUILDS: usize = 7;
    /// Rebuild period k.
    pub const EVERY: usize = 8;
    /// Fixed-point terms beyond the representable range.
    pub const FIXED_OVER: usize = 9;
    /// Particles whose current (truncated) candidate list overflowed; cleared by a rebuild.
    pub const CAND_STALE: usize = 10;
    /// Lowest device index of a particle whose list overflowed while the device ran (`u32::MAX`:
    /// none; cleared when read).
    pub const OVER_FIRST: usize = 11;
    /// Particles over 64 neighbours in the current evaluation (`nbr_build`; zeroed by `nbr_fold`).
    pub const NBR_EVAL: usize = 12;
    /// The most mask bits a particle's list needed (bitmask lists, `gpu::mask_lists`): past
    /// the mask the list overflowed.
    pub const NBR_NEED: usize = 13;
    /// The most entries a block of the pooled lists needed (`gpu::pooled_lists`), noted by
    /// its overflowing particles: past the block's room the list overflowed.
    pub const POOL_NEED: usize = 14;
    /// Words.
    pub const LEN: usize = 16;
}

/// Entries of `vparams` (`VP_*` in variant_bindings.wgsl): the variant constants, then the
/// device clock (`gpu::clock`) and the constants of the adaptive dt.
pub mod vparam {
    /// 1/quantum of field group f at `INV_Q + f`.
    pub const INV_Q: usize = 0;
    /// Quantum of field group f at `Q + f`.
    pub const Q: usize = 4;
    /// (support + skin)².
    pub const CAND_R2: usize = 8;
    /// (skin / 2)².
    pub const HALF_SKIN2: usize = 9;
    /// Device clock: dt of the step being taken.
    pub const DT: usize = 12;
    /// Device clock: time.
    pub const T: usize = 13;
    /// Device clock: rounding error of `T` (t = T + T_LO).
    pub const T_LO: usize = 14;
    /// Adaptive dt: `time.cfl`, then c_max, ν_max, ρ̄, σ_max (the arguments of `DtLimits::compute`).
    pub const CFL: usize = 16;
    /// 1 with an adaptive dt (computed on the device by the opening integrator stage), 0 fixed.
    pub const ADAPTIVE: usize = 21;
    /// 1 while the particles are in physical cell order (every search renumbers them: slot s
    /// holds particle s, `GpuSolver::set_reorder_every` on a `cells` search), 0 otherwise.
    pub const PHYSICAL: usize = 22;
    /// Entries.
    pub const LEN: usize = 24;
}

/// The group-1 buffers.
pub struct VBufs<T: Real> {
    pub vctl: GpuVec<u32>,
    pub vparams: GpuVec<T>,
    pub counts: GpuVec<u32>,
    /// Binding 3: one buffer per list chunk with slot lists (`gpu::list_chunks`), else one.
    pub nbr: Vec<GpuVec<u32>>,
    /// Binding 4: cached (W, F′) per slot, one buffer per list chunk, or the high words of a
    /// fixed-point accumulation (one buffer).
    pub cache_wf: Vec<GpuVec<u32>>,
    /// Binding 5: the tracking candidate mask's upper words (a stand-in without masks).
    pub cand_hi: GpuVec<u32>,
    pub cand: GpuVec<u32>,
    pub ref_pos: GpuVec<V2<T>>,
    /// Binding 8: the block accumulator, one buffer per list chunk (`gpu::list_chunks`).
    pub accum: Vec<GpuVec<u32>>,
    /// The list chunks `(base, len)` and each one's range (binding 9).
    pub chunks: Vec<(usize, usize)>,
    ranges: Vec<Uniform<[u32; 4]>>,
    spec: VariantSpec,
    every: u32,
}

/// The name of binding 4 (what it holds for `spec`, `gpu::mask_lists::ListWords`).
pub fn binding4_name(spec: &VariantSpec) -> &'static str {
    if spec.kernel_values == super::variant::KernelValues::Cached {
        "cache_wf"
    } else {
        "accum_hi"
    }
}

/// Power of two 2^(⌊log₂ s⌋ − 48) (the fixed-point quantum of a field of magnitude s).
fn quantum(s: f64) -> f64 {
    2f64.powi(s.max(1e-300).log2().floor() as i32 - 48)
}

impl<T: Real> VBufs<T> {
    /// Allocates what `spec` uses for `n` particles on `cells` grid cells and writes the constants.
    pub fn new(ctx: &GpuContext, spec: VariantSpec, m: &Model<T>, n: usize, cells: usize) -> Result<Self, GpuError> {
        let tracking = spec.search == SearchKind::Tracking;
        let u = |name: &str, len| GpuVec::<u32>::new(ctx, &format!("sphlab.{name}"), len);
        let w = list_words(&spec, n, cells, size_of::<T>());
        let b4 = binding4_name(&spec);
        let cap = ctx.buffer_cap();
        let chunks = chunks(n, chunk_len(&spec, n, size_of::<T>(), cap));
        // A split array's words for a chunk of `len` particles (`list_words` of the chunk).
        let split = |name: &str, words: fn(&ListWords) -> usize| -> Result<Vec<GpuVec<u32>>, GpuError> {
            if chunks.len() == 1 || words(&w) == 1 {
                return Ok(vec![u(name, words(&w))?]);
            }
            chunks.iter().map(|&(_, len)| u(name, words(&list_words(&spec, len, cells, size_of::<T>())))).collect()
        };
        let ranges =
            chunks.iter().map(|&(b, l)| Uniform::new(ctx, "sphlab.vchunk", &[b as u32, l as u32, 0, 0])).collect();
        let b = Self {
            vctl: u("vctl", vctl::LEN)?,
            vparams: GpuVec::new(ctx, "sphlab.vparams", vparam::LEN)?,
            // List or candidate counts (0..n, n..2n); a renumbering's scratch for phase and
            // orig_of (`GpuSolver::record_renumbered`).
            counts: u("counts", 2 * n.max(1))?,
            nbr: split("nbr", |w| w.nbr)?,
            cache_wf: split(b4, |w| w.b4)?,
            cand_hi: u("cand_hi", w.b5)?,
            cand: u("cand", w.cand)?,
            ref_pos: GpuVec::<V2<T>>::new(ctx, "sphlab.ref_pos", if tracking { n } else { 1 })?,
            accum: split("accum", |w| w.accum)?,
            chunks,
            ranges,
            spec,
            every: TrackingCfg::default().every,
        };
        b.vparams.upload(ctx, &Self::constants(m))?;
        b.reset(ctx)?;
        Ok(b)
    }

    /// `vparams`: 1/q and q per field group, (support + skin)², (skin/2)², the clock at t = 0
    /// (dt = the fixed dt, 0 when adaptive) and the adaptive-dt constants.
    fn constants(m: &Model<T>) -> Vec<T> {
        let kp = m.kernel;
        let (dx, h) = (m.dx.f64(), kp.h.f64());
        let support = kp.support.f64();
        let g = (0..=1000)
            .map(|k| crate::physics::kernel::kernel_dwdr(&kp, T::c(support * k as f64 / 1000.0)).f64().abs())
            .fold(0.0, f64::max);
        let b = m.phases.iter().map(|p| (p.stiffness + p.p_b.abs()).f64()).fold(0.0, f64::max);
        let eta = m.phases.iter().map(|p| p.eta.f64()).fold(0.0, f64::max);
        let p = b + m.sigma_max / h + eta * m.c_max / h;
        let s_grad = NBR_SLOTS as f64 * g * dx.powi(4);
        let scales = [1.0 / (dx * dx), s_grad, s_grad * p.max(1e-30), 1.0];
        let mut v = vec![T::zero(); vparam::LEN];
        for (f, s) in scales.iter().enumerate() {
            let q = quantum(*s);
            v[vparam::INV_Q + f] = T::c(1.0 / q);
            v[vparam::Q + f] = T::c(q);
        }
        let skin = support * TrackingCfg::default().skin_ratio;
        v[vparam::CAND_R2] = T::c((support + skin) * (support + skin));
        v[vparam::HALF_SKIN2] = T::c(0.25 * skin * skin);
        v[vparam::DT] = T::c(m.dt_fixed.max(0.0));
        for (k, c) in [m.cfl, m.c_max, m.nu_max, m.rho_mean, m.sigma_max].into_iter().enumerate() {
            v[vparam::CFL + k] = T::c(c);
        }
        v[vparam::ADAPTIVE] = T::c(if m.dt_fixed <= 0.0 { 1.0 } else { 0.0 });
        v
    }

    /// Says whether the particles are in physical cell order (`vparam::PHYSICAL`).
    pub fn set_physical(&self, ctx: &GpuContext, on: bool) {
        let v = [T::c(if on { 1.0 } else { 0.0 })];
        let at = (vparam::PHYSICAL * size_of::<T>()) as u64;
        ctx.queue.write_buffer(&self.vparams.buffer, at, bytemuck::cast_slice(&v));
        ctx.traffic.write();
    }

    /// Clears the control words and forces a tracking rebuild at the next evaluation.
    pub fn reset(&self, ctx: &GpuContext) -> Result<(), GpuError> {
        let mut c = vec![0u32; vctl::LEN];
        c[vctl::OVER_FIRST] = u32::MAX;
        c[vctl::REBUILD] = 1;
        c[vctl::EVERY] = self.every;
        self.vctl.upload(ctx, &c)
    }

    /// Forces a tracking rebuild at the next evaluation (positions were replaced by hand),
    /// keeping the overflow counters.
    pub fn invalidate(&self, ctx: &GpuContext) -> Result<(), GpuError> {
        let mut c = self.vctl.read_back(ctx)?;
        c[vctl::REBUILD] = 1;
        self.vctl.upload(ctx, &c)
    }

    /// Tracking-list builds so far.
    pub fn rebuilds(&self, ctx: &GpuContext) -> Result<u64, GpuError> {
        Ok(self.vctl.read_back(ctx)?[vctl::REBUILDS] as u64)
    }

    /// `Err(NeighbourOverflow)` when a particle had more neighbours than the 64 list slots
    /// since the last call or its current tracking list (96 slots) is truncated (its `particle`
    /// is the noted DEVICE index: the solver maps it to the original one), `Err(Gpu)` when a
    /// fixed-point term left the accumulator's range (then clears the counters).
    pub fn overflow(&self, ctx: &GpuContext, step: u64) -> Result<(), SolverError> {
        let c = self.vctl.read_back(ctx).map_err(|e| SolverError::Gpu(e.to_string()))?;
        self.overflow_in(ctx, c, step)
    }

    /// [`Self::overflow`] on control words `c` already read back (`gpu::clock`'s one readback).
    pub fn overflow_in(&self, ctx: &GpuContext, mut c: Vec<u32>, step: u64) -> Result<(), SolverError> {
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        let cand = c[vctl::CAND_OVER].max(c[vctl::CAND_STALE]);
        let masks = uses_masks(&self.spec);
        let (bits, need) = (nbr_bits(&self.spec), c[vctl::NBR_NEED] as usize);
        let err = if cand > 0 && cand_masks(&self.spec) {
            let what = " (tracking candidates: bits of the candidate mask over the cell walk)".to_string();
            Some((cand, 32 * CAND_WORDS, c[vctl::CAND_MAX], what))
        } else if cand > 0 {
            Some((cand, CAND_SLOTS, c[vctl::CAND_MAX], " (tracking candidates)".to_string()))
        } else if c[vctl::NBR_OVER] > 0 && masks && need > bits {
            Some((c[vctl::NBR_OVER], bits, need as u32, " (bits of the list mask over the cell walk)".to_string()))
        } else if c[vctl::NBR_OVER] > 0 && c[vctl::POOL_NEED] as usize > POOL_REGION - POOL_BLOCK {
            let what = format!(
                " (entries of a pooled list block of {POOL_BLOCK} particles: room for {POOL_MEAN} per particle)"
            );
            Some((c[vctl::NBR_OVER], POOL_REGION - POOL_BLOCK, c[vctl::POOL_NEED], what))
        } else if c[vctl::NBR_OVER] > 0 {
            Some((c[vctl::NBR_OVER], NBR_SLOTS, c[vctl::NBR_MAX], String::new()))
        } else {
            None
        };
        let fixed = c[vctl::FIXED_OVER];
        if err.is_none() && fixed == 0 {
            return Ok(());
        }
        let first = c[vctl::OVER_FIRST];
        for w in [vctl::NBR_OVER, vctl::NBR_MAX, vctl::NBR_NEED, vctl::POOL_NEED, vctl::CAND_OVER, vctl::FIXED_OVER] {
            c[w] = 0;
        }
        c[vctl::OVER_FIRST] = u32::MAX;
        if c[vctl::CAND_STALE] == 0 {
            c[vctl::CAND_MAX] = 0;
        }
        self.vctl.upload(ctx, &c).map_err(gpu)?;
        let Some((particles, slots, max, what)) = err else {
            return Err(SolverError::Gpu(format!(
                "step {step}: {}: {fixed} fixed-point terms exceed the accumulator range (2^62 quanta)",
                self.spec
            )));
        };
        Err(SolverError::NeighbourOverflow {
            step,
            particle: (first != u32::MAX).then_some(first as usize),
            particles: particles as usize,
            slots,
            max: max as usize,
            variant: format!("{}{what}", self.spec),
        })
    }

    /// The accumulator buffers a block stage clears first (the fixed-point high words are in
    /// binding 4 unless kernel values are cached).
    pub(crate) fn accumulators(&self) -> Vec<&wgpu::Buffer> {
        let split = self.spec.accumulation == super::variant::Accumulation::Fixed
            && self.spec.kernel_values != super::variant::KernelValues::Cached;
        let mut v: Vec<&wgpu::Buffer> = self.accum.iter().map(|b| &b.buffer).collect();
        if split {
            v.extend(self.cache_wf.iter().map(|b| &b.buffer));
        }
        v
    }

    /// Every storage buffer allocated (each list chunk's once).
    pub(crate) fn all_storage(&self) -> Vec<&wgpu::Buffer> {
        let mut v = self.storage(0).to_vec();
        for c in 1..self.chunks.len() {
            for split in [&self.nbr, &self.cache_wf, &self.accum] {
                if split.len() > 1 {
                    v.push(&split[c].buffer);
                }
            }
        }
        v
    }

    /// The storage buffers of chunk `c`'s bind group (binding k at k).
    pub(crate) fn storage(&self, c: usize) -> [&wgpu::Buffer; N_VSTORAGE as usize] {
        fn of(v: &[GpuVec<u32>], c: usize) -> &wgpu::Buffer {
            &v[c.min(v.len() - 1)].buffer
        }
        [
            &self.vctl.buffer,
            &self.vparams.buffer,
            &self.counts.buffer,
            of(&self.nbr, c),
            of(&self.cache_wf, c),
            &self.cand_hi.buffer,
            &self.cand.buffer,
            &self.ref_pos.buffer,
            of(&self.accum, c),
        ]
    }

    /// The bind groups of `layout` (group 1) over these buffers, one per list chunk.
    pub fn bind_groups(
        &self,
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
    ) -> Result<Vec<wgpu::BindGroup>, GpuError> {
        (0..self.chunks.len())
            .map(|c| {
                let mut entries: Vec<_> = self
                    .storage(c)
                    .into_iter()
                    .enumerate()
                    .map(|(k, b)| wgpu::BindGroupEntry { binding: k as u32, resource: b.as_entire_binding() })
                    .collect();
                entries.push(wgpu::BindGroupEntry {
                    binding: CHUNK_BINDING,
                    resource: self.ranges[c].buffer.as_entire_binding(),
                });
                ctx.scoped(|d| {
                    d.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("sphlab.variant"),
                        layout,
                        entries: &entries,
                    })
                })
            })
            .collect()
    }
}

/// The group-1 layout and the two-group pipeline layout over `state` (group 0).
pub fn layouts(
    ctx: &GpuContext,
    state: &wgpu::BindGroupLayout,
) -> Result<(wgpu::BindGroupLayout, wgpu::PipelineLayout), GpuError> {
    let need = super::solver_buffers::N_STORAGE + N_VSTORAGE;
    let lim = &ctx.limits;
    let allowed = lim
        .max_storage_buffers_per_shader_stage
        .min(lim.max_buffers_and_acceleration_structures_per_shader_stage.saturating_sub(1));
    if allowed < need {
        return Err(GpuError::Unsupported(format!(
            "the solver binds {need} storage buffers and a uniform; the adapter allows {allowed} storage buffers per shader stage"
        )));
    }
    let entry = |binding: u32, ty: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    };
    let mut entries: Vec<_> =
        (0..N_VSTORAGE).map(|k| entry(k, wgpu::BufferBindingType::Storage { read_only: false })).collect();
    entries.push(entry(CHUNK_BINDING, wgpu::BufferBindingType::Uniform));
    ctx.scoped(|d| {
        let bgl = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sphlab.variant"),
            entries: &entries,
        });
        let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sphlab.state+variant"),
            bind_group_layouts: &[Some(state), Some(&bgl)],
            immediate_size: 0,
        });
        (bgl, pl)
    })
}
