//! Compiled pipelines of each variant, built once per [`GpuContext`] and reused by every solver
//! of that variant (every size of a study sweep): the two bind-group layouts and the stage
//! pipelines depend only on the variant (with the subgroup kernels' lanes per particle) and the
//! device, never on the particle count.

use super::solver_buffers::layouts;
use super::stages::Pipelines;
use super::variant::VariantSpec;
use super::variant_buffers as vbufs;
use super::{GpuContext, GpuError};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// What a solver of one variant binds against: state layout (group 0), strategy layout
/// (group 1), cell-ordering layout (group 2, `gpu::reorder`) and the pipelines compiled against them.
pub struct Compiled {
    /// Group 0 (particle state).
    pub state_layout: wgpu::BindGroupLayout,
    /// Group 1 (strategy buffers).
    pub variant_layout: wgpu::BindGroupLayout,
    /// Group 2 (cell ordering).
    pub reorder_layout: wgpu::BindGroupLayout,
    /// The stage pipelines.
    pub pipes: Arc<Pipelines>,
}

/// The per-context cache (a field of [`GpuContext`]).
#[derive(Default)]
pub struct PipelineCache {
    map: Mutex<HashMap<(VariantSpec, u32), Arc<Compiled>>>,
    compiles: Mutex<u64>,
}

impl PipelineCache {
    /// The compiled pipelines of `spec` on `ctx` with `lanes` lanes per particle in the subgroup
    /// kernels (`stages::lanes_define`), compiling them on first use.
    pub fn get(&self, ctx: &GpuContext, spec: &VariantSpec, lanes: u32) -> Result<Arc<Compiled>, GpuError> {
        if let Some(c) = self.map.lock().expect("pipeline cache").get(&(*spec, lanes)) {
            return Ok(c.clone());
        }
        let (state_layout, _) = layouts(ctx)?;
        let (variant_layout, pl) = vbufs::layouts(ctx, &state_layout)?;
        let (reorder_layout, rpl) = super::reorder::layouts(ctx, &state_layout, &variant_layout)?;
        let pipes = Arc::new(Pipelines::build(ctx, spec, lanes, &pl, &rpl)?);
        let c = Arc::new(Compiled { state_layout, variant_layout, reorder_layout, pipes });
        *self.compiles.lock().expect("pipeline cache") += 1;
        self.map.lock().expect("pipeline cache").insert((*spec, lanes), c.clone());
        Ok(c)
    }

    /// How many variants were compiled on this context so far.
    pub fn compiles(&self) -> u64 {
        *self.compiles.lock().expect("pipeline cache")
    }
}
