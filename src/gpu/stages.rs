//! The table of GPU kernels per variant: which entry point of which `kernels-variants/` file runs
//! for each CPU stage name, over which index range, compiled with which defines. The `thread`
//! table is the base; the search adds its kernels to `neighbour_search` (tracking lists, the
//! explicit 64-slot lists), and the mapping / kernel-value axes replace the three pair-sum
//! stages (number_density, colour_gradient, acceleration) by their own kernels
//! ([`pair_stage`]); the other stages keep the thread kernels over the search's iterator. Every pipeline shares the one explicit layout of
//! [`super::solver_buffers`]; labels are `sphlab.<variant>.<stage>` (`.<entry>` added
//! when a stage has several kernels or its entry differs: `stage_<name>` avoids a clash with a
//! library function of the same name).

use super::compose::{compose_variant, F64};
use super::variant::{Accumulation, KernelValues, Mapping, Precision, SearchVariant, VariantSpec};
use super::{GpuContext, GpuError};
use std::collections::HashMap;

/// The index range a kernel is dispatched over (64 threads per workgroup unless noted).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    /// Every particle.
    All,
    /// Fluid particles.
    Fluid,
    /// Wall particles.
    Wall,
    /// One thread.
    One,
    /// One thread per grid cell.
    Cells,
    /// One workgroup (its own size).
    Group,
    /// The 16 × 32 block layout: N/32 workgroups in x, 4 in y (64 slots).
    Block,
}

/// One kernel: entry point, file (relative to `kernels-variants/`), dispatch domain.
#[derive(Clone, Copy, Debug)]
pub struct KernelDef {
    /// Entry point name (also the pipeline label suffix).
    pub entry: &'static str,
    /// File under `kernels-variants/`.
    pub file: &'static str,
    /// Dispatch range.
    pub domain: Domain,
}

const fn k(entry: &'static str, file: &'static str, domain: Domain) -> KernelDef {
    KernelDef { entry, file, domain }
}

/// Kernels of the `cells` neighbour search, in dispatch order.
pub const CELLS_SEARCH: &[KernelDef] = &[
    k("cell_count", "search/cell_count.wgsl", Domain::All),
    k("cell_scan", "search/cell_scan.wgsl", Domain::Group),
    k("cell_scatter", "search/cell_scatter.wgsl", Domain::All),
    k("cell_sort", "search/cell_scatter.wgsl", Domain::Cells),
];

/// The `thread` mapping: CPU stage name → kernels in dispatch order.
pub const THREAD_STAGES: &[(&str, &[KernelDef])] = &[
    ("number_density", &[k("number_density", "thread/number_density.wgsl", Domain::All)]),
    (
        "contact_line",
        &[
            k("contact_line", "thread/contact_line.wgsl", Domain::Fluid),
            k("contact_sort", "thread/contact_line.wgsl", Domain::One),
        ],
    ),
    ("wall_typing", &[k("wall_typing", "thread/wall_typing.wgsl", Domain::Wall)]),
    ("equation_of_state", &[k("equation_of_state", "thread/equation_of_state.wgsl", Domain::All)]),
    ("wall_pressure", &[k("wall_pressure", "thread/wall_pressure.wgsl", Domain::Wall)]),
    ("colour_gradient", &[k("colour_gradient", "thread/colour_gradient.wgsl", Domain::All)]),
    ("normal_correction", &[k("stage_normal_correction", "thread/normal_correction.wgsl", Domain::All)]),
    ("surface_stress", &[k("stage_surface_stress", "thread/surface_stress.wgsl", Domain::All)]),
    ("acceleration", &[k("acceleration", "thread/acceleration.wgsl", Domain::All)]),
    ("xsph", &[k("xsph", "thread/xsph.wgsl", Domain::Fluid)]),
    ("midpoint_predict", &[k("midpoint_predict", "thread/integrate.wgsl", Domain::Fluid)]),
    ("midpoint_correct", &[k("midpoint_correct", "thread/integrate.wgsl", Domain::Fluid)]),
    ("verlet_drift", &[k("verlet_drift", "thread/integrate.wgsl", Domain::Fluid)]),
    ("verlet_kick", &[k("verlet_kick", "thread/integrate.wgsl", Domain::Fluid)]),
    ("check", &[k("check", "thread/integrate.wgsl", Domain::Fluid)]),
    ("reduce_max", &[k("reduce_max", "thread/integrate.wgsl", Domain::Fluid)]),
];

/// Tracking lists, before the cell sort: displacement reduction and the rebuild decision.
pub const TRACKING_PRE: &[KernelDef] =
    &[k("track_check", "search/tracking.wgsl", Domain::All), k("track_every", "search/tracking.wgsl", Domain::One)];

/// Tracking lists, after the cell sort: candidate build (when flagged), flag cleared.
pub const TRACKING_POST: &[KernelDef] =
    &[k("track_build", "search/tracking.wgsl", Domain::All), k("track_clear", "search/tracking.wgsl", Domain::One)];

/// The explicit lists (and cached kernel values), built last in `neighbour_search`.
pub const NBR_BUILD: KernelDef = k("nbr_build", "search/nbr_list.wgsl", Domain::All);

/// The pair-sum stages whose kernels depend on the mapping and the kernel values.
pub const PAIR_STAGES: [&str; 3] = ["number_density", "colour_gradient", "acceleration"];

/// Kernels of pair-sum stage `name` for `spec`; `None` keeps the thread kernels.
pub fn pair_stage(spec: &VariantSpec, name: &'static str) -> Option<Vec<KernelDef>> {
    let fin = match name {
        "number_density" => "finalize_density",
        "colour_gradient" => "finalize_gradient",
        "acceleration" => "finalize_acceleration",
        _ => return None,
    };
    let block = |file| vec![k(name, file, Domain::Block), k(fin, "block/finalize.wgsl", Domain::All)];
    match spec.mapping {
        Mapping::Thread if spec.kernel_values == KernelValues::Cached => {
            Some(vec![k(name, "list/pair_sums.wgsl", Domain::All)])
        }
        Mapping::Thread => None,
        Mapping::BlockAtomic => Some(block("block/atomic.wgsl")),
        Mapping::BlockTree => Some(block("block/tree.wgsl")),
    }
}

/// The stage table of a variant: `neighbour_search` first, then the stages by CPU name.
pub fn kernel_table(spec: &VariantSpec) -> Result<Vec<(&'static str, Vec<KernelDef>)>, String> {
    spec.implemented()?;
    let mut search = match spec.search {
        SearchVariant::Direct => Vec::new(),
        SearchVariant::Cells => CELLS_SEARCH.to_vec(),
        SearchVariant::Tracking => [TRACKING_PRE, CELLS_SEARCH, TRACKING_POST].concat(),
    };
    if spec.has_lists() {
        search.push(NBR_BUILD);
    }
    let mut t = vec![("neighbour_search", search)];
    t.extend(THREAD_STAGES.iter().map(|(n, ks)| (*n, pair_stage(spec, n).unwrap_or_else(|| ks.to_vec()))));
    Ok(t)
}

/// Composition defines of a variant.
pub fn defines(spec: &VariantSpec) -> Vec<&'static str> {
    let mut d = Vec::new();
    if spec.precision == Precision::F64 {
        d.push(F64);
    }
    match spec.search {
        SearchVariant::Direct => d.push("DIRECT"),
        SearchVariant::Tracking => d.push("TRACKING"),
        SearchVariant::Cells => {}
    }
    if spec.kernel_values == KernelValues::Cached {
        d.push("CACHED");
    }
    match spec.accumulation {
        Accumulation::Cas => d.push("ACC_CAS"),
        Accumulation::Native => d.push("ACC_NATIVE"),
        Accumulation::Fixed | Accumulation::None => {}
    }
    d
}

/// The compiled pipelines of a variant, by stage name.
pub struct Pipelines {
    /// Stage name → (kernel, pipeline) in dispatch order.
    pub stages: HashMap<&'static str, Vec<(KernelDef, wgpu::ComputePipeline)>>,
}

impl Pipelines {
    /// Composes and compiles every kernel of `spec` against `layout` (one module per file).
    pub fn build(ctx: &GpuContext, spec: &VariantSpec, layout: &wgpu::PipelineLayout) -> Result<Self, GpuError> {
        let table: Vec<(&'static str, Vec<KernelDef>)> = kernel_table(spec).map_err(GpuError::Unsupported)?;
        let defs = defines(spec);
        let mut modules: HashMap<&'static str, wgpu::ShaderModule> = HashMap::new();
        let mut stages = HashMap::new();
        for (name, kernels) in table {
            let mut v = Vec::new();
            for kd in kernels {
                if !modules.contains_key(kd.file) {
                    let src = compose_variant(kd.file, &defs)?;
                    let label = format!("sphlab.{spec}.{}", kd.file);
                    let m = ctx.scoped(|d| {
                        d.create_shader_module(wgpu::ShaderModuleDescriptor {
                            label: Some(&label),
                            source: wgpu::ShaderSource::Wgsl(src.into()),
                        })
                    })?;
                    modules.insert(kd.file, m);
                }
                let label = if kd.entry.ends_with(name) {
                    format!("sphlab.{spec}.{name}")
                } else {
                    format!("sphlab.{spec}.{name}.{}", kd.entry)
                };
                let p = ctx
                    .scoped(|d| {
                        d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                            label: Some(&label),
                            layout: Some(layout),
                            module: &modules[kd.file],
                            entry_point: Some(kd.entry),
                            compilation_options: Default::default(),
                            cache: None,
                        })
                    })
                    .map_err(|e| GpuError::Validation(format!("{label}: {e}")))?;
                v.push((kd, p));
            }
            stages.insert(name, v);
        }
        Ok(Self { stages })
    }
}
