//! Particles renumbered in cell order (twin of `kernels-variants/search/reorder.wgsl`, bind
//! group 2, bound only by the reorder pipelines): ONE buffer holding the control words and the
//! device permutation `orig_of[device]` (one binding: with the state's 22 and the variant's 9
//! that is lavapipe's 32 per stage), plus the host side of the permutation. In the evaluations
//! the host says (a `cells` search: every one, so the particles stay in physical cell order;
//! tracking: every [`RBufs::set_every`] evaluations, rebuilding its lists then) the search's
//! last kernel writes every particle at its slot into the twins of the persistent arrays, and
//! the host swaps their roles and copies phase and `orig_of` back
//! (`GpuSolver::record_renumbered`). The first renumbering puts the walls in their static
//! sort's order. The direct search never renumbers: it allocates the control words alone and
//! its permutation is the identity. Everything the host reads or writes goes through
//! [`to_original`] / [`to_device`], so outputs, snapshots, `verify` and the CPU comparison see
//! particles in their original order.

use super::{GpuContext, GpuError, GpuVec};
use crate::real::Real;

/// The kernel file.
pub const FILE: &str = "search/reorder.wgsl";

/// Words of `rctl` (`R_*` in reorder.wgsl).
pub mod rctl {
    /// 1: renumber in this evaluation.
    pub const NOW: usize = 0;
    /// Evaluations since the last renumbering.
    pub const SINCE: usize = 1;
    /// Renumber every this many evaluations (0: never).
    pub const EVERY: usize = 2;
    /// Renumberings so far.
    pub const COUNT: usize = 3;
    /// Control words; `orig_of` (n) follows.
    pub const LEN: usize = 8;
}

/// Storage buffers of group 2 (one: with groups 0 and 1 that is 32, lavapipe's per-stage maximum).
pub const N_RSTORAGE: u32 = 1;

/// Words of the `reorder` buffer for `n` particles: the control words and `orig_of` (n); the
/// control words alone when the search never renumbers. The memory plan's twin.
pub fn len(renumbers: bool, n: usize) -> usize {
    if renumbers {
        rctl::LEN + n
    } else {
        rctl::LEN
    }
}

/// The group-2 buffer.
pub struct RBufs<T: Real> {
    /// Control words ([`rctl`]), the per-cell wall prefix, `orig_of`.
    pub buf: GpuVec<u32>,
    n: usize,
    renumbers: bool,
    _real: std::marker::PhantomData<T>,
}

impl<T: Real> RBufs<T> {
    /// Allocates the permutation (identity) of `n` particles when the search `renumbers`
    /// (stand-ins otherwise); renumbering every `every` evaluations (0: never).
    pub fn new(ctx: &GpuContext, n: usize, every: u32, renumbers: bool) -> Result<Self, GpuError> {
        let b = Self {
            buf: GpuVec::new(ctx, "sphlab.reorder", len(renumbers, n))?,
            n,
            renumbers,
            _real: std::marker::PhantomData,
        };
        let mut init = vec![0u32; b.buf.len()];
        if renumbers {
            for (d, w) in init[b.orig_at()..].iter_mut().enumerate() {
                *w = d as u32;
            }
        }
        b.buf.upload(ctx, &init)?;
        b.set_every(ctx, every)?;
        Ok(b)
    }

    /// Renumbers every `every` evaluations from now on, the first at the next evaluation
    /// (0: never), keeping the count.
    pub fn set_every(&self, ctx: &GpuContext, every: u32) -> Result<(), GpuError> {
        let mut c = self.buf.read_range(ctx, 0, rctl::LEN)?;
        c[rctl::NOW] = 0;
        c[rctl::EVERY] = every;
        c[rctl::SINCE] = every;
        ctx.queue.write_buffer(&self.buf.buffer, 0, bytemuck::cast_slice(&c));
        ctx.traffic.write();
        Ok(())
    }

    /// Puts the permutation back to the identity (particles loaded in their original order).
    pub fn reset_order(&self, ctx: &GpuContext) -> Result<(), GpuError> {
        if self.renumbers {
            let id: Vec<u32> = (0..self.n as u32).collect();
            ctx.queue.write_buffer(&self.buf.buffer, 4 * self.orig_at() as u64, bytemuck::cast_slice(&id));
            ctx.traffic.write();
        }
        Ok(())
    }

    /// Renumberings so far.
    pub fn count(&self, ctx: &GpuContext) -> Result<u64, GpuError> {
        Ok(self.buf.read_range(ctx, rctl::COUNT, 1)?[0] as u64)
    }

    /// Word where `orig_of` starts (`R_ORIG` in reorder.wgsl).
    pub fn orig_at(&self) -> usize {
        rctl::LEN
    }

    /// `orig_of`: the original index of each device index.
    pub fn orig_of(&self, ctx: &GpuContext) -> Result<Vec<u32>, GpuError> {
        if !self.renumbers {
            return Ok((0..self.n as u32).collect());
        }
        self.buf.read_range(ctx, self.orig_at(), self.n)
    }

    pub fn storage(&self) -> [&wgpu::Buffer; N_RSTORAGE as usize] {
        [&self.buf.buffer]
    }

    /// The bind group of `layout` (group 2) over these buffers.
    pub fn bind_group(&self, ctx: &GpuContext, layout: &wgpu::BindGroupLayout) -> Result<wgpu::BindGroup, GpuError> {
        let entries: Vec<_> = self
            .storage()
            .into_iter()
            .enumerate()
            .map(|(k, b)| wgpu::BindGroupEntry { binding: k as u32, resource: b.as_entire_binding() })
            .collect();
        ctx.scoped(|d| {
            d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("sphlab.reorder"), layout, entries: &entries })
        })
    }
}

/// The group-2 layout and the three-group pipeline layout of the reorder kernels over `state`
/// (group 0) and `variant` (group 1).
pub fn layouts(
    ctx: &GpuContext,
    state: &wgpu::BindGroupLayout,
    variant: &wgpu::BindGroupLayout,
) -> Result<(wgpu::BindGroupLayout, wgpu::PipelineLayout), GpuError> {
    let need = super::solver_buffers::N_STORAGE + super::variant_buffers::N_VSTORAGE + N_RSTORAGE;
    let lim = &ctx.limits;
    let allowed = lim
        .max_storage_buffers_per_shader_stage
        .min(lim.max_buffers_and_acceleration_structures_per_shader_stage.saturating_sub(1));
    if allowed < need || lim.max_bind_groups < 3 {
        return Err(GpuError::Unsupported(format!(
            "cell reordering binds {need} storage buffers in 3 groups; the adapter allows {allowed} storage buffers \
             per shader stage and {} bind groups",
            lim.max_bind_groups
        )));
    }
    let entries: Vec<_> = (0..N_RSTORAGE)
        .map(|k| wgpu::BindGroupLayoutEntry {
            binding: k,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    ctx.scoped(|d| {
        let bgl = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sphlab.reorder"),
            entries: &entries,
        });
        let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sphlab.state+variant+reorder"),
            bind_group_layouts: &[Some(state), Some(variant), Some(&bgl)],
            immediate_size: 0,
        });
        (bgl, pl)
    })
}

/// Device-ordered `dev` (`per` consecutive elements per particle, `orig_of.len()` particles,
/// anything beyond kept in place) in the original order.
pub fn to_original<X: Copy>(dev: Vec<X>, per: usize, orig_of: &[u32]) -> Vec<X> {
    let mut out = dev.clone();
    for (d, &o) in orig_of.iter().enumerate() {
        let (d, o) = (d * per, o as usize * per);
        out[o..o + per].copy_from_slice(&dev[d..d + per]);
    }
    out
}

/// Original-ordered `orig` in the device order (inverse of [`to_original`]).
pub fn to_device<X: Copy>(orig: &[X], per: usize, orig_of: &[u32]) -> Vec<X> {
    let mut out = orig.to_vec();
    for (d, &o) in orig_of.iter().enumerate() {
        let (d, o) = (d * per, o as usize * per);
        out[d..d + per].copy_from_slice(&orig[o..o + per]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_and_original_order_are_inverse() {
        let orig_of = [2u32, 0, 1, 3];
        let dev: Vec<u32> = vec![20, 21, 0, 1, 10, 11, 30, 31, 99];
        let o = to_original(dev.clone(), 2, &orig_of);
        assert_eq!(o, vec![0, 1, 10, 11, 20, 21, 30, 31, 99]);
        assert_eq!(to_device(&o, 2, &orig_of), dev);
    }
}
