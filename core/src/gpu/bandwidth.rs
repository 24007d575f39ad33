//! What the engine says about its own memory traffic: the adapter's measured streaming
//! bandwidth ([`measure_bandwidth`]: a copy kernel timed with timestamp queries) and a
//! modelled count of the bytes one force evaluation moves ([`modelled_bytes_per_evaluation`]),
//! whose ratio to the measured time gives the fraction of the memory roofline.
//!
//! **Measured bandwidth.** `copy` reads one `vec4<u32>` and writes one per thread from one
//! buffer to another of the requested size ([`PROBE_BYTES`] for the study, far above any
//! last-level cache, so caches cannot inflate it; [`QUICK_PROBE_BYTES`] for a single run's
//! summary), capped by the adapter's buffer size; the buffers are bound in chunks of at most the
//! binding limit, one dispatch per chunk (over x and y like the solver's kernels), all in one
//! pass. One warm-up pass, then [`PROBE_REPEATS`] passes each bracketed by beginning/end-of-pass
//! timestamps; the best pass gives 2 × bytes / time (read + write). Only with
//! `TIMESTAMP_QUERY`: otherwise `None` (never estimated from wall time).
//!
//! **Modelled bytes per evaluation** (the compulsory traffic, a lower bound): every
//! per-particle array a kernel touches moves once per kernel (reads + writes, by
//! [`stage_bytes`]); neighbour data gathered through the cell iterator (`pos[j]`, `sigma[j]`, …)
//! is assumed to come from cache (counted zero); what is stored per pair moves per pair: list
//! entries (4 B per neighbour written by `nbr_build` and read by each pair-sum stage; the
//! bitmask lists of `gpu::mask_lists` move their mask words per particle instead), cached
//! kernel values and image positions (2 × real2 per neighbour, written once, read per
//! pair-sum stage) and the block accumulators (one atomic read-modify-write of 4 B — 8 B in
//! fixed point — per term and component, per row for block-tree, plus the clear and the
//! finalize read). The mean neighbour count is that of the lattice, k̄ = π (support/Δx)².
//! So the roofline fraction = modelled bytes / (measured time × measured bandwidth) is a lower
//! bound of the bandwidth a variant really uses.

use super::solver::spread;
use super::variant::{Accumulation, KernelValues, Mapping, SumLayout, VariantSpec};
use super::{GpuContext, GpuError};
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::stage::Stage;
use serde::Serialize;

/// Bytes of each probe buffer (before the binding cap).
pub const PROBE_BYTES: u64 = 1 << 30;
/// Bytes of each buffer of the quick probe behind `sphlab run`'s summary (above the last-level
/// cache of current GPUs, but not by much; its method string says the size).
pub const QUICK_PROBE_BYTES: u64 = 64 << 20;
/// Timed passes of the probe (the best counts).
pub const PROBE_REPEATS: u32 = 4;

const COPY_WGSL: &str = "
@group(0) @binding(0) var<storage, read> src: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read_write> dst: array<vec4<u32>>;
@compute @workgroup_size(64)
fn copy(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = gid.x + gid.y * nwg.x * 64u;
    if i < arrayLength(&dst) {
        dst[i] = src[i];
    }
}
";

/// The measured streaming bandwidth.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Bandwidth {
    /// Bytes read + written per pass / best pass time, in GB/s (10⁹ B/s).
    pub gb_per_s: f64,
    /// Bytes of each probe buffer.
    pub buffer_bytes: u64,
    /// Best pass, ns.
    pub best_ns: f64,
    /// How it was measured.
    pub method: String,
}

/// Share of a run's time budget the full-size probe may take; beyond it the probe shrinks.
pub const PROBE_BUDGET_SHARE: f64 = 0.05;

/// [`measure_bandwidth`] at up to `max_bytes` per buffer within `budget_s` seconds (`None`: no
/// limit, the full size at once). Under a budget the quick probe runs first; its rate gives
/// each size's cost (the buffers' first fill plus every pass, 2 × bytes each), and the largest
/// power-of-two halving of `max_bytes` whose cost fits [`PROBE_BUDGET_SHARE`] of the budget is
/// measured next — none above the quick size fitting, the quick probe's result stands. Its
/// `method` names the size it used.
pub fn measure_bandwidth_within(
    ctx: &GpuContext,
    max_bytes: u64,
    budget_s: Option<f64>,
) -> Result<Option<Bandwidth>, GpuError> {
    let Some(budget) = budget_s else { return measure_bandwidth(ctx, max_bytes) };
    let Some(quick) = measure_bandwidth(ctx, QUICK_PROBE_BYTES.min(max_bytes))? else { return Ok(None) };
    match probe_bytes_within(max_bytes, quick.gb_per_s, PROBE_BUDGET_SHARE * budget) {
        Some(bytes) if bytes > quick.buffer_bytes => measure_bandwidth(ctx, bytes),
        _ => Ok(Some(quick)),
    }
}

/// The largest `max_bytes >> k` (at least [`QUICK_PROBE_BYTES`]) whose probe — the buffers'
/// first fill and `PROBE_REPEATS + 1` passes, each moving 2 × bytes at `gb_per_s` — takes at
/// most `seconds`; `None` if not even the quick size does.
pub fn probe_bytes_within(max_bytes: u64, gb_per_s: f64, seconds: f64) -> Option<u64> {
    let cost = |b: u64| f64::from(PROBE_REPEATS + 2) * 2.0 * b as f64 / (gb_per_s * 1e9);
    let mut bytes = max_bytes;
    while bytes > 0 && bytes >= QUICK_PROBE_BYTES.min(max_bytes) {
        if cost(bytes) <= seconds {
            return Some(bytes);
        }
        bytes /= 2;
    }
    None
}

/// Times the copy kernel on `ctx` over two buffers of `bytes` each (capped by the adapter's
/// buffer size); `None` without `TIMESTAMP_QUERY`.
pub fn measure_bandwidth(ctx: &GpuContext, bytes: u64) -> Result<Option<Bandwidth>, GpuError> {
    if !ctx.has(wgpu::Features::TIMESTAMP_QUERY) {
        return Ok(None);
    }
    let align = u64::from(ctx.limits.min_storage_buffer_offset_alignment).max(16);
    let chunk = ctx.buffer_cap() / align * align;
    let bytes = bytes.min(ctx.limits.max_buffer_size) / 16 * 16;
    let pipeline = ctx.compute_pipeline("sphlab.bandwidth", COPY_WGSL, "copy")?;
    let buffer = |label| {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        })
    };
    let (src, dst) = (buffer("sphlab.bandwidth.src"), buffer("sphlab.bandwidth.dst"));
    // One bind group and grid per chunk of at most the binding limit.
    let mut chunks = Vec::new();
    let mut offset = 0;
    while offset < bytes {
        let size = chunk.min(bytes - offset);
        let part = |buffer| wgpu::BufferBinding { buffer, offset, size: std::num::NonZeroU64::new(size) };
        let bg = ctx.scoped(|d| {
            d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sphlab.bandwidth"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::Buffer(part(&src)) },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Buffer(part(&dst)) },
                ],
            })
        })?;
        chunks.push((bg, spread((size / 16).div_ceil(64) as usize, ctx.limits.max_compute_workgroups_per_dimension)));
        offset += size;
    }
    let best = super::timing::best_pass_ns(
        ctx,
        "sphlab.bandwidth",
        PROBE_REPEATS + 1,
        |pass| {
            pass.set_pipeline(&pipeline);
            for (bg, (gx, gy)) in &chunks {
                pass.set_bind_group(0, bg, &[]);
                pass.dispatch_workgroups(*gx, *gy, 1);
            }
        },
        |_| {},
    )?;
    let Some(best_ns) = best else { return Ok(None) };
    Ok(Some(Bandwidth {
        gb_per_s: 2.0 * bytes as f64 / best_ns,
        buffer_bytes: bytes,
        best_ns,
        method: format!(
            "copy kernel over 2 × {} (dispatches per pass: {}), best of {PROBE_REPEATS} timestamped passes (read + write)",
            crate::plan::fmt_bytes(bytes as f64),
            chunks.len()
        ),
    }))
}

/// Per-particle bytes (reads + writes) of the per-particle arrays of `stage`'s kernels, for
/// real size `r` (the per-pair traffic is added by [`modelled_bytes_per_evaluation`]); and the
/// particles it runs over: 0 all, 1 fluid, 2 wall.
pub fn stage_bytes(spec: &VariantSpec, stage: Stage, r: f64) -> (f64, u8) {
    let v = 2.0 * r;
    match stage {
        // cell_count (pos → cell_of, count RMW, the list slot kept: 20), then, in every
        // evaluation after a step, the merge (each kept slot and its cell_of read by the 3×3
        // cells around it: 72; the list written, then sorted: 12); tracking adds the
        // displacement check (pos, ref_pos). The cells search renumbers at every evaluation
        // (physical cell order): each particle's r, v, r⁰, v⁰, m, phase and orig_of read and
        // written into the twins, phase and orig_of (and the fluids' colour) copied back, three
        // vec2 twins cleared; tracking's renumbering every 16 steps is left out.
        Stage::NeighbourSearch => match spec.search {
            SearchKind::Direct if !spec.sorts_cells() => (0.0, 0),
            SearchKind::Direct => (v + 104.0, 0),
            SearchKind::Cells => (v + 104.0 + 2.0 * (4.0 * v + r + 8.0) + 24.0 + 3.0 * v, 0),
            SearchKind::Tracking => (3.0 * v + 104.0, 0),
        },
        // σ is stored with 1/σ² (a real2 record).
        Stage::NumberDensity => (2.0 * v + r, 0),
        // Every fluid particle's phase, and a liquid particle's position (counted for all); the
        // contact angles of the unbalanced Young force read only the points' windows.
        Stage::ContactLine => (v + 4.0, 1),
        Stage::WallTyping => (v + 4.0 + r, 2),
        Stage::EquationOfState => (v + 3.0 * r + 8.0, 0),
        Stage::WallPressure => (v + r, 2),
        Stage::ColourGradient => (v + 4.0 + v + 2.0 * v, 0),
        Stage::NormalCorrection => (4.0 + 2.0 * v, 0),
        Stage::SurfaceStress => (4.0 + 3.0 * v, 0),
        Stage::Acceleration => (5.0 * v + 3.0 * r + 4.0, 1),
        Stage::Xsph => (3.0 * v + 2.0 * r + 4.0, 1),
        _ => (0.0, 0),
    }
}

/// Components a pair-sum stage accumulates per particle (block layouts), `None` for the others.
fn pair_components(stage: Stage) -> Option<f64> {
    match stage {
        Stage::NumberDensity | Stage::Acceleration => Some(2.0),
        Stage::ColourGradient => Some(4.0),
        _ => None,
    }
}

/// Modelled bytes one force evaluation of `spec` moves (module doc) over `stages` (the active
/// evaluation stages, in order), for `n` particles of which `n_fluid` fluid, `support_over_dx`
/// = support / Δx.
pub fn modelled_bytes_per_evaluation(
    spec: &VariantSpec,
    stages: &[Stage],
    n: usize,
    n_fluid: usize,
    support_over_dx: f64,
) -> f64 {
    let r = if spec.precision == Precision::F64 { 8.0 } else { 4.0 };
    let k = std::f64::consts::PI * support_over_dx * support_over_dx;
    let (n, nf) = (n as f64, n_fluid as f64);
    let count = |over: u8| match over {
        1 => nf,
        2 => n - nf,
        _ => n,
    };
    let cached = spec.kernel_values == KernelValues::Cached;
    // A list entry (one word), with cached kernel values also (W, F′) (x_j is read from pos[j]).
    let per_pair_read = if spec.has_lists() { 4.0 + if cached { 2.0 * r } else { 0.0 } } else { 0.0 };
    // What one particle's list moves per write or read: its mask words, or k entries.
    let list = if spec.has_lists() && super::mask_lists::uses_masks(spec) {
        4.0 * super::mask_lists::nbr_bits(spec) as f64 / 32.0
    } else {
        k * per_pair_read
    };
    let atom = if spec.accumulation == Accumulation::Fixed { 8.0 } else { 4.0 };
    let mut bytes = 0.0;
    for &s in stages {
        let (b, over) = stage_bytes(spec, s, r);
        bytes += b * count(over);
        if s == Stage::NeighbourSearch && spec.has_lists() {
            bytes += n * (4.0 + list);
        }
        let Some(comps) = pair_components(s) else { continue };
        let over = if s == Stage::Acceleration { nf } else { n };
        bytes += over * list;
        if spec.mapping.layout() == SumLayout::Block {
            let terms = if spec.mapping == Mapping::BlockTree { 4.0 } else { k };
            // RMW per term and component, then the clear (8 words) and the finalize read.
            bytes += n * (terms * comps * 2.0 * atom + 32.0 + comps * atom);
        }
    }
    bytes
}

/// The engine's traffic figures for one run (`sphlab run --backend gpu`'s summary, the study).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct EngineTraffic {
    /// Variant id.
    pub variant: String,
    /// Bytes of the device buffers (the memory plan's total, which equals what the solver
    /// allocates: `tests/gpu_variants.rs`).
    pub device_bytes: u64,
    /// [`modelled_bytes_per_evaluation`].
    pub modelled_bytes_per_evaluation: f64,
    /// Force evaluations per step (2 for the midpoint integrator, 1 for Verlet).
    pub evaluations_per_step: f64,
    /// The measured streaming bandwidth (`None` without timestamps).
    pub bandwidth: Option<Bandwidth>,
    /// Modelled bytes per step / (time per step × bandwidth), once a time is known.
    pub roofline_fraction: Option<f64>,
}

impl EngineTraffic {
    /// The figures of `spec` on `scene` with `n` particles (`n_fluid` fluid).
    pub fn new(
        spec: &VariantSpec,
        scene: &crate::scene::Scene,
        n: usize,
        n_fluid: usize,
        device_bytes: u64,
        bandwidth: Option<Bandwidth>,
    ) -> Self {
        let m = crate::model::Model::<f64>::new(scene);
        let stages = m.stages.evaluation();
        let bytes = modelled_bytes_per_evaluation(spec, &stages, n, n_fluid, m.support() / m.dx);
        let evals = if scene.time.integrator == crate::scene::Integrator::Midpoint { 2.0 } else { 1.0 };
        EngineTraffic {
            variant: spec.to_string(),
            device_bytes,
            modelled_bytes_per_evaluation: bytes,
            evaluations_per_step: evals,
            bandwidth,
            roofline_fraction: None,
        }
    }

    /// Fraction of the memory roofline at `seconds_per_step` (`None` without a bandwidth).
    pub fn fraction(&self, seconds_per_step: f64) -> Option<f64> {
        let bw = self.bandwidth.as_ref()?.gb_per_s * 1e9;
        (seconds_per_step > 0.0)
            .then(|| self.modelled_bytes_per_evaluation * self.evaluations_per_step / (seconds_per_step * bw))
    }

    /// One line for people.
    pub fn describe(&self) -> String {
        let bw = match &self.bandwidth {
            Some(b) => format!("measured streaming bandwidth {:.2} GB/s", b.gb_per_s),
            None => "no bandwidth (the adapter has no timestamps)".into(),
        };
        let frac =
            self.roofline_fraction.map_or(String::new(), |f| format!(" → {:.2} % of the memory roofline", 100.0 * f));
        format!(
            "{}: device buffers {}, modelled {} per evaluation × {} per step, {bw}{frac}",
            self.variant,
            crate::plan::fmt_bytes(self.device_bytes as f64),
            crate::plan::fmt_bytes(self.modelled_bytes_per_evaluation),
            self.evaluations_per_step
        )
    }
}
