//! Slot lists beyond one binding: the explicit lists' slots (`nbr` with slot lists) and the
//! cached kernel values (`cache_wf`) hold 64 entries per particle (49 words in the pooled
//! layout, `gpu::pooled_lists`), so past a few million
//! particles one array no longer fits the adapter's per-binding limit (2 GiB holds 4,194,304
//! particles of f32 `cache_wf`). They are then split by particle into chunks that each fit (twin
//! of `ChunkRange` in kernels-variants/common/variant_bindings.wgsl): one buffer per chunk and
//! array, one group-1 bind group per chunk carrying the chunk's range, and the kernels that read
//! or write the slots ([`runs_per_chunk`]) dispatched once per chunk with their grid over the
//! chunk's particles; the block mappings' accumulator is split alike. Every other array stays
//! whole, so a pair term still reads any neighbour.
//! Whenever the slots fit, there is one chunk of every particle and nothing changes.

use super::mask_lists::uses_masks;
use super::pooled_lists::{SlotLayout, POOL_BLOCK, POOL_REGION};
use super::stages::KernelDef;
use super::variant::{Accumulation, KernelValues, SumLayout, VariantSpec};
use super::variant_buffers::NBR_SLOTS;

/// Chunks start at multiples of this many particles: a whole number of workgroups of every
/// mapping (256 threads, 32 block rows, 64 / G subgroup particles).
pub const CHUNK_ALIGN: usize = 256;

/// The arrays of `spec` that chunking splits, with their bytes per particle (`real` bytes per
/// real): `nbr` with slot lists (one u32 per slot), `cache_wf` with cached kernel values (a real
/// pair per slot), and with those the block mappings' accumulator (`accum`, 4 or, fixed point
/// with cached values, 8 words; the fixed point's high words `accum_hi`, 4 words, without), which
/// their per-chunk kernels address by the chunk's particles. None for mask lists or without
/// lists.
pub fn split_arrays(spec: &VariantSpec, real: usize) -> Vec<(&'static str, usize)> {
    let mut v = Vec::new();
    // Words per particle of the slot arrays: 64 slots, or a pooled region's share.
    let slots = if spec.slots == SlotLayout::Pooled { POOL_REGION / POOL_BLOCK } else { NBR_SLOTS };
    if spec.has_lists() && !uses_masks(spec) {
        v.push(("nbr", slots * 4));
    }
    let cached = spec.kernel_values == KernelValues::Cached;
    if cached {
        v.push(("cache_wf", slots * 2 * real));
    }
    if !v.is_empty() && spec.mapping.layout() == SumLayout::Block {
        let fixed = spec.accumulation == Accumulation::Fixed;
        v.push(("accum", if fixed && cached { 32 } else { 16 }));
        if fixed && !cached {
            v.push(("accum_hi", 16));
        }
    }
    v
}

/// Particles per chunk of `spec` for `n` particles under `cap` bytes per buffer: `n` (one chunk)
/// when every slot array fits, else the largest multiple of [`CHUNK_ALIGN`] whose arrays each
/// fit (at least [`CHUNK_ALIGN`]: a cap below 256 particles' slots is refused by the plan).
pub fn chunk_len(spec: &VariantSpec, n: usize, real: usize, cap: u64) -> usize {
    let widest = split_arrays(spec, real).iter().map(|a| a.1).max().unwrap_or(0) as u64;
    if widest == 0 || n as u64 * widest <= cap {
        return n.max(1);
    }
    ((cap / widest) as usize / CHUNK_ALIGN * CHUNK_ALIGN).max(CHUNK_ALIGN)
}

/// Particles whose slots a chunk of `len` particles allocates: `len`, or with pooled lists
/// its whole blocks (`gpu::pooled_lists`).
pub fn allocated_len(spec: &VariantSpec, len: usize) -> usize {
    if spec.slots == SlotLayout::Pooled {
        len.div_ceil(POOL_BLOCK).max(1) * POOL_BLOCK
    } else {
        len
    }
}

/// The chunks `(base, len)` of `n` particles at `len` per chunk (one of every particle when
/// `len ≥ n`).
pub fn chunks(n: usize, len: usize) -> Vec<(usize, usize)> {
    if len >= n {
        return vec![(0, n)];
    }
    (0..n).step_by(len.max(1)).map(|b| (b, len.min(n - b))).collect()
}

/// True when kernel `kd` reads or writes the split arrays, so it runs once per chunk: the list
/// build, the list-driven pair sums of the thread (`cached`), block and subgroup mappings, and
/// the block mappings' finalize kernels (which read the chunk's accumulator).
pub fn runs_per_chunk(kd: &KernelDef) -> bool {
    kd.entry == "nbr_build"
        || matches!(
            kd.file,
            "list/pair_sums.wgsl"
                | "block/atomic.wgsl"
                | "block/tree.wgsl"
                | "block/finalize.wgsl"
                | "subgroup/pair_sums.wgsl"
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_fit_the_cap_and_cover_every_particle_once() {
        let cached: VariantSpec = "cells.thread.cached.f32".parse().unwrap();
        // cache_wf: 64 slots × 8 B = 512 B per particle; nbr 256 B.
        assert_eq!(split_arrays(&cached, 4), vec![("nbr", 256), ("cache_wf", 512)]);
        let cap = 2u64 << 30;
        assert_eq!(chunk_len(&cached, 4_194_304, 4, cap), 4_194_304, "fits: one chunk");
        assert_eq!(chunk_len(&cached, 4_194_305, 4, cap), 4_194_304);
        let len = chunk_len(&cached, 100_000_000, 4, cap);
        assert!(len as u64 * 512 <= cap && len.is_multiple_of(CHUNK_ALIGN) && (len + CHUNK_ALIGN) as u64 * 512 > cap);
        let c = chunks(100_000_000, len);
        assert_eq!(c.len(), 24);
        assert_eq!(c[0], (0, len));
        assert!(c.windows(2).all(|w| w[0].0 + w[0].1 == w[1].0));
        assert_eq!(c.last().map(|l| l.0 + l.1), Some(100_000_000));
        assert_eq!(chunks(1000, 1000), vec![(0, 1000)]);
        assert_eq!(chunks(1000, 256), vec![(0, 256), (256, 256), (512, 256), (768, 232)]);
        // f64 halves the chunk; mask lists and variants without lists are never split.
        let f64c: VariantSpec = "cells.thread.cached.f64".parse().unwrap();
        assert_eq!(chunk_len(&f64c, 100_000_000, 8, cap), len / 2);
        let masks: VariantSpec = "cells.subgroup.recomputed.f32.masks".parse().unwrap();
        assert!(split_arrays(&masks, 4).is_empty());
        assert_eq!(chunk_len(&masks, 100_000_000, 4, 1 << 20), 100_000_000);
        let thread: VariantSpec = "cells.thread.recomputed.f32".parse().unwrap();
        assert!(split_arrays(&thread, 4).is_empty());
    }
}
