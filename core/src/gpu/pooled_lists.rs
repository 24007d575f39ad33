//! Pooled slot lists for the cached kernel values (twin of `POOLED_LISTS` in
//! kernels-variants/common/variant_bindings.wgsl and `nbr_build` in search/nbr_list.wgsl).
//!
//! The full layout gives every particle its 64 slots (the thesis's §6.4.1 bound, 4 blocks of
//! 16 threads), although a particle of the quintic at h = 1.2Δx has 37 neighbours on the
//! lattice and about 41 (π·3.6²) disordered. A cached variant keeps two arrays of those slots
//! (`nbr`, `cache_wf`), so past a few 10⁷ particles the empty slots decide whether it fits the
//! device. The pooled layout keeps the per-particle bound of 64 but shares room: particles in
//! blocks of [`POOL_BLOCK`] (aligned with every list chunk and workgroup) hold [`POOL_MEAN`]
//! entries per particle on average.
//! A block's region of `nbr` starts with one word per particle, the particle's first entry
//! (relative to the region), its entries follow those of the block's earlier particles, and
//! `cache_wf` holds each entry's kernel values at the same index. `nbr_build` walks twice (counts,
//! then entries after a workgroup prefix sum of the counts). A block that needs more than its
//! room is an overflow the host reports, never a silent cut.
//!
//! A cached variant takes the pooled layout when the full one does not fit the device
//! (`gpu::plan::resolve_lists`) or when its id says `.pooled`.

/// Particles per block of the pooled layout (a divisor of every workgroup size and of
/// `list_chunks::CHUNK_ALIGN`).
pub const POOL_BLOCK: usize = 64;

// Blocks align with the smallest workgroup (64 threads) and every list chunk.
const _: () =
    assert!(64usize.is_multiple_of(POOL_BLOCK) && crate::gpu::list_chunks::CHUNK_ALIGN.is_multiple_of(POOL_BLOCK));

/// Entries per particle a block holds on average (three quarters of the 64 slots; a block
/// holds 37 on the lattice of the quintic at h = 1.2Δx, about 41 disordered).
pub const POOL_MEAN: usize = 48;

/// Words of one block's region: its header (one word per particle) and its entries.
pub const POOL_REGION: usize = POOL_BLOCK * (1 + POOL_MEAN);

/// Slot layout of the explicit lists of a variant with cached kernel values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SlotLayout {
    /// Chosen by the memory plan: full while the variant fits the device, pooled beyond.
    Auto,
    /// 64 slots for every particle (`.full`).
    Full,
    /// Blocks of 64 particles sharing 48 entries per particle (`.pooled`).
    Pooled,
}

impl SlotLayout {
    /// The id suffix (`None` for `Auto`).
    pub fn suffix(self) -> Option<&'static str> {
        match self {
            SlotLayout::Auto => None,
            SlotLayout::Full => Some("full"),
            SlotLayout::Pooled => Some("pooled"),
        }
    }

    /// The layout of an id suffix.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "full" => Some(SlotLayout::Full),
            "pooled" => Some(SlotLayout::Pooled),
            _ => None,
        }
    }
}

/// Words of the pooled `nbr` array (and entries of `cache_wf`) for `len` particles: one region
/// per block, the last block's whole.
pub fn pooled_words(len: usize) -> usize {
    len.div_ceil(POOL_BLOCK).max(1) * POOL_REGION
}

/// The index of entry `k` of particle `l` of a chunk (`l` counted from the chunk's base) in the
/// pooled `nbr` array `nbr` of that chunk (twin of `nbr_slot` with `POOLED_LISTS`).
pub fn pooled_slot(nbr: &[u32], l: usize, k: usize) -> usize {
    let region = l / POOL_BLOCK * POOL_REGION;
    region + nbr[region + l % POOL_BLOCK] as usize + k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_hold_a_header_and_the_mean_entries() {
        assert_eq!(pooled_words(0), POOL_REGION);
        assert_eq!(pooled_words(64), POOL_REGION);
        assert_eq!(pooled_words(65), 2 * POOL_REGION);
        // Two blocks: particle 65's entries start after block 1's header and particle 64's 3.
        let mut nbr = vec![0u32; pooled_words(128)];
        nbr[POOL_REGION] = POOL_BLOCK as u32;
        nbr[POOL_REGION + 1] = POOL_BLOCK as u32 + 3;
        assert_eq!(pooled_slot(&nbr, 64, 0), POOL_REGION + POOL_BLOCK);
        assert_eq!(pooled_slot(&nbr, 65, 2), POOL_REGION + POOL_BLOCK + 5);
        for s in ["full", "pooled"] {
            assert_eq!(SlotLayout::parse(s).and_then(SlotLayout::suffix), Some(s));
        }
    }
}
