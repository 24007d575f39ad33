// mask_lists.wgsl: the compact neighbour and tracking lists (`MASK_LISTS`: the cells and
// tracking searches with recomputed kernel values; `MASK_CANDS`: the tracking candidates alone,
// also with cached kernel values, whose lists keep slots; twin of `gpu::mask_lists`). A particle's
// candidates are the cells of a square box around its (inversely imaged) cell, walked code by
// code (existing image codes in order), row by row; the cells of one row are adjacent in the
// counting sort of the fluids and in the walls' static sort, so each row is two contiguous
// spans of slots (its fluids, then its walls: common/neighbours.wgsl), and the walk numbers
// the candidates 0, 1, 2, … in that order. A list is a bitmask over these walk ordinals, a few
// words per particle instead of one index per entry:
// * explicit lists (`nbr`, cells): bit b set when walk ordinal b of the 3 × 3 box around the
//   cell of x_i, over this evaluation's sort, is a neighbour; NBR_WORDS_CELLS words, the first
//   half in `nbr`, the second in `cand` (unused by the cells search), word-major (w·n + i);
// * tracking candidates: the 4 × 4 box that holds the circle of support + skin (≤ 1.5 cells)
//   around the reference position: columns cx − 2 … cx + 1 when x lies in the lower half of
//   its cell, cx − 1 … cx + 2 otherwise (rows alike). Bit b set when ordinal b was within
//   support + skin at the build. The walk refers to the sort of the build, which the next
//   evaluation's counting sort overwrites, so `track_build` keeps a copy of `sorted` and
//   `cell_start` after the mask words in `cand`; CAND_WORDS words, CAND_LO_WORDS in `cand`,
//   the rest in binding 5 (`cand_hi`);
// * explicit lists over tracking: bit m set when the m-th candidate (m-th set bit of the
//   candidate mask) is a neighbour; NBR_WORDS_TRACK words in `nbr`.
// Every box is derived from positions by subtraction, multiplication and floor only (no
// multiply-add a compiler could contract), so the building and the reading kernels and the
// host's decoder walk exactly the same spans. A neighbour (or candidate) whose ordinal falls
// past the mask is counted as an overflow and reported by the host, never dropped silently.
// Library module (needs common/variant_bindings); no entry points.

#import common/variant_bindings
#import common/walk

// Moves the walk to the span holding ordinal b (at or after the current one) and returns the
// particle there; 0xFFFFFFFF when the walk ends first.
fn walk_to(k: ptr<function, Walk>, b: u32) -> u32 {
    while b >= (*k).ord + ((*k).s1 - (*k).s0) {
        if !walk_next(k) {
            return 0xFFFFFFFFu;
        }
    }
    return walk_particle(k, (*k).s0 + (b - (*k).ord));
}

// Position of the t-th (from 0) set bit of m (t < countOneBits(m)).
fn select_bit(m: u32, t: u32) -> u32 {
    var r = m;
    for (var s = 0u; s < t; s++) {
        r &= r - 1u;
    }
    return firstTrailingBit(r);
}

#ifdef TRACKING
const NBR_WORDS: u32 = NBR_WORDS_TRACK;
#else
const NBR_WORDS: u32 = NBR_WORDS_CELLS;
#endif

// Word w of particle i's neighbour mask.
fn nbr_word(i: u32, w: u32) -> u32 {
#ifdef TRACKING
    return nbr[w * params.n + i];
#else
    let half = NBR_WORDS_CELLS / 2u;
    if w < half {
        return nbr[w * params.n + i];
    }
    return cand[(w - half) * params.n + i];
#endif
}

fn set_nbr_word(i: u32, w: u32, v: u32) {
#ifdef TRACKING
    nbr[w * params.n + i] = v;
#else
    let half = NBR_WORDS_CELLS / 2u;
    if w < half {
        nbr[w * params.n + i] = v;
    } else {
        cand[(w - half) * params.n + i] = v;
    }
#endif
}

#ifdef TRACKING
// Word w of particle i's candidate mask.
fn cand_word(i: u32, w: u32) -> u32 {
    if w < CAND_LO_WORDS {
        return cand[w * params.n + i];
    }
    return cand_hi[(w - CAND_LO_WORDS) * params.n + i];
}

fn set_cand_word(i: u32, w: u32, v: u32) {
    if w < CAND_LO_WORDS {
        cand[w * params.n + i] = v;
    } else {
        cand_hi[(w - CAND_LO_WORDS) * params.n + i] = v;
    }
}

// Walk ordinal of the m-th candidate of i (0xFFFFFFFF past the last).
fn cand_ordinal(i: u32, m: u32) -> u32 {
    var t = m;
    for (var w = 0u; w < CAND_WORDS; w++) {
        let word = cand_word(i, w);
        let c = countOneBits(word);
        if t < c {
            return 32u * w + select_bit(word, t);
        }
        t -= c;
    }
    return 0xFFFFFFFFu;
}
#endif

// The k-th neighbour of particle i at xi as (j, code); j = 0xFFFFFFFF when there is none.
fn mask_entry(i: u32, xi: real2, k: u32) -> vec2<u32> {
    var t = k;
    var b = 0xFFFFFFFFu;
    for (var w = 0u; w < NBR_WORDS; w++) {
        let word = nbr_word(i, w);
        let c = countOneBits(word);
        if t < c {
            b = 32u * w + select_bit(word, t);
            break;
        }
        t -= c;
    }
#ifdef TRACKING
    b = cand_ordinal(i, b);
    var walk = walk_begin(ref_pos[i], 4u, true);
#else
    var walk = walk_begin(xi, 3u, false);
#endif
    if b == 0xFFFFFFFFu || !walk_next(&walk) {
        return vec2<u32>(0xFFFFFFFFu, 0u);
    }
    let j = walk_to(&walk, b);
    return vec2<u32>(j, walk.code);
}
