//! The compact neighbour and tracking lists of the cells and tracking searches with recomputed
//! kernel values (twin of `kernels-variants/common/mask_lists.wgsl`, which says the format):
//! bitmasks over a walk of cell-sorted spans instead of one index per entry. Here: the word
//! counts (twins of the WGSL constants), the buffer sizes of every variant's list storage
//! ([`list_words`], shared by `VBufs::new` and the memory plan), and the host's decoder of the
//! masks into packed lists ([`decode`], for the exact comparison with the CPU lists).

use super::pooled_lists::{pooled_words, SlotLayout};
use super::variant::{Accumulation, KernelValues, ListFormat, SumLayout, VariantSpec};
use super::variant_buffers::{CAND_SLOTS, NBR_SLOTS};
use crate::model::Images;
use crate::neighbours::cells::CellBox;
use crate::neighbours::{SearchKind, IMAGE_SHIFT};
use crate::real::{Real, V2};

/// Mask words of a list over the 3 × 3 cells (half in `nbr`, half in `cand`).
pub const NBR_WORDS_CELLS: usize = 6;
/// Mask words of a list over the tracking candidates (in `nbr`).
pub const NBR_WORDS_TRACK: usize = 5;
/// Mask words of the tracking candidates.
pub const CAND_WORDS: usize = 9;
/// Of which in `cand` (the rest in binding 5).
pub const CAND_LO_WORDS: usize = 4;

/// True when `spec` keeps its explicit lists (and, tracking, its candidates) as bitmasks (the
/// `MASK_LISTS` define): its list format is [`ListFormat::Masks`] and its kernel values are
/// recomputed (cached values are stored per list slot, so a cached tracking variant's masks are
/// its candidates' alone: [`cand_masks`]). The direct search has no cell order of its own: with
/// masks it runs the cells search's counting sort for the lists' storage alone and keeps its
/// all-pairs search. An unresolved [`ListFormat::Auto`] counts as slots: the solver resolves it
/// by N first (`gpu::plan::resolve_lists`).
pub fn uses_masks(spec: &VariantSpec) -> bool {
    spec.lists == ListFormat::Masks && spec.list_format_matters() && spec.kernel_values == KernelValues::Recomputed
}

/// True when `spec` keeps its tracking candidates as bitmasks over the build's walk (the
/// `MASK_CANDS` define): a tracking variant whose list format is [`ListFormat::Masks`].
pub fn cand_masks(spec: &VariantSpec) -> bool {
    spec.search == SearchKind::Tracking && spec.lists == ListFormat::Masks
}

/// Mask bits of a list (the most walk or candidate ordinals it can hold).
pub fn nbr_bits(spec: &VariantSpec) -> usize {
    32 * if spec.search == SearchKind::Tracking { NBR_WORDS_TRACK } else { NBR_WORDS_CELLS }
}

/// 32-bit words of the list-format buffers of group 1 for `n` particles on `cells` cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ListWords {
    /// Binding 3: explicit lists (slots or mask words).
    pub nbr: usize,
    /// Binding 4: cached (W, F′) per slot, or the high words of a fixed-point accumulation.
    pub b4: usize,
    /// Binding 5: the tracking mask's upper words.
    pub b5: usize,
    /// Binding 6: tracking candidates (slots, or mask words and the build's sort), or the
    /// second half of a cells list mask.
    pub cand: usize,
    /// Binding 8: the block accumulator.
    pub accum: usize,
}

/// The words of each list-format buffer of `spec` (1: a stand-in), `real` bytes per real.
pub fn list_words(spec: &VariantSpec, n: usize, cells: usize, real: usize) -> ListWords {
    let lists = spec.has_lists();
    let tracking = spec.search == SearchKind::Tracking;
    let cached = spec.kernel_values == KernelValues::Cached;
    let masks = uses_masks(spec);
    let cands = cand_masks(spec);
    let block = spec.mapping.layout() == SumLayout::Block;
    let on = |b: bool, len: usize| if b { len } else { 1 };
    // Slots per list: 64 for every particle, or the pooled layout's regions.
    let slots = if spec.slots == SlotLayout::Pooled { pooled_words(n) } else { n * NBR_SLOTS };
    let slot_v2 = slots * 2 * real / 4;
    let nbr = match (lists, masks, tracking) {
        (false, _, _) => 1,
        (true, false, _) => slots,
        (true, true, true) => n * NBR_WORDS_TRACK,
        (true, true, false) => n * NBR_WORDS_CELLS / 2,
    };
    let cand = match (tracking, cands) {
        (true, true) => (CAND_LO_WORDS + 1) * n + cells + 1,
        (true, false) => n * CAND_SLOTS,
        (false, _) => on(lists && masks, n * NBR_WORDS_CELLS / 2),
    };
    let fixed = spec.accumulation == Accumulation::Fixed;
    ListWords {
        nbr,
        b4: if cached { slot_v2 } else { on(block && fixed, 4 * n) },
        b5: on(cands, (CAND_WORDS - CAND_LO_WORDS) * n),
        cand,
        accum: on(block, if fixed && cached { 8 * n } else { 4 * n }),
    }
}

/// The non-empty spans `(code, s0, s1)` of the walk of the `w` × `w` box around `xi`, each row
/// its fluid span over `start` then its wall span over `walls` (twin of `walk_next`).
fn walk<T: Real>(
    grid: &CellBox<T>,
    images: &Images<T>,
    xi: V2<T>,
    w: i64,
    (start, walls): (&[u32], &[u32]),
) -> Vec<(u32, u32, u32)> {
    let (nx, ny) = (grid.nx as i64, grid.ny as i64);
    let mut spans = Vec::new();
    for code in images.codes() {
        let q = images.inverse_pos(code, xi);
        let f = [(q.x - grid.origin.x) * grid.inv_cell, (q.y - grid.origin.y) * grid.inv_cell];
        let c: Vec<i64> = f
            .iter()
            .zip([nx, ny])
            .map(|(f, len)| {
                let cell = (f.f64().floor() as i64).clamp(-2, len + 1);
                if w == 3 {
                    cell - 1
                } else {
                    let half = ((*f * T::c(2.0)).f64().floor() as i64 - 2 * f.f64().floor() as i64).clamp(0, 1);
                    cell - 2 + half
                }
            })
            .collect();
        for row in 0..w {
            let y = c[1] + row;
            let (x0, x1) = (c[0].max(0), (c[0] + w - 1).min(nx - 1));
            if y < 0 || y >= ny || x0 > x1 {
                continue;
            }
            let r = (nx * y) as usize;
            for starts in [start, walls] {
                let (s0, s1) = (starts[r + x0 as usize], starts[r + x1 as usize + 1]);
                if s1 > s0 {
                    spans.push((code, s0, s1));
                }
            }
        }
    }
    spans
}

/// The set bits of particle `d`'s mask, words at `word(w)`, in increasing order.
fn bits(words: usize, word: impl Fn(usize) -> u32) -> Vec<usize> {
    (0..32 * words).filter(|&b| word(b / 32) >> (b % 32) & 1 == 1).collect()
}

/// The entry (j | code << 28, device indices) at each walk ordinal of `ords`.
fn locate(spans: &[(u32, u32, u32)], sorted: &[u32], ords: &[usize]) -> Vec<u32> {
    let mut out = Vec::with_capacity(ords.len());
    let (mut k, mut base) = (0usize, 0usize);
    for &b in ords {
        while k < spans.len() && b >= base + (spans[k].2 - spans[k].1) as usize {
            base += (spans[k].2 - spans[k].1) as usize;
            k += 1;
        }
        let Some(&(code, s0, _)) = spans.get(k) else { break };
        out.push(sorted[s0 as usize + b - base] | code << IMAGE_SHIFT);
    }
    out
}

/// What [`decode`] reads back: the device's positions and buffers, in device order.
pub struct MaskBuffers<'a, T> {
    /// Positions (the cells lists' query points).
    pub pos: &'a [V2<T>],
    /// Reference positions of the tracking build.
    pub ref_pos: &'a [V2<T>],
    /// This evaluation's `cell_start` (all of it: the fluids' starts, the previous ones, the
    /// walls') and the particle in each slot.
    pub cell_start: &'a [u32],
    pub sorted: &'a [u32],
    /// Bindings 3, 6 and 5.
    pub nbr: &'a [u32],
    pub cand: &'a [u32],
    pub cand_hi: &'a [u32],
}

/// Every particle's list (device indices, packed j | code << 28, walk order) from the masks of
/// a list variant with [`uses_masks`].
pub fn decode<T: Real>(spec: &VariantSpec, grid: &CellBox<T>, images: &Images<T>, b: &MaskBuffers<T>) -> Vec<Vec<u32>> {
    let n = b.pos.len();
    let cells = grid.cells();
    let (fluid, walls) = (&b.cell_start[..cells + 1], &b.cell_start[2 * (cells + 1)..3 * (cells + 1)]);
    (0..n)
        .map(|d| {
            if spec.search == SearchKind::Tracking {
                let snap_sorted = &b.cand[CAND_LO_WORDS * n..(CAND_LO_WORDS + 1) * n];
                let snap_start = &b.cand[(CAND_LO_WORDS + 1) * n..];
                let spans = walk(grid, images, b.ref_pos[d], 4, (snap_start, walls));
                let cw = |w: usize| {
                    if w < CAND_LO_WORDS {
                        b.cand[w * n + d]
                    } else {
                        b.cand_hi[(w - CAND_LO_WORDS) * n + d]
                    }
                };
                let cands = locate(&spans, snap_sorted, &bits(CAND_WORDS, cw));
                bits(NBR_WORDS_TRACK, |w| b.nbr[w * n + d]).into_iter().filter_map(|m| cands.get(m).copied()).collect()
            } else {
                let spans = walk(grid, images, b.pos[d], 3, (fluid, walls));
                let half = NBR_WORDS_CELLS / 2;
                let nw = |w: usize| if w < half { b.nbr[w * n + d] } else { b.cand[(w - half) * n + d] };
                locate(&spans, b.sorted, &bits(NBR_WORDS_CELLS, nw))
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn list_words_fit_a_2_gib_binding_at_1e8() {
        let n = 100_000_000;
        let cap = (2usize << 30) / 4;
        let masked: Vec<VariantSpec> =
            VariantSpec::all().iter().filter_map(|s| s.with_lists(ListFormat::Masks)).collect();
        let recomputed = masked.iter().filter(|s| s.kernel_values == KernelValues::Recomputed);
        assert!(recomputed.clone().all(uses_masks) && recomputed.count() >= 20);
        // The cached tracking variants: masks for the candidates; their list slots and cache are
        // split into list chunks (`gpu::list_chunks`), the rest fits.
        let cached: Vec<&VariantSpec> = masked.iter().filter(|s| s.kernel_values == KernelValues::Cached).collect();
        assert!(cached.len() == 12 && cached.iter().all(|s| cand_masks(s) && !uses_masks(s)));
        for spec in &masked {
            let w = list_words(spec, n, n / 12, 4);
            let split: Vec<&str> = crate::gpu::list_chunks::split_arrays(spec, 4).iter().map(|a| a.0).collect();
            let b4 = if split.contains(&"cache_wf") { "cache_wf" } else { "b4" };
            for (name, words) in [("nbr", w.nbr), (b4, w.b4), ("b5", w.b5), ("cand", w.cand), ("accum", w.accum)] {
                assert!(words <= cap || split.contains(&name), "{spec}: {name} {words} words");
            }
        }
    }

    #[test]
    fn the_tracking_box_holds_support_plus_skin() {
        // The 4 × 4 box reaches at least 1.5 cells from x on every side.
        let cfg = crate::neighbours::TrackingCfg::default();
        assert!((1.0 + cfg.skin_ratio) / crate::neighbours::cells::CELL_FACTOR <= 1.5);
    }
}
