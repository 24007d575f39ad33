//! The GPU memory plan of one variant, computed before any device buffer exists: every buffer
//! the solver allocates (twins of `Bufs::new` in `gpu/solver_buffers.rs` and `VBufs::new` in
//! `gpu/variant_buffers.rs`, element counts × element sizes, each at least 4 bytes and a
//! multiple of 4 as `GpuVec` allocates; a test holds the total equal to what a solver really
//! allocates), compared with what the device offers:
//! * every buffer is bound whole, so each must fit `max_storage_buffer_binding_size` and
//!   `max_buffer_size` (the smaller is the cap). Nothing holds more than two words or one vec2
//!   per particle (the step's start state r⁰, v⁰ and the two colour-gradient slots are one
//!   binding each), so the per-particle vec2 arrays (`pos`, …) and `counts` reach the cap first:
//!   8 B × N in f32 on lavapipe's 128 MiB, N ≤ 16,777,216 (the 2N-element `state0` and `grad`
//!   they replace stopped at 8,388,608);
//! * the sum must fit the device memory. wgpu has no query for it, so it comes from
//!   `--gpu-memory`, else, on a CPU adapter (lavapipe: device memory is host memory), from
//!   `MemAvailable`, else it is unknown and only the per-buffer caps are checked
//!   ([`DeviceLimits::memory_source`] says which);
//! * the dispatch grid: a kernel over N threads needs ⌈N/64⌉ ≤ max_groups² workgroups (x·y).
//!
//! What does not fit is refused (exit 2 at the command line, `GpuError::TooLarge` in the
//! solver) naming the buffer, the bytes needed and the bytes available. Timestamp query
//! buffers (only while stage timing is on) and the bandwidth probe's buffers are not counted.

use crate::gpu::mask_lists::list_words;
use crate::gpu::variant::{KernelValues, ListFormat, SlotLayout, VariantSpec};
use crate::gpu::variant_buffers::{binding4_name, vctl};
use crate::gpu::GpuContext;
use crate::model::{CONTACT_WORDS, MAX_CONTACTS};
use crate::neighbours::SearchKind;
use crate::plan::fmt_bytes;
use serde::Serialize;

/// Cells per workgroup of the parallel cell scan (`search/cell_scan.wgsl`); the per-block sums
/// live after the counts in `cell_count`.
pub const SCAN_BLOCK: usize = 256;

/// The largest grid whose cell scan the last workgroup of the integrator stage runs (the
/// stage table's `cell_scan` epilogue: one workgroup walks every cell, so beyond this the scan
/// is the search's own dispatch, spread over the blocks).
pub const FUSED_SCAN_CELLS: usize = 4096;

/// Blocks of the parallel cell scan for `cells` cells.
pub fn scan_blocks(cells: usize) -> usize {
    cells.div_ceil(SCAN_BLOCK)
}

/// Words of the solver's control buffer (`ctl::LEN` of `gpu/solver_buffers.rs`).
const CTL_WORDS: f64 = crate::gpu::solver_buffers::ctl::LEN as f64;
/// Entries of `vparams` (`VBufs::new`).
const VPARAMS: f64 = crate::gpu::variant_buffers::vparam::LEN as f64;

/// What the device offers.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct DeviceLimits {
    /// `max_buffer_size`.
    pub max_buffer_size: u64,
    /// `max_storage_buffer_binding_size`.
    pub max_binding_size: u64,
    /// `max_compute_workgroups_per_dimension`.
    pub max_groups_per_dim: u32,
    /// Device memory in bytes, when known.
    pub memory: Option<u64>,
    /// Where `memory` came from.
    pub memory_source: String,
}

impl DeviceLimits {
    /// The limits granted to `ctx`'s device; `gpu_memory` (`--gpu-memory`) overrides the
    /// memory heuristic (host `MemAvailable` on a CPU adapter, unknown elsewhere).
    pub fn of(ctx: &GpuContext, gpu_memory: Option<u64>) -> Self {
        let (memory, memory_source) = match gpu_memory {
            Some(m) => (Some(m), "--gpu-memory".to_string()),
            None if ctx.adapter_info.device_type == wgpu::DeviceType::Cpu => match crate::plan::available_memory() {
                Some(m) => (Some(m), "host MemAvailable (CPU adapter: device memory is host memory)".into()),
                None => (None, "unknown (CPU adapter without /proc/meminfo; pass --gpu-memory)".into()),
            },
            None => (None, "unknown (wgpu has no device-memory query; pass --gpu-memory)".into()),
        };
        DeviceLimits {
            max_buffer_size: ctx.limits.max_buffer_size,
            max_binding_size: ctx.limits.max_storage_buffer_binding_size,
            max_groups_per_dim: ctx.limits.max_compute_workgroups_per_dimension,
            memory,
            memory_source,
        }
    }

    /// A stated adapter for the plan tables: `memory` bytes of device memory, every buffer
    /// (binding and allocation) capped at `binding` bytes, 65,535 workgroups per dimension.
    pub fn stated(memory: u64, binding: u64, what: &str) -> Self {
        DeviceLimits {
            max_buffer_size: binding,
            max_binding_size: binding,
            max_groups_per_dim: 65535,
            memory: Some(memory),
            memory_source: what.to_string(),
        }
    }

    /// The per-buffer cap: the smaller of the binding and buffer limits.
    pub fn buffer_cap(&self) -> u64 {
        self.max_binding_size.min(self.max_buffer_size)
    }
}

/// One device buffer of the plan.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BufferPlan {
    /// Buffer name (the label without `sphlab.`).
    pub name: &'static str,
    /// Bytes allocated.
    pub bytes: u64,
}

/// The device buffers of one variant for `n` particles on `cells` cells.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct GpuPlan {
    /// Variant id.
    pub variant: String,
    /// Particles (fluid + wall).
    pub n: u64,
    /// Cells of the search grid.
    pub cells: u64,
    /// Every buffer, in allocation order.
    pub buffers: Vec<BufferPlan>,
    /// Sum of the buffers (and the parameter uniform).
    pub total_bytes: u64,
    /// The variant as planned (its list format may still be `Auto`: [`GpuPlan::check`]
    /// resolves it against the limits).
    #[serde(skip)]
    pub spec: VariantSpec,
}

/// `spec` with its list format resolved for `n` particles on `cells` cells under `lim`: the one
/// place the format is chosen. A forced format, or a variant without the choice, is kept; else
/// [`ListFormat::Slots`] (one index per entry, the fast lists) while every buffer of the slot
/// plan fits the adapter's per-buffer cap and the dispatch grid fits, [`ListFormat::Masks`]
/// beyond (a few words per particle; device memory in all is checked on the result). With
/// cached kernel values (tracking: only the candidates have masks) the list slots and the cache
/// count as split into list chunks in either format.
///
/// Then the slot layout of the cached variants (`gpu::pooled_lists`): full (64 slots per
/// particle) while that plan fits `lim` in every check, device memory included; pooled beyond.
pub fn resolve_lists(spec: &VariantSpec, n: u64, cells: u64, lim: &DeviceLimits) -> VariantSpec {
    let spec = resolve_format(spec, n, cells, lim);
    if spec.slots != SlotLayout::Auto || spec.kernel_values != KernelValues::Cached {
        return spec;
    }
    let full = VariantSpec { slots: SlotLayout::Full, ..spec };
    if GpuPlan::new(&full, n, cells).check(lim).is_ok() {
        full
    } else {
        VariantSpec { slots: SlotLayout::Pooled, ..spec }
    }
}

/// The list format of [`resolve_lists`].
fn resolve_format(spec: &VariantSpec, n: u64, cells: u64, lim: &DeviceLimits) -> VariantSpec {
    if spec.lists != ListFormat::Auto || !spec.list_format_matters() {
        return *spec;
    }
    // Cached values are split into list chunks in either format: then only the candidates
    // choose (the slot layout, chosen next, changes no candidate buffer).
    let cached = spec.kernel_values == KernelValues::Cached;
    let layout = if cached && spec.slots == SlotLayout::Auto { SlotLayout::Full } else { spec.slots };
    let slots = VariantSpec { lists: ListFormat::Slots, slots: layout, ..*spec };
    let per_buffer = DeviceLimits { memory: None, ..lim.clone() };
    if GpuPlan::new(&slots, n, cells).check_in(&per_buffer, cached).is_ok() {
        slots
    } else {
        VariantSpec { lists: ListFormat::Masks, ..*spec }
    }
}

/// Bytes `GpuVec` allocates for `len` elements of `size` bytes (at least 4, a multiple of 4).
fn alloc(len: u64, size: u64) -> u64 {
    (len * size).max(4).next_multiple_of(4)
}

impl GpuPlan {
    /// The plan of `spec` for `n` particles on `cells` grid cells: exactly the bytes
    /// `GpuSolver::new` allocates (tested).
    pub fn new(spec: &VariantSpec, n: u64, cells: u64) -> Self {
        let r = spec.precision.bytes() as u64;
        let v2 = 2 * r;
        let tracking = spec.search == SearchKind::Tracking;
        let on = |b: bool, len: u64| if b { len } else { 1 };
        let w = list_words(spec, n as usize, cells as usize, r as usize);
        let b4 = binding4_name(spec);
        let blocks = scan_blocks(cells as usize) as u64;
        let params = (if r == 8 {
            size_of::<crate::gpu::params::Params<f64>>()
        } else {
            size_of::<crate::gpu::params::Params<f32>>()
        } as u64)
            .max(16)
            .next_multiple_of(16);
        let reorder = crate::gpu::reorder::len(tracking || spec.search == SearchKind::Cells, n as usize);
        let list: [(&'static str, u64, u64); 33] = [
            ("pos", n, v2),
            ("vel", n, v2),
            ("phase", n, 4),
            ("pos0", n, v2),
            ("vel0", n, v2),
            ("sigma", n, v2),
            ("chi", n, r),
            ("mass", n, r),
            ("colour", n, 4),
            ("rho", n, r),
            ("p", n, r),
            ("grad0", n, v2),
            ("grad1", n, v2),
            ("pi", n, v2),
            ("acc", n, v2),
            ("vt", n, v2),
            ("contacts", (CONTACT_WORDS * MAX_CONTACTS) as u64, r),
            ("ctl", CTL_WORDS as u64, 4),
            ("cell_count", cells + blocks, 4),
            ("cell_start", 3 * (cells + 1), 4),
            ("sorted", 2 * n, 4),
            ("cell_of", n, 4),
            ("vctl", vctl::LEN as u64, 4),
            ("vparams", VPARAMS as u64, r),
            ("counts", 2 * n.max(1), 4),
            ("nbr", w.nbr as u64, 4),
            (b4, w.b4 as u64, 4),
            ("cand_hi", w.b5 as u64, 4),
            ("cand", w.cand as u64, 4),
            ("ref_pos", on(tracking, n), v2),
            ("accum", w.accum as u64, 4),
            ("params", 1, params),
            // Cell ordering (gpu::reorder): control words, and for the cells and tracking
            // searches the permutation (the renumbering's scratch is arrays above:
            // `GpuSolver::record_renumbered`).
            ("reorder", reorder as u64, 4),
        ];
        let buffers: Vec<BufferPlan> =
            list.iter().map(|&(name, len, size)| BufferPlan { name, bytes: alloc(len, size) }).collect();
        let total_bytes = buffers.iter().map(|b| b.bytes).sum();
        GpuPlan { variant: spec.to_string(), n, cells, buffers, total_bytes, spec: *spec }
    }

    /// The plan of [`resolve_lists`]'s choice under `lim` (the variant as the solver runs it).
    pub fn resolved(spec: &VariantSpec, n: u64, cells: u64, lim: &DeviceLimits) -> Self {
        GpuPlan::new(&resolve_lists(spec, n, cells, lim), n, cells)
    }

    /// Bytes per particle of buffer `b` when it is a per-slot array that list chunks split
    /// (`gpu::list_chunks`), else `None`.
    fn split_bytes(&self, b: &BufferPlan) -> Option<u64> {
        crate::gpu::list_chunks::split_arrays(&self.spec, self.spec.precision.bytes())
            .iter()
            .find(|a| a.0 == b.name)
            .map(|a| a.1 as u64)
    }

    /// Particles per list chunk under the per-buffer `cap` (`n`: one chunk).
    fn chunk_len(&self, cap: u64) -> u64 {
        crate::gpu::list_chunks::chunk_len(&self.spec, self.n as usize, self.spec.precision.bytes(), cap) as u64
    }

    /// List chunks under the per-buffer `cap` (1 unless the slot arrays pass it).
    pub fn list_chunks(&self, cap: u64) -> u64 {
        self.n.max(1).div_ceil(self.chunk_len(cap))
    }

    /// The bytes of the largest single buffer `b` allocates under `cap` (a chunk's for the
    /// split slot arrays).
    pub fn allocated(&self, b: &BufferPlan, cap: u64) -> u64 {
        match self.split_bytes(b) {
            Some(per) => {
                let len = self.chunk_len(cap).min(self.n) as usize;
                alloc(crate::gpu::list_chunks::allocated_len(&self.spec, len) as u64, per)
            }
            None => b.bytes,
        }
    }

    /// The largest single buffer under `cap`: name and bytes.
    pub fn largest(&self, cap: u64) -> (&'static str, u64) {
        self.buffers.iter().map(|b| (b.name, self.allocated(b, cap))).max_by_key(|b| b.1).expect("buffers")
    }

    /// Ok when every buffer (each list chunk of the split slot arrays), the total and the
    /// dispatch grid fit `lim`; else the first that does not, naming the buffer, the bytes
    /// needed and the bytes available.
    pub fn check(&self, lim: &DeviceLimits) -> Result<(), String> {
        self.check_in(lim, true)
    }

    /// [`Self::check`], with the slot arrays whole unless `chunking` (the list format's choice
    /// keeps slots only while they fit whole: [`resolve_lists`]).
    fn check_in(&self, lim: &DeviceLimits, chunking: bool) -> Result<(), String> {
        let auto_slots = self.spec.slots == SlotLayout::Auto && self.spec.kernel_values == KernelValues::Cached;
        if auto_slots || (self.spec.lists == ListFormat::Auto && self.spec.list_format_matters()) {
            return GpuPlan::resolved(&self.spec, self.n, self.cells, lim).check_in(lim, chunking);
        }
        let head = format!("GPU memory plan of {} for {} particles", self.variant, self.n);
        let cap = lim.buffer_cap();
        let bytes = |b: &BufferPlan| if chunking { self.allocated(b, cap) } else { b.bytes };
        if let Some(b) = self.buffers.iter().find(|b| bytes(b) > cap) {
            let which = if lim.max_binding_size <= lim.max_buffer_size {
                "max_storage_buffer_binding_size"
            } else {
                "max_buffer_size"
            };
            let note = match self.split_bytes(b) {
                Some(per) if chunking => format!(
                    " ({per} B of list slots per particle in chunks of at least {} particles)",
                    crate::gpu::list_chunks::CHUNK_ALIGN
                ),
                _ => String::new(),
            };
            return Err(format!(
                "{head}: buffer `{}` needs {} bytes ({}), over the adapter's {which} of {} bytes ({}){note}; \
                 lower domain.nx or choose a variant with smaller buffers (sphlab variants --memory N)",
                b.name,
                bytes(b),
                fmt_bytes(bytes(b) as f64),
                cap,
                fmt_bytes(cap as f64),
            ));
        }
        if let Some(m) = lim.memory {
            if self.total_bytes > m {
                let (name, big) = self.largest(cap);
                return Err(format!(
                    "{head}: the device buffers need {} bytes ({}) in all, over the {} bytes ({}) of device \
                     memory ({}); the largest is `{name}` ({})",
                    self.total_bytes,
                    fmt_bytes(self.total_bytes as f64),
                    m,
                    fmt_bytes(m as f64),
                    lim.memory_source,
                    fmt_bytes(big as f64)
                ));
            }
        }
        let g = lim.max_groups_per_dim.max(1) as u64;
        let need = self.n.div_ceil(32).max(self.cells.div_ceil(64));
        if need > g * g {
            return Err(format!(
                "{head}: a kernel needs {need} workgroups, over the {} (x · y) the adapter's \
                 max_compute_workgroups_per_dimension of {g} allows",
                g * g
            ));
        }
        Ok(())
    }
}

/// Loop iterations lavapipe allows one invocation group in all, over every loop of a shader
/// (Mesa gallivm's `LP_MAX_TGSI_LOOP_ITERATIONS`); past it every loop exits silently.
pub const LAVAPIPE_LOOP_ITERATIONS: u64 = 65_535;

/// Candidates the direct search tests per loop iteration (`DIRECT_CHUNK` in
/// kernels-variants/common/neighbours.wgsl).
pub const DIRECT_CHUNK: u64 = 8;

/// Loop iterations that locate one neighbour of the direct search on the masks' walk: the
/// slots of its cell (lattice cells of about a support hold ~13 particles) and the walk's spans
/// (9 codes × 3 rows), with margin.
const MASK_LOOKUP: u64 = 64;

/// Invocations lavapipe runs in lockstep (256-bit vectors of 32-bit lanes).
const LAVAPIPE_LANES: u64 = 8;

/// Ok unless `spec` is a direct search on lavapipe (`driver` names llvmpipe) whose loops could
/// pass its per-group iteration cap: each invocation scans `codes · n` candidates,
/// `DIRECT_CHUNK` per iteration, plus two iterations per neighbour (up to 64); lanes of a group
/// that find neighbours at different candidates iterate apart, so the bound takes the group's
/// worst case, every lane apart. Measured: a one-candidate loop lost neighbours from
/// 2,304 particles (4 codes) on; the chunked loop is exact at 11,664 (this bound: 16,126).
pub fn direct_loop_check(spec: &VariantSpec, n: u64, codes: u64, driver: &str) -> Result<(), String> {
    if spec.search != SearchKind::Direct || !driver.to_ascii_lowercase().contains("llvmpipe") {
        return Ok(());
    }
    // With mask lists, each of up to 64 neighbours is then located in its cell and on the walk
    // (`direct_ordinal`, search/nbr_list.wgsl): at most MASK_LOOKUP more iterations each.
    let lookup = if crate::gpu::mask_lists::uses_masks(spec) { MASK_LOOKUP } else { 0 };
    let per_lane = (codes * n).div_ceil(DIRECT_CHUNK) + (2 + lookup) * 64;
    let worst = LAVAPIPE_LANES * per_lane;
    if worst > LAVAPIPE_LOOP_ITERATIONS {
        let max_n = (LAVAPIPE_LOOP_ITERATIONS / LAVAPIPE_LANES - (2 + lookup) * 64) * DIRECT_CHUNK / codes.max(1);
        return Err(format!(
            "{spec} on lavapipe: the direct search scans {codes} image codes × {n} particles per thread; \
             lavapipe ends every loop after {LAVAPIPE_LOOP_ITERATIONS} iterations per invocation group \
             (Mesa's LP_MAX_TGSI_LOOP_ITERATIONS), silently, which would drop neighbours (worst case \
             {worst} iterations); direct runs there up to {max_n} particles with {codes} codes; use a \
             cells or tracking variant"
        ));
    }
    Ok(())
}

/// Bytes per particle of `spec` (the buffers' growth per particle, cells at `cells_per_particle`).
pub fn bytes_per_particle(spec: &VariantSpec, cells_per_particle: f64) -> f64 {
    let n = 1u64 << 20;
    let (a, b) = (GpuPlan::new(spec, n, (n as f64 * cells_per_particle) as u64), GpuPlan::new(spec, 0, 0));
    (a.total_bytes - b.total_bytes) as f64 / n as f64
}

/// The largest N that `spec` can run within `lim` (cells at `cells_per_particle` per particle),
/// also within `max_particles` (the 28-bit index of the packed lists).
pub fn max_particles(spec: &VariantSpec, cells_per_particle: f64, lim: &DeviceLimits, max_particles: u64) -> u64 {
    let fits = |n: u64| GpuPlan::new(spec, n, (n as f64 * cells_per_particle).ceil() as u64).check(lim).is_ok();
    if !fits(1) {
        return 0;
    }
    let (mut lo, mut hi) = (1u64, max_particles);
    if fits(hi) {
        return hi;
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[cfg(test)]
mod tests;
