//! The GPU kernels of each stage of [`crate::stage::TABLE`] per variant: which entry point of which
//! `kernels-variants/` file runs, over which index range, compiled with which defines. The
//! `thread` table is the base (a stage's thread kernel is the entry point named as the stage);
//! the search adds its kernels to `neighbour_search` (cell reordering, tracking lists, the explicit 64-slot
//! lists), and the mapping / kernel-value axes replace the three pair-sum stages
//! ([`PAIR_STAGES`]) by their own kernels ([`pair_stage`]); the other stages keep the thread
//! kernels over the search's iterator. Every pipeline shares the one explicit layout of
//! [`super::solver_buffers`]; labels are `sphlab.<variant>.<stage>`, with `.<entry>` added for
//! a kernel whose entry point is not the stage name.

use super::compose::{compose_variant, F64};
use super::variant::{Accumulation, KernelValues, SumLayout, VariantSpec, SUBGROUP_LANES};
use super::{GpuContext, GpuError};
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::stage::Stage;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

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
    /// One workgroup per block of `plan::gpu::SCAN_BLOCK` cells (the parallel cell scan).
    ScanBlocks,
    /// One workgroup (its own size).
    Group,
    /// One workgroup (its own size) when the scene measures contact angles (Mode A's unbalanced
    /// Young force, docs/PHYSICS.md §8.2.5), else none.
    ContactAngles,
    /// One workgroup when the cell scan has more than `plan::SCAN_BLOCK` blocks, else none
    /// (`scan_add` sums the block sums itself then).
    BlockSums,
    /// The 16 × 32 block layout: N/32 workgroups in x, 4 in y (64 slots).
    Block,
    /// A group of G = min(lanes, the adapter's largest subgroup) lanes per particle
    /// ([`super::variant::SUBGROUP_LANES`]): N / (64 / G) workgroups of 64.
    Subgroups,
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

/// Kernels of the `cells` neighbour search, in dispatch order: the count, the scan ([`CELL_SCAN`])
/// and either the scatter and sort or, when the integrator has counted the particles after the
/// previous search built its lists, the merge of those lists ([`CELL_MERGE`]; the host records
/// one or the other: `GpuSolver::record_pass`).
pub const CELLS_SEARCH: &[KernelDef] = &[
    k("cell_count", "search/cell_count.wgsl", Domain::All),
    CELL_SCAN[0],
    CELL_SCAN[1],
    k("cell_scatter", "search/cell_scatter.wgsl", Domain::All),
    k("cell_sort", "search/cell_scatter.wgsl", Domain::Cells),
    k(CELL_MERGE, "search/cell_scatter.wgsl", Domain::Cells),
];

/// The kernels of the cell scan: the search's own, and the `cell_scan` stage's when it runs as a
/// pass of its own (fused, the last workgroup of the integrator stage scans).
pub const CELL_SCAN: [KernelDef; 2] = [
    k("scan_blocks", "search/cell_scan.wgsl", Domain::BlockSums),
    k("scan_add", "search/cell_scan.wgsl", Domain::ScanBlocks),
];

/// The entry point that builds each cell's list from the previous lists of the cells around it.
pub const CELL_MERGE: &str = "cell_merge";

/// The thread kernel of stage `s` (entry point = stage name) in `file`.
const fn t(s: Stage, file: &'static str, domain: Domain) -> KernelDef {
    k(s.name(), file, domain)
}

/// Particles renumbered in cell order (`gpu::reorder`; group 2 bound), in the evaluations the
/// host says: the cell lists built and every particle written into the twin arrays at its slot
/// (the walls into their static sort's order), by `reorder_sort` or `reorder_merge` in place of
/// the search's `cell_sort` or [`CELL_MERGE`] (the host records the one that replaces the
/// kernel the search would have run, then swaps the twins' roles). A halted device vetoes:
/// every particle is copied to its own slot.
pub const REORDER: &[KernelDef] =
    &[k("reorder_sort", super::reorder::FILE, Domain::Cells), k("reorder_merge", super::reorder::FILE, Domain::Cells)];

/// The `thread` mapping: stage → kernels in dispatch order (every stage but the search).
pub const THREAD_STAGES: &[(Stage, &[KernelDef])] = &[
    (Stage::NumberDensity, &[t(Stage::NumberDensity, "thread/number_density.wgsl", Domain::All)]),
    (
        Stage::ContactLine,
        &[
            t(Stage::ContactLine, "thread/contact_line.wgsl", Domain::Fluid),
            k("contact_angle", "thread/contact_angle.wgsl", Domain::ContactAngles),
        ],
    ),
    (Stage::WallTyping, &[t(Stage::WallTyping, "thread/wall_typing.wgsl", Domain::Wall)]),
    (Stage::EquationOfState, &[t(Stage::EquationOfState, "thread/equation_of_state.wgsl", Domain::All)]),
    (Stage::WallPressure, &[t(Stage::WallPressure, "thread/wall_pressure.wgsl", Domain::Wall)]),
    (Stage::ColourGradient, &[t(Stage::ColourGradient, "thread/colour_gradient.wgsl", Domain::All)]),
    (Stage::NormalCorrection, &[t(Stage::NormalCorrection, "thread/normal_correction.wgsl", Domain::All)]),
    (Stage::SurfaceStress, &[t(Stage::SurfaceStress, "thread/surface_stress.wgsl", Domain::All)]),
    (Stage::Acceleration, &[t(Stage::Acceleration, "thread/acceleration.wgsl", Domain::All)]),
    (Stage::Xsph, &[t(Stage::Xsph, "thread/xsph.wgsl", Domain::Fluid)]),
    (Stage::MidpointPredict, &[t(Stage::MidpointPredict, "thread/integrate.wgsl", Domain::Fluid)]),
    (Stage::MidpointCorrect, &[t(Stage::MidpointCorrect, "thread/integrate.wgsl", Domain::Fluid)]),
    (Stage::VerletDrift, &[t(Stage::VerletDrift, "thread/integrate.wgsl", Domain::Fluid)]),
    (Stage::VerletKick, &[t(Stage::VerletKick, "thread/integrate.wgsl", Domain::Fluid)]),
    (
        Stage::Check,
        &[
            k("clock_tick", "thread/integrate.wgsl", Domain::One),
            t(Stage::Check, "thread/integrate.wgsl", Domain::Fluid),
        ],
    ),
    (Stage::CellCount, &[t(Stage::CellCount, "search/cell_count.wgsl", Domain::All)]),
    (Stage::CellScan, &CELL_SCAN),
    (Stage::ReduceMax, &[t(Stage::ReduceMax, "thread/integrate.wgsl", Domain::Fluid)]),
];

/// Tracking lists, before the cell sort: displacement reduction and the rebuild decision.
pub const TRACKING_PRE: &[KernelDef] =
    &[k("track_check", "search/tracking.wgsl", Domain::All), k("track_every", "search/tracking.wgsl", Domain::One)];

/// Tracking lists, after the cell sort: candidate build (when flagged), flag cleared.
pub const TRACKING_POST: &[KernelDef] =
    &[k("track_build", "search/tracking.wgsl", Domain::All), k("track_clear", "search/tracking.wgsl", Domain::One)];

/// The explicit lists (and cached kernel values), built last in `neighbour_search`, then the
/// evaluation's overflow count folded into its maximum (one thread).
pub const NBR_BUILD: &[KernelDef] =
    &[k("nbr_build", "search/nbr_list.wgsl", Domain::All), k("nbr_fold", "search/nbr_list.wgsl", Domain::One)];

/// The pair-sum stages whose kernels depend on the mapping and the kernel values, each with
/// the entry point that finalises a block accumulation.
pub const PAIR_STAGES: [(Stage, &str); 3] = [
    (Stage::NumberDensity, "finalize_density"),
    (Stage::ColourGradient, "finalize_gradient"),
    (Stage::Acceleration, "finalize_acceleration"),
];

/// Kernels of pair-sum stage `stage` for `spec`; `None` keeps the thread kernels.
pub fn pair_stage(spec: &VariantSpec, stage: Stage) -> Option<Vec<KernelDef>> {
    let fin = PAIR_STAGES.iter().find(|(s, _)| *s == stage)?.1;
    let block = |file| vec![k(stage.name(), file, Domain::Block), k(fin, "block/finalize.wgsl", Domain::All)];
    match (spec.mapping.layout(), spec.mapping.pair_file()) {
        (SumLayout::Block, Some(file)) => Some(block(file)),
        (SumLayout::Subgroup, Some(file)) => Some(vec![k(stage.name(), file, Domain::Subgroups)]),
        (_, Some(file)) => Some(vec![k(stage.name(), file, Domain::All)]),
        (_, None) if spec.kernel_values == KernelValues::Cached => {
            Some(vec![k(stage.name(), "list/pair_sums.wgsl", Domain::All)])
        }
        (_, None) => None,
    }
}

/// The kernels of every stage of a variant: `neighbour_search` first, then the table's order.
pub fn kernel_table(spec: &VariantSpec) -> Vec<(Stage, Vec<KernelDef>)> {
    let mut search = match spec.search {
        // The masks' walk needs this evaluation's cell sort (no renumbering).
        SearchKind::Direct if spec.sorts_cells() => CELLS_SEARCH.to_vec(),
        SearchKind::Direct => Vec::new(),
        SearchKind::Cells => [CELLS_SEARCH, REORDER].concat(),
        SearchKind::Tracking => [TRACKING_PRE, CELLS_SEARCH, REORDER, TRACKING_POST].concat(),
    };
    if spec.has_lists() {
        search.extend_from_slice(NBR_BUILD);
    }
    let mut t = vec![(Stage::NeighbourSearch, search)];
    t.extend(THREAD_STAGES.iter().map(|(s, ks)| (*s, pair_stage(spec, *s).unwrap_or_else(|| ks.to_vec()))));
    if !spec.sorts_cells() {
        // No cells to count.
        t.retain(|(s, _)| !matches!(s, Stage::CellCount | Stage::CellScan));
    }
    t
}

/// The domain of a kernel of a fused pass: its own, widened to every particle when an
/// epilogue's own kernel (the one named as its stage) runs over more particles than the head's
/// fluid or wall range (the cell count of every particle after the fluids' integration).
fn fused_domain(own: Domain, pass: &[Stage], table: &[(Stage, Vec<KernelDef>)]) -> Domain {
    let epilogue_domain = |s: &Stage| {
        table
            .iter()
            .find(|(t, _)| t == s)
            .and_then(|(_, ks)| ks.iter().find(|kd| kd.entry == s.name()))
            .map(|kd| kd.domain)
    };
    let wider = pass[1..].iter().filter_map(epilogue_domain).any(|d| d == Domain::All);
    match own {
        Domain::Fluid | Domain::Wall if wider => Domain::All,
        d => d,
    }
}

/// Composition defines of a variant.
pub fn defines(spec: &VariantSpec) -> Vec<&'static str> {
    let mut d = Vec::new();
    if spec.precision == Precision::F64 {
        d.push(F64);
    }
    match spec.search {
        SearchKind::Direct => d.push("DIRECT"),
        SearchKind::Tracking => d.push("TRACKING"),
        SearchKind::Cells => {}
    }
    if spec.kernel_values == KernelValues::Cached {
        d.push("CACHED");
    }
    d.extend(spec.workgroup.define());
    if super::mask_lists::uses_masks(spec) {
        d.push("MASK_LISTS");
    }
    let cands = super::mask_lists::cand_masks(spec);
    if cands {
        d.push("MASK_CANDS");
    }
    // The neighbour loop's spans are the iterator's single neighbours (common/neighbours.wgsl).
    if spec.search == SearchKind::Direct || cands {
        d.push("NB_ITERATOR");
    }
    if spec.slots == super::pooled_lists::SlotLayout::Pooled {
        d.push("POOLED_LISTS");
    } else if spec.has_lists() && spec.mapping.layout() == SumLayout::Thread {
        d.push("SLOT_MAJOR");
    }
    match spec.accumulation {
        Accumulation::Cas => d.push("ACC_CAS"),
        Accumulation::Native => d.push("ACC_NATIVE"),
        Accumulation::Fixed | Accumulation::None => {}
    }
    d
}

/// The define that composes the subgroup kernels with `lanes` lanes per particle (`LANES2`,
/// `LANES4`, `LANES8`; none for [`SUBGROUP_LANES`], the kernels' default), `Err` naming the
/// accepted values for any other count.
pub fn lanes_define(lanes: u32) -> Result<Option<&'static str>, String> {
    match lanes {
        2 => Ok(Some("LANES2")),
        4 => Ok(Some("LANES4")),
        8 => Ok(Some("LANES8")),
        SUBGROUP_LANES => Ok(None),
        _ => Err(format!("subgroup lanes per particle must be 2, 4, 8 or {SUBGROUP_LANES} (got {lanes})")),
    }
}

/// Kernels and their pipelines, in dispatch order.
pub type Compiled = Vec<(KernelDef, wgpu::ComputePipeline)>;

/// The compiled pipelines of a variant, by stage, and its fused passes (compiled on first use).
pub struct Pipelines {
    /// Stage → (kernel, pipeline) in dispatch order.
    pub stages: HashMap<Stage, Compiled>,
    spec: VariantSpec,
    /// Lanes per particle the subgroup kernels were composed with ([`lanes_define`]).
    pub lanes: u32,
    layout: wgpu::PipelineLayout,
    fused: Mutex<HashMap<Vec<Stage>, Arc<Compiled>>>,
}

/// The define that runs epilogue stage `s` at the end of its pass (common/pair_terms.wgsl).
pub fn fuse_define(s: Stage) -> String {
    format!("FUSE_{}", s.name().to_uppercase())
}

/// Modules by file, composed with one define set.
type Modules = HashMap<&'static str, wgpu::ShaderModule>;

/// Composes (into `modules`, once per file) and compiles `kernels` with `defs`, each pipeline
/// labelled by `label(kernel)`, against `layouts.0` (the reorder kernels against `layouts.1`).
fn compile(
    ctx: &GpuContext,
    spec: &VariantSpec,
    (kernels, defs): (&[KernelDef], &[&str]),
    modules: &mut Modules,
    layouts: (&wgpu::PipelineLayout, &wgpu::PipelineLayout),
    label: impl Fn(&KernelDef) -> String,
) -> Result<Compiled, GpuError> {
    let mut v = Vec::new();
    for kd in kernels {
        if !modules.contains_key(kd.file) {
            let src = compose_variant(kd.file, defs)?;
            let label = format!("sphlab.{spec}.{}", kd.file);
            let m = ctx.scoped(|d| {
                d.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&label),
                    source: wgpu::ShaderSource::Wgsl(src.into()),
                })
            })?;
            modules.insert(kd.file, m);
        }
        let label = label(kd);
        let p = ctx
            .scoped(|d| {
                d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(&label),
                    layout: Some(if kd.file == super::reorder::FILE { layouts.1 } else { layouts.0 }),
                    module: &modules[kd.file],
                    entry_point: Some(kd.entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            })
            .map_err(|e| GpuError::Validation(format!("{label}: {e}")))?;
        v.push((*kd, p));
    }
    Ok(v)
}

impl Pipelines {
    /// Composes and compiles every kernel of `spec` against `layout` (the reorder kernels against
    /// `reorder_layout`, which adds group 2), one module per file and stage, the subgroup kernels
    /// with `lanes` lanes per particle ([`lanes_define`]).
    pub fn build(
        ctx: &GpuContext,
        spec: &VariantSpec,
        lanes: u32,
        layout: &wgpu::PipelineLayout,
        reorder_layout: &wgpu::PipelineLayout,
    ) -> Result<Self, GpuError> {
        let mut defs = defines(spec);
        defs.extend(lanes_define(lanes).map_err(GpuError::Unsupported)?);
        let mut modules = Modules::new();
        let mut stages = HashMap::new();
        for (stage, kernels) in kernel_table(spec) {
            let label = |kd: &KernelDef| {
                if kd.entry == stage.name() {
                    format!("sphlab.{spec}.{stage}")
                } else {
                    format!("sphlab.{spec}.{stage}.{}", kd.entry)
                }
            };
            let both = (layout, reorder_layout);
            stages.insert(stage, compile(ctx, spec, (&kernels, &defs), &mut modules, both, label)?);
        }
        Ok(Self { stages, spec: *spec, lanes, layout: layout.clone(), fused: Mutex::new(HashMap::new()) })
    }

    /// The kernels of a fused pass (its first stage's, composed with `FUSED` and the
    /// [`fuse_define`] of each later stage, `stage::passes`), compiled on first use; a pass of
    /// one stage is that stage's own kernels.
    pub fn fused(&self, ctx: &GpuContext, pass: &[Stage]) -> Result<Arc<Compiled>, GpuError> {
        if let Some(c) = self.fused.lock().unwrap_or_else(|p| p.into_inner()).get(pass) {
            return Ok(c.clone());
        }
        let head = pass[0];
        let table = kernel_table(&self.spec);
        let mut kernels = table.iter().find(|(s, _)| *s == head).map(|(_, k)| k.clone()).unwrap_or_default();
        for kd in &mut kernels {
            kd.domain = fused_domain(kd.domain, pass, &table);
        }
        let extra: Vec<String> = pass[1..].iter().map(|s| fuse_define(*s)).collect();
        let mut defs = defines(&self.spec);
        defs.extend(lanes_define(self.lanes).map_err(GpuError::Unsupported)?);
        if pass.len() > 1 {
            defs.push("FUSED");
        }
        defs.extend(extra.iter().map(String::as_str));
        let name = crate::stage::pass_label(pass);
        let spec = self.spec;
        let label = |kd: &KernelDef| format!("sphlab.{spec}.{name}.{}", kd.entry);
        let layouts = (&self.layout, &self.layout);
        let c = Arc::new(compile(ctx, &spec, (&kernels, &defs), &mut Modules::new(), layouts, label)?);
        self.fused.lock().unwrap_or_else(|p| p.into_inner()).insert(pass.to_vec(), c.clone());
        Ok(c)
    }
}
