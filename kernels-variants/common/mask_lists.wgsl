// mask_lists.wgsl: the compact neighbour and tracking lists (`MASK_LISTS`: the cells and
// tracking searches with recomputed kernel values; twin of `gpu::mask_lists`). A particle's
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

// Cells of the grid for position p in cell units (before the floor of `cell_coords`).
fn cell_units(p: real2) -> real2 {
    return real2((p.x - params.grid_origin_x) * params.grid_inv_cell, (p.y - params.grid_origin_y) * params.grid_inv_cell);
}

// Lower-left cell of the walk box of width `w` (3: cells, 4: tracking) around q.
fn box_corner(q: real2, w: u32) -> vec2<i32> {
    let f = cell_units(q);
    let nx = real(params.grid_nx);
    let ny = real(params.grid_ny);
    let c = vec2<i32>(i32(clamp(floor(f.x), real(-2.0), nx + real(1.0))), i32(clamp(floor(f.y), real(-2.0), ny + real(1.0))));
    if w == 3u {
        return c - vec2<i32>(1, 1);
    }
    // The half of the cell q lies in (0 lower, 1 upper), in integers.
    let h = vec2<i32>(i32(floor(f.x * real(2.0))), i32(floor(f.y * real(2.0)))) - 2 * vec2<i32>(i32(floor(f.x)), i32(floor(f.y)));
    return c - vec2<i32>(2, 2) + clamp(h, vec2<i32>(0, 0), vec2<i32>(1, 1));
}

// One walk over the spans of a box (module comment).
struct Walk {
    xi: real2,     // the query point (inversely imaged per code)
    code: u32,     // current image code
    row: u32,      // current row of the box
    half: u32,     // 0: the row's fluid span, 1: its wall span
    w: u32,        // box width (3 or 4)
    corner: vec2<i32>,
    s0: u32,       // current span [s0, s1) of the sort
    s1: u32,
    ord: u32,      // walk ordinal of s0
    snap: bool,    // true: the tracking build's copy of the sort
    phys: bool,    // physical cell order (`physical_order`, read once)
}

fn walk_begin(xi: real2, w: u32, snap: bool) -> Walk {
    var k: Walk;
    k.xi = xi;
    k.code = 0xFFFFFFFFu;
    k.row = w - 1u;
    k.half = 1u;
    k.w = w;
    k.corner = vec2<i32>(0, 0);
    k.s0 = 0u;
    k.s1 = 0u;
    k.ord = 0u;
    k.snap = snap;
    k.phys = physical_order();
    return k;
}

// `cell_start` of this evaluation, or of the tracking build.
fn span_start(snap: bool, c: u32) -> u32 {
#ifdef TRACKING
    if snap {
        return cand[(CAND_LO_WORDS + 1u) * params.n + c];
    }
#endif
    return cell_start[c];
}

// The particle in slot s of walk k's sort: this evaluation's, or the tracking build's copy
// (the walls' slots are static).
fn walk_particle(k: ptr<function, Walk>, s: u32) -> u32 {
#ifdef TRACKING
    if (*k).snap {
        return cand[CAND_LO_WORDS * params.n + s];
    }
#endif
    return slot_at(s, (*k).phys);
}

// Advances to the next non-empty span; false at the end of the walk.
fn walk_next(k: ptr<function, Walk>) -> bool {
    (*k).ord += (*k).s1 - (*k).s0;
    loop {
        (*k).half ^= 1u;
        if (*k).half == 0u {
            (*k).row += 1u;
        }
        if (*k).row >= (*k).w {
            var c = (*k).code + 1u;
            while c < 9u && !image_exists(params, c) {
                c++;
            }
            if c >= 9u {
                (*k).s0 = 0u;
                (*k).s1 = 0u;
                return false;
            }
            (*k).code = c;
            (*k).corner = box_corner(inverse_pos(params, c, (*k).xi), (*k).w);
            (*k).row = 0u;
        }
        let y = (*k).corner.y + i32((*k).row);
        let x0 = max((*k).corner.x, 0);
        let x1 = min((*k).corner.x + i32((*k).w) - 1, i32(params.grid_nx) - 1);
        if y < 0 || y >= i32(params.grid_ny) || x0 > x1 {
            continue;
        }
        let r = u32(i32(params.grid_nx) * y);
        if (*k).half == 0u {
            (*k).s0 = span_start((*k).snap, r + u32(x0));
            (*k).s1 = span_start((*k).snap, r + u32(x1) + 1u);
        } else {
            (*k).s0 = wall_start(r + u32(x0));
            (*k).s1 = wall_start(r + u32(x1) + 1u);
        }
        if (*k).s1 > (*k).s0 {
            return true;
        }
    }
    return false;
}

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
