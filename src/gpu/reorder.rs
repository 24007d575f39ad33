//! Cell-ordered particles (twin of `kernels-variants/search/reorder.wgsl`, bind group 2, bound
//! only by the reorder pipelines): the control words with the per-cell wall prefix and the
//! device permutation `orig_of[device]` (the gathers' scratch is `counts` and `grad`, free at
//! that point of an evaluation), plus the host side of the permutation. The direct search never
//! renumbers: it allocates one-word stand-ins and its permutation is the identity. The device renumbers the fluid particles in cell order every
//! [`RBufs::set_every`] evaluations (tracking variants: whenever their lists are rebuilt) inside
//! `neighbour_search`; walls keep their indices. Everything the host reads or writes goes
//! through [`to_original`] / [`to_device`], so outputs, snapshots, `verify` and the CPU
//! comparison see particles in their original order.

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
    /// 1 once the per-cell wall prefix is computed.
    pub const WALLS_READY: usize = 4;
    /// Control words; the per-cell wall prefix (cells + 1 words) follows.
    pub const LEN: usize = 8;
}

/// Storage buffers of group 2 (two: with groups 0 and 1 that is 31 of lavapipe's 32 per stage).
pub const N_RSTORAGE: u32 = 2;

/// Elements of (`reorder_ctl`, `reorder_idx`) for `n` particles on `cells` cells; one-word
/// stand-ins (the control words alone) when the search never renumbers. The memory plan's twin.
pub fn lens(renumbers: bool, n: usize, cells: usize) -> (usize, usize) {
    if renumbers {
        (rctl::LEN + cells + 1, n.max(1))
    } else {
        (rctl::LEN, 1)
    }
}

/// The group-2 buffers.
pub struct RBufs<T: Real> {
    /// Control words ([`rctl`]), then the per-cell wall prefix.
    pub rctl: GpuVec<u32>,
    /// `orig_of` (n).
    pub ridx: GpuVec<u32>,
    n: usize,
    renumbers: bool,
    _real: std::marker::PhantomData<T>,
}

impl<T: Real> RBufs<T> {
    /// Allocates the permutation (identity) of `n` particles on a grid of `cells` cells when the
    /// search `renumbers` (stand-ins otherwise); renumbering every `every` evaluations (0: never).
    pub fn new(ctx: &GpuContext, n: usize, cells: usize, every: u32, renumbers: bool) -> Result<Self, GpuError> {
        let (lc, li) = lens(renumbers, n, cells);
        let b = Self {
            rctl: GpuVec::new(ctx, "sphlab.reorder_ctl", lc)?,
            ridx: GpuVec::new(ctx, "sphlab.reorder_idx", li)?,
            n,
            renumbers,
            _real: std::marker::PhantomData,
        };
        if renumbers && n > 0 {
            b.ridx.upload(ctx, &(0..n as u32).collect::<Vec<u32>>())?;
        }
        b.set_every(ctx, every)?;
        Ok(b)
    }

    /// Renumbers every `every` evaluations from now on, the first at the next evaluation
    /// (0: never), keeping the count and the wall prefix.
    pub fn set_every(&self, ctx: &GpuContext, every: u32) -> Result<(), GpuError> {
        let mut c = self.rctl.read_back(ctx)?;
        c[rctl::NOW] = 0;
        c[rctl::EVERY] = every;
        c[rctl::SINCE] = every;
        self.rctl.upload(ctx, &c)
    }

    /// Renumberings so far.
    pub fn count(&self, ctx: &GpuContext) -> Result<u64, GpuError> {
        Ok(self.rctl.read_back(ctx)?[rctl::COUNT] as u64)
    }

    /// `orig_of`: the original index of each device index.
    pub fn orig_of(&self, ctx: &GpuContext) -> Result<Vec<u32>, GpuError> {
        if !self.renumbers {
            return Ok((0..self.n as u32).collect());
        }
        let mut v = self.ridx.read_back(ctx)?;
        v.truncate(self.n);
        Ok(v)
    }

    pub fn storage(&self) -> [&wgpu::Buffer; N_RSTORAGE as usize] {
        [&self.rctl.buffer, &self.ridx.buffer]
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
