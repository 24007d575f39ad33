//! GPU variant ids (docs/STUDY.md): search × mapping × accumulation × kernel values × precision
//! (× workgroup size, a study axis of the thread mapping), written
//! `"{search}.{mapping}[.{accum}].{kernel_values}.{precision}[.wg{128|256}]"`, e.g.
//! `cells.thread.recomputed.f32`, `cells.thread.recomputed.f32.wg256` or
//! `tracking.block-atomic.fixed.cached.f32`; the mappings are
//! registered in one table (`mappings!`: id, kernel file, layout; `subgroup` needs SUBGROUP).
//! [`VariantSpec::all`] lists every combination that makes sense (an accumulation only for the block mappings; no
//! float atomics in f64, so f64 block variants accumulate in fixed point only) and every one
//! is implemented; [`VariantSpec::support`] says why an adapter cannot run one.

pub use super::pooled_lists::SlotLayout;
use super::GpuContext;
use crate::neighbours::SearchKind;
use crate::real::Precision;
use std::fmt;
use std::str::FromStr;

/// How a mapping lays out the neighbour sums.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SumLayout {
    /// One thread per particle, sequential gather (no atomics in the sums, no accumulation).
    Thread,
    /// The thesis's 16 × 32 block over the 64-slot lists: atomics into an accumulator
    /// (`cas`, `native` or `fixed`), then a finalize kernel per field.
    Block,
    /// A group of `min(SUBGROUP_LANES, S)` lanes of a subgroup per particle over the 64-slot
    /// lists, the group's sums added by a shuffle butterfly (no atomics, no accumulation; needs SUBGROUP).
    Subgroup,
}

/// How the block mappings accumulate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Accumulation {
    /// No accumulation across threads (thread mapping).
    None,
    /// Compare-and-swap loop on float bits.
    Cas,
    /// Native `atomic<f32>` add (SHADER_FLOAT32_ATOMIC).
    Native,
    /// Fixed-point integer atomics.
    Fixed,
}

/// Kernel values: recomputed in every stage or cached per neighbour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KernelValues {
    /// Recomputed from distances in every stage.
    Recomputed,
    /// Cached per neighbour pair once per evaluation.
    Cached,
}

/// Threads per workgroup of the one-thread-per-item kernels (`GROUP_THREADS`,
/// kernels-variants/common/dispatch.wgsl): 64 for every mapping; 128 or 256 as a study axis of
/// the thread mapping (the block layout is 16 × 32, the subgroup mapping's groups hold 64).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Workgroup {
    /// 64 threads (the default, written nowhere in the id).
    W64,
    /// 128 threads (`.wg128`).
    W128,
    /// 256 threads (`.wg256`).
    W256,
}

impl Workgroup {
    /// Every size, smallest first.
    pub const ALL: &'static [Workgroup] = &[Workgroup::W64, Workgroup::W128, Workgroup::W256];
    /// Threads per workgroup.
    pub fn threads(self) -> u32 {
        match self {
            Workgroup::W64 => 64,
            Workgroup::W128 => 128,
            Workgroup::W256 => 256,
        }
    }
    /// The id suffix (`wg128`; `wg64` for the default, which ids leave out).
    pub fn name(self) -> String {
        format!("wg{}", self.threads())
    }
    /// The size of `threads` (64, 128 or 256).
    pub fn of(threads: u32) -> Option<Self> {
        Self::ALL.iter().copied().find(|w| w.threads() == threads)
    }
    /// The composition define (`WG128`, `WG256`; none for 64).
    pub fn define(self) -> Option<&'static str> {
        match self {
            Workgroup::W64 => None,
            Workgroup::W128 => Some("WG128"),
            Workgroup::W256 => Some("WG256"),
        }
    }
}

/// One GPU variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VariantSpec {
    /// Neighbour search.
    pub search: SearchKind,
    /// Work mapping.
    pub mapping: Mapping,
    /// Accumulation (`None` exactly for the thread mapping).
    pub accumulation: Accumulation,
    /// Kernel values.
    pub kernel_values: KernelValues,
    /// Precision.
    pub precision: Precision,
    /// Threads per workgroup of the one-thread-per-item kernels (64 unless a thread variant
    /// says `.wg128` or `.wg256`).
    pub workgroup: Workgroup,
    /// Format of the neighbour and tracking lists (`gpu::mask_lists`): chosen by N unless the
    /// id forces one with `.slots` or `.masks`.
    pub lists: ListFormat,
    /// Slot layout of the lists with cached kernel values (`gpu::pooled_lists`): chosen by the
    /// memory plan unless the id forces one with `.full` or `.pooled`.
    pub slots: SlotLayout,
}

/// Format of the explicit neighbour lists and tracking candidates of the cells and tracking
/// searches with recomputed kernel values (the other variants always keep slots).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ListFormat {
    /// Chosen by the memory plan (`gpu::plan::resolve_lists`): slots while every slot buffer
    /// fits the adapter's per-buffer cap, masks beyond.
    Auto,
    /// One index per entry: 64 neighbour slots, 96 tracking-candidate slots.
    Slots,
    /// Bitmasks over the cell walk (`gpu::mask_lists`).
    Masks,
}

impl ListFormat {
    /// The id suffix (`None` for `Auto`).
    pub fn suffix(self) -> Option<&'static str> {
        match self {
            ListFormat::Auto => None,
            ListFormat::Slots => Some("slots"),
            ListFormat::Masks => Some("masks"),
        }
    }
}

macro_rules! names {
    ($t:ty { $($v:ident = $s:literal),* }) => {
        impl $t {
            /// Every value.
            pub const ALL: &'static [$t] = &[$(<$t>::$v),*];
            /// The id component.
            pub fn name(self) -> &'static str {
                match self { $(<$t>::$v => $s),* }
            }
            fn parse(s: &str) -> Option<Self> {
                match s { $($s => Some(<$t>::$v),)* _ => None }
            }
        }
    };
}

/// The mapping registry: one line per mapping, `Variant = "id": file, layout;`. The file holds
/// the mapping's pair-sum kernels, one entry point per pair-sum stage named as the stage
/// (`None`: each stage's own thread kernel, or the list kernels with cached values).
macro_rules! mappings {
    ($($(#[$doc:meta])* $v:ident = $id:literal: $file:expr, $layout:ident;)*) => {
        /// Work mapping of the neighbour sums (the registry of [`mappings!`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Mapping {
            $($(#[$doc])* $v,)*
        }
        names!(Mapping { $($v = $id),* });
        impl Mapping {
            /// The file of the pair-sum kernels under `kernels-variants/`.
            pub fn pair_file(self) -> Option<&'static str> {
                match self { $(Mapping::$v => $file,)* }
            }
            /// How the sums are laid out.
            pub fn layout(self) -> SumLayout {
                match self { $(Mapping::$v => SumLayout::$layout,)* }
            }
        }
    };
}
mappings! {
    /// One thread per particle, sequential gather (no atomics in the sums).
    Thread = "thread": None, Thread;
    /// Thesis §6.4.1: 32 particles × 16 neighbour threads per workgroup, 4 workgroups in y
    /// over the 64 list slots, one atomic add per pair term.
    BlockAtomic = "block-atomic": Some("block/atomic.wgsl"), Block;
    /// The same layout, tree reduction of each row in workgroup memory, then one atomic add
    /// per particle per workgroup.
    BlockTree = "block-tree": Some("block/tree.wgsl"), Block;
    /// Beyond the thesis: a group of [`SUBGROUP_LANES`] lanes of a subgroup per particle over
    /// its list, the group's partial sums added by a `subgroupShuffleXor` butterfly (Features::SUBGROUP).
    Subgroup = "subgroup": Some("subgroup/pair_sums.wgsl"), Subgroup;
}
names!(Accumulation { None = "none", Cas = "cas", Native = "native", Fixed = "fixed" });
names!(KernelValues { Recomputed = "recomputed", Cached = "cached" });

impl Default for VariantSpec {
    fn default() -> Self {
        DEFAULT_VARIANT.parse().expect("default id parses")
    }
}

/// Largest subgroup the `subgroup` mapping takes (its workgroups have 64 threads).
pub const SUBGROUP_MAX: u32 = 64;

/// Lanes per particle of the `subgroup` mapping (`LANES`, kernels-variants/subgroup/pair_sums.wgsl):
/// each particle gets G = min(SUBGROUP_LANES, S) lanes of a subgroup of S (S / G particles per
/// subgroup), a group sized to lists of ~30–40 entries; the tests also compose 2, 4 and 8
/// (`GpuSolver::with_subgroup_lanes`, `stages::lanes_define`).
pub const SUBGROUP_LANES: u32 = 16;

/// The variant `--backend gpu` uses without `--variant`.
pub const DEFAULT_VARIANT: &str = "cells.thread.recomputed.f32";

impl VariantSpec {
    /// True when the accumulation fits the mapping (`none` exactly for the non-block mappings)
    /// and a workgroup size other than 64 is the thread mapping's.
    pub fn is_consistent(&self) -> bool {
        (self.mapping.layout() != SumLayout::Block) == (self.accumulation == Accumulation::None)
            && (self.workgroup == Workgroup::W64 || self.mapping.layout() == SumLayout::Thread)
            && (self.lists == ListFormat::Auto || self.list_format_matters())
            && (self.slots == SlotLayout::Auto || self.kernel_values == KernelValues::Cached)
    }

    /// True when the list format is a choice: every search with recomputed kernel values that
    /// keeps lists, and every tracking variant (it keeps candidates; with cached kernel values
    /// only the candidates take masks, the cache needs list slots). The direct search's masks
    /// index the walk of a cell sort run for their storage alone (`gpu::mask_lists`).
    pub fn list_format_matters(&self) -> bool {
        self.search == SearchKind::Tracking || (self.kernel_values == KernelValues::Recomputed && self.has_lists())
    }

    /// True when the variant sorts the particles into cells: the cells and tracking searches, and
    /// the direct search whose lists are masks over a cell walk.
    pub fn sorts_cells(&self) -> bool {
        self.search != SearchKind::Direct || crate::gpu::mask_lists::uses_masks(self)
    }

    /// The same variant with list format `lists` (`None` unless the format is a choice).
    pub fn with_lists(self, lists: ListFormat) -> Option<VariantSpec> {
        Some(VariantSpec { lists, ..self }).filter(|s| s.is_consistent())
    }

    /// The same variant with slot layout `slots` (`None` unless it has cached kernel values).
    pub fn with_slots(self, slots: SlotLayout) -> Option<VariantSpec> {
        Some(VariantSpec { slots, ..self }).filter(|s| s.is_consistent())
    }

    /// The same variant with `workgroup` threads per workgroup (`None` unless consistent).
    pub fn with_workgroup(self, workgroup: Workgroup) -> Option<VariantSpec> {
        Some(VariantSpec { workgroup, ..self }).filter(|s| s.is_consistent())
    }

    /// Every variant that makes sense at the default workgroup size, in a stable order (the
    /// workgroup sizes of the thread mapping are a study axis: [`Self::with_workgroup`]).
    pub fn all() -> Vec<VariantSpec> {
        let mut v = Vec::new();
        for &search in SearchKind::ALL {
            for &mapping in Mapping::ALL {
                for &accumulation in Accumulation::ALL {
                    for &kernel_values in KernelValues::ALL {
                        for &precision in Precision::ALL {
                            let (workgroup, lists) = (Workgroup::W64, ListFormat::Auto);
                            let s = VariantSpec {
                                search,
                                mapping,
                                accumulation,
                                kernel_values,
                                precision,
                                workgroup,
                                lists,
                                slots: SlotLayout::Auto,
                            };
                            if s.is_consistent() && s.meaningful().is_ok() {
                                v.push(s);
                            }
                        }
                    }
                }
            }
        }
        v
    }

    /// Every id, comma separated (for error messages).
    pub fn all_ids() -> String {
        Self::all().iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")
    }

    /// True when the variant runs on explicit 64-slot neighbour lists (block and subgroup
    /// mappings, cached kernel values).
    pub fn has_lists(&self) -> bool {
        self.mapping.layout() != SumLayout::Thread || self.kernel_values == KernelValues::Cached
    }

    /// `Err(reason)` for a consistent id that is not a meaningful variant.
    pub fn meaningful(&self) -> Result<(), String> {
        if self.precision == Precision::F64 && matches!(self.accumulation, Accumulation::Cas | Accumulation::Native) {
            return Err(format!(
                "{self}: f64 {} accumulation is not meaningful: WGSL has no 64-bit float atomics \
                 (a u64 CAS would need SHADER_INT64_ATOMIC_ALL_OPS); use `fixed` in f64",
                self.accumulation.name()
            ));
        }
        Ok(())
    }

    /// The optional adapter features this variant needs, with their names.
    pub fn features(&self) -> Vec<(wgpu::Features, &'static str)> {
        let mut v = Vec::new();
        if self.precision == Precision::F64 {
            v.push((wgpu::Features::SHADER_F64, "SHADER_F64"));
        }
        if self.accumulation == Accumulation::Native {
            v.push((wgpu::Features::SHADER_FLOAT32_ATOMIC, "SHADER_FLOAT32_ATOMIC"));
        }
        if self.mapping.layout() == SumLayout::Subgroup {
            v.push((wgpu::Features::SUBGROUP, "SUBGROUP"));
        }
        v
    }

    /// `Err(reason)` when the adapter lacks a feature or a limit this variant needs.
    pub fn support(&self, ctx: &GpuContext) -> Result<(), String> {
        let threads = self.workgroup.threads();
        if threads > ctx.limits.max_compute_invocations_per_workgroup
            || threads > ctx.limits.max_compute_workgroup_size_x
        {
            return Err(format!(
                "{self}: {threads} threads per workgroup exceed the adapter's limits ({} invocations, x size {})",
                ctx.limits.max_compute_invocations_per_workgroup, ctx.limits.max_compute_workgroup_size_x
            ));
        }
        if self.mapping.layout() == SumLayout::Block {
            let (inv, wgs) =
                (ctx.limits.max_compute_invocations_per_workgroup, ctx.limits.max_compute_workgroup_size_y);
            if inv < 512 || wgs < 32 {
                return Err(format!(
                    "{self}: the 16 × 32 block layout needs 512 invocations per workgroup (adapter: {inv}, y size {wgs})"
                ));
            }
            let real = if self.precision == Precision::F64 { 8 } else { 4 };
            let tree = 2 * 512 * 2 * real;
            if self.mapping == Mapping::BlockTree && ctx.limits.max_compute_workgroup_storage_size < tree {
                return Err(format!(
                    "{self}: the tree reduction needs {tree} bytes of workgroup memory (adapter: {})",
                    ctx.limits.max_compute_workgroup_storage_size
                ));
            }
        }
        for (feature, name) in self.features() {
            if !ctx.has(feature) {
                return Err(format!("{self}: the adapter lacks {name}"));
            }
        }
        let sg = ctx.adapter_info.subgroup_max_size;
        if self.mapping.layout() == SumLayout::Subgroup && sg > SUBGROUP_MAX {
            return Err(format!("{self}: subgroups of up to {sg} lanes do not fit the mapping's 64-thread workgroup"));
        }
        Ok(())
    }

    /// `Err(reason)` when this build has no implementation of the variant: every consistent,
    /// meaningful id is implemented. Parsing an id checks it; [`super::solver::GpuSolver::new`]
    /// checks a spec built field by field.
    pub fn implemented(&self) -> Result<(), String> {
        if !self.is_consistent() {
            return Err(format!(
                "{self}: an accumulation belongs to the block mappings only, a workgroup size to the thread mapping"
            ));
        }
        self.meaningful()
    }
}

impl fmt::Display for VariantSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.search.name(), self.mapping.name())?;
        if self.accumulation != Accumulation::None {
            write!(f, ".{}", self.accumulation.name())?;
        }
        write!(f, ".{}.{}", self.kernel_values.name(), self.precision.name())?;
        if self.workgroup != Workgroup::W64 {
            write!(f, ".{}", self.workgroup.name())?;
        }
        if let Some(l) = self.lists.suffix() {
            write!(f, ".{l}")?;
        }
        if let Some(l) = self.slots.suffix() {
            write!(f, ".{l}")?;
        }
        Ok(())
    }
}

impl FromStr for VariantSpec {
    type Err = String;
    fn from_str(id: &str) -> Result<Self, String> {
        let bad = || format!("unknown GPU variant `{id}`; valid ids: {}", VariantSpec::all_ids());
        let mut parts: Vec<&str> = id.split('.').collect();
        let slots = parts.last().and_then(|s| SlotLayout::parse(s)).unwrap_or(SlotLayout::Auto);
        if slots != SlotLayout::Auto {
            parts.pop();
        }
        let lists = match parts.last() {
            Some(&"slots") => ListFormat::Slots,
            Some(&"masks") => ListFormat::Masks,
            _ => ListFormat::Auto,
        };
        if lists != ListFormat::Auto {
            parts.pop();
        }
        let mut workgroup = Workgroup::W64;
        if let Some(threads) = parts.last().and_then(|w| w.strip_prefix("wg")) {
            workgroup =
                threads.parse().ok().and_then(Workgroup::of).filter(|w| *w != Workgroup::W64).ok_or_else(|| {
                    format!(
                        "GPU variant `{id}`: the workgroup size must be wg128 or wg256 (64, the default, is left out)"
                    )
                })?;
            parts.pop();
        }
        let (s, m, a, k, p) = match parts.as_slice() {
            [s, m, k, p] => (*s, *m, "none", *k, *p),
            [s, m, a, k, p] if *a != "none" => (*s, *m, *a, *k, *p),
            _ => return Err(bad()),
        };
        let spec = VariantSpec {
            search: SearchKind::parse(s).ok_or_else(bad)?,
            mapping: Mapping::parse(m).ok_or_else(bad)?,
            accumulation: Accumulation::parse(a).ok_or_else(bad)?,
            kernel_values: KernelValues::parse(k).ok_or_else(bad)?,
            precision: Precision::parse(p).ok_or_else(bad)?,
            workgroup,
            lists,
            slots,
        };
        if !spec.is_consistent() {
            if slots != SlotLayout::Auto && spec.kernel_values != KernelValues::Cached {
                return Err(format!(
                    "GPU variant `{id}`: a slot layout (.full or .pooled) belongs to the variants with cached kernel values"
                ));
            }
            if lists != ListFormat::Auto && !spec.list_format_matters() {
                return Err(format!(
                    "GPU variant `{id}`: a list format (.slots or .masks) belongs to every tracking variant \
                     and to the other searches with recomputed kernel values that keep lists (block and \
                     subgroup mappings)"
                ));
            }
            if workgroup != Workgroup::W64 {
                return Err(format!("GPU variant `{id}`: a workgroup size belongs to the thread mapping only"));
            }
            return Err(bad());
        }
        spec.meaningful()?;
        Ok(spec)
    }
}

#[cfg(test)]
mod tests;
