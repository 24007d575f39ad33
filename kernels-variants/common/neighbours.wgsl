// neighbours.wgsl: the neighbour loop of the `thread` stages, for the three searches, as a walk
// over spans of slots with a plain loop over each span (DualSPHysics' "range" loops):
//
//     var w = nb_spans(i, xi);
//     while nb_span(&w) {
//         for (var s = w.s0; s < w.s1; s++) {
//             let nb = nb_at(w, s);
//             if nb.hit { … nb.j, nb.code, nb.xj … }
//         }
//     }
//
// A neighbour is (j, code) with |x_i − image_pos(code, x_j)|² < support² (twin of
// `neighbours::within`), self included. The spans, by search:
// * cells (neither `DIRECT` nor `TRACKING`): the span walk of common/walk.wgsl over the 3×3
//   cells around `inverse_pos(c, x_i)`, each row its fluid slots (the counting sort of the
//   fluids, slots 0..n_fluid) then its wall slots (the walls' static sort, `wall_start`); a slot
//   holds particle `sorted[s]`, or s itself in physical cell order (`physical_order`: the
//   particles renumbered in cell order at every search, search/reorder.wgsl);
// * `TRACKING` with slot candidates: one span, the particle's tracking candidates
//   (kernels-variants/search/tracking.wgsl), each entry (j, code) packed;
// * `NB_ITERATOR` (the direct search, and tracking with `MASK_CANDS`): spans of one neighbour,
//   handed out by the iterator `nb_next` below — the direct search tests DIRECT_CHUNK
//   candidates per loop iteration in straight-line code (every particle under every existing
//   image code, O(N²·images), the order of the CPU lists: code, then index; lavapipe ends every
//   loop of an invocation group after 65,535 iterations in all, gallivm's
//   LP_MAX_TGSI_LOOP_ITERATIONS, silently: one candidate per iteration lost neighbours from
//   ~2,300 particles; the plan refuses direct beyond `plan::gpu::LAVAPIPE_LOOP_CANDIDATES`
//   there); the tracking masks are the set bits of the candidate mask on the build's walk
//   (common/mask_lists.wgsl).
// The span form keeps the per-candidate loop free of iterator state (why and what it changed:
// reports/engine/README.md, "The neighbour loop as spans").
// Shared include (needs common/bindings: pos, sorted, cell_start; common/variant_bindings:
// counts, cand); no entry points.

#import common/variant_bindings
#import common/walk
#ifdef MASK_LISTS
#import common/mask_lists
#else
#ifdef MASK_CANDS
#import common/mask_lists
#endif
#endif

// One candidate of a span: the particle j, its image code and image position, and whether it
// is a neighbour (within the support).
struct NbHit {
    j: u32,
    code: u32,
    xj: real2,
    hit: bool,
}

// Candidate j under image code `code`, whose transform is `map`, for the query point xi.
fn nb_hit(xi: real2, j: u32, code: u32, map: ImageMap) -> NbHit {
    let xj = image_apply(map, pos[j]);
    let d = xi - xj;
    return NbHit(j, code, xj, d.x * d.x + d.y * d.y < params.support2);
}

#ifdef NB_ITERATOR
// The iterator of the direct search and the tracking masks (module comment).
struct Nb {
    j: u32,        // current neighbour index
    code: u32,     // its image code
    xj: real2,     // image position of j
    xi: real2,     // the query particle
    cur: u32,      // DIRECT: flat cursor (code·n + j)
    end: u32,
    mask: u32,     // DIRECT: hits of the current chunk not yet returned (bit k = candidate base + k)
    base: u32,     // DIRECT: flat cursor (code·n + j) of the current chunk's first candidate
    i: u32,        // the query particle's index
    m: u32,        // TRACKING with MASK_CANDS: candidate ordinal of the current candidate
#ifdef MASK_CANDS
    walk: Walk,    // TRACKING: the walk of the build's box (common/walk.wgsl)
    word: u32,     // TRACKING: current word of the candidate mask
    live: bool,    // TRACKING: the walk has a span left
#endif
}
#endif

// Candidates tested per loop iteration of the direct search.
const DIRECT_CHUNK: u32 = 8u;

// Cell coordinates of p, clamped to [−2, n+1] like `CellGrid::coords`.
fn cell_coords(p: real2) -> vec2<i32> {
    let fx = floor((p.x - params.grid_origin_x) * params.grid_inv_cell);
    let fy = floor((p.y - params.grid_origin_y) * params.grid_inv_cell);
    let nx = real(params.grid_nx);
    let ny = real(params.grid_ny);
    return vec2<i32>(i32(clamp(fx, real(-2.0), nx + real(1.0))), i32(clamp(fy, real(-2.0), ny + real(1.0))));
}

// Cell coordinates of p clamped into the grid: the cell whose list holds a particle at p.
fn grid_coords(p: real2) -> vec2<i32> {
    return clamp(cell_coords(p), vec2<i32>(0, 0), vec2<i32>(i32(params.grid_nx) - 1, i32(params.grid_ny) - 1));
}

// Linear cell of p (coordinates clamped into the grid), as `CellGrid::cell_of`.
fn cell_index(p: real2) -> u32 {
    let c = grid_coords(p);
    return u32(c.x + i32(params.grid_nx) * c.y);
}

// Cells per block of the cell scan (twin of search/cell_scan.wgsl's SCAN_BLOCK, plan::SCAN_BLOCK).
const COUNT_SCAN_BLOCK: u32 = 256u;

// The first step of the counting sort for fluid particle i (walls are sorted once, by the host:
// `wall_start`): its cell, the cell's count and the scan's
// block sum (kept after the counts), on counts the host cleared. Run by search/cell_count.wgsl,
// or at the end of an integrator stage (the stage table's `cell_count` epilogue) by the thread
// that has just moved the particle.
// The slot i of the last search's lists is kept after them (`sorted[n + i]`) for the merge of
// search/cell_scatter.wgsl (nothing reads `sorted` while the particles move and are counted).
fn cell_count_at(i: u32) {
    let c = cell_index(pos[i]);
    cell_of[i] = c;
    atomicAdd(&cell_counts[c], 1u);
    atomicAdd(&cell_counts[params.grid_nx * params.grid_ny + c / COUNT_SCAN_BLOCK], 1u);
    sorted[params.n + i] = sorted[i];
}

// Cell c's start of the last search, kept after this search's starts by the scan (first write
// of a start: `keep_start`) for the merge.
fn prev_start(c: u32) -> u32 {
    return cell_start[params.grid_nx * params.grid_ny + 1u + c];
}

// Writes cell c's start (c = cells: the total), keeping the one it replaces.
fn keep_start(c: u32, start: u32) {
    let cells = params.grid_nx * params.grid_ny;
    cell_start[cells + 1u + c] = cell_start[c];
    cell_start[c] = start;
}

// Writes the scan's total (the start after the last cell) and checks it: every fluid particle
// is counted once, so a total other than n_fluid means the scan read counts that were not all there —
// in the fused scan below, a last workgroup that saw another workgroup's "done" before its
// counts (relaxed atomics order nothing between addresses) — and the step is noted in
// ctl[CTL_SCAN_MISS] for the host, which refuses the run (`gpu::solver::stepping`).
fn scan_total(cells: u32, total: u32) {
    keep_start(cells, total);
    if total != params.n_fluid {
        note_scan_miss();
    }
}

fn note_scan_miss() {
    atomicMin(&ctl[CTL_SCAN_MISS], atomicLoad(&ctl[CTL_STEP]));
}

// The stage table's `cell_scan` as the epilogue of an integrator stage: the exclusive prefix
// sum of the counts into `cell_start`, by the whole last workgroup (thread t of GROUP_THREADS,
// called in uniform control flow), each thread a contiguous chunk of cells; the counts are
// reset (as `scan_add` does). Grids of at most `plan::FUSED_SCAN_CELLS` cells.
var<workgroup> scan_part: array<u32, GROUP_THREADS>;

fn scan_cells_in_group(t: u32) {
    let cells = params.grid_nx * params.grid_ny;
    let chunk = (cells + GROUP_THREADS - 1u) / GROUP_THREADS;
    let a = min(t * chunk, cells);
    let e = min(a + chunk, cells);
    var s = 0u;
    for (var c = a; c < e; c++) {
        s += atomicLoad(&cell_counts[c]);
    }
    scan_part[t] = s;
    workgroupBarrier();
    if t == 0u {
        var run = 0u;
        for (var k = 0u; k < GROUP_THREADS; k++) {
            let v = scan_part[k];
            scan_part[k] = run;
            run += v;
        }
        scan_total(cells, run);
    }
    workgroupBarrier();
    let first = scan_part[t];
    var run = first;
    for (var c = a; c < e; c++) {
        let v = atomicLoad(&cell_counts[c]);
        keep_start(c, run);
        atomicStore(&cell_counts[c], 0u);
        run += v;
    }
    // A count that changed between the two reads (one arriving late) moved this chunk's starts.
    if run - first != s {
        note_scan_miss();
    }
}

#ifdef NB_ITERATOR
fn nb_begin(i: u32, xi: real2) -> Nb {
    var it: Nb;
    it.xi = xi;
    it.code = 0u;
    it.cur = 0u;
    it.end = 0u;
    it.i = i;
    it.m = 0xFFFFFFFFu;
#ifdef DIRECT
    it.end = 9u * params.n; // flat cursor: code·n + j over the nine codes
#else
    // TRACKING with MASK_CANDS. (Local copies: a pointer to a struct member cannot be a call
    // argument in SPIR-V output.)
    var walk = walk_begin(ref_pos[i], 4u, true);
    it.live = walk_next(&walk);
    it.walk = walk;
    it.word = 0u;
    it.mask = cand_word(i, 0u);
#endif
    return it;
}

#ifdef DIRECT
// Bit k set when candidate `c0 + k` (flat cursor, below `stop`) of code `code`, whose transform
// is `map`, is a neighbour.
fn direct_hit(xi: real2, code: u32, map: ImageMap, c0: u32, stop: u32, k: u32) -> u32 {
    let c = c0 + k;
    if c >= stop {
        return 0u;
    }
    let d = xi - image_apply(map, pos[c - code * params.n]);
    return select(0u, 1u << k, d.x * d.x + d.y * d.y < params.support2);
}
#endif

// Advances to the next neighbour; false at the end.
fn nb_next(it: ptr<function, Nb>) -> bool {
#ifdef DIRECT
    loop {
        if (*it).mask != 0u {
            let c = (*it).base + firstTrailingBit((*it).mask);
            (*it).mask &= (*it).mask - 1u;
            let code = c / params.n;
            let j = c - code * params.n;
            (*it).j = j;
            (*it).code = code;
            (*it).xj = image_apply(image_map_of(code), pos[j]);
            return true;
        }
        if (*it).cur >= (*it).end {
            return false;
        }
        let code = (*it).cur / params.n;
        if !image_code_exists(code) {
            (*it).cur = (code + 1u) * params.n;
            continue;
        }
        // DIRECT_CHUNK candidates of this code, unrolled: one loop iteration for all of them.
        let c0 = (*it).cur;
        let stop = min(c0 + DIRECT_CHUNK, (code + 1u) * params.n);
        let xi = (*it).xi;
        let m = image_map_of(code);
        (*it).mask = direct_hit(xi, code, m, c0, stop, 0u) | direct_hit(xi, code, m, c0, stop, 1u)
            | direct_hit(xi, code, m, c0, stop, 2u) | direct_hit(xi, code, m, c0, stop, 3u)
            | direct_hit(xi, code, m, c0, stop, 4u) | direct_hit(xi, code, m, c0, stop, 5u)
            | direct_hit(xi, code, m, c0, stop, 6u) | direct_hit(xi, code, m, c0, stop, 7u);
        (*it).base = c0;
        (*it).cur = stop;
    }
    return false;
#else
    return nb_next_mask(it);
#endif
}

// Spans of one neighbour each, from the iterator.
struct NbSpans {
    it: Nb,
    s0: u32,
    s1: u32,
}

fn nb_spans(i: u32, xi: real2) -> NbSpans {
    return NbSpans(nb_begin(i, xi), 0u, 0u);
}

// The next span; false at the end.
fn nb_span(w: ptr<function, NbSpans>) -> bool {
    var it = (*w).it;
    let more = nb_next(&it);
    (*w).it = it;
    (*w).s1 = select(0u, 1u, more);
    return more;
}

fn nb_at(w: NbSpans, s: u32) -> NbHit {
    return NbHit(w.it.j, w.it.code, w.it.xj, true);
}
#else
#ifdef TRACKING
// One span: the tracking candidates of particle i, each entry (j, code) packed.
struct NbSpans {
    xi: real2,
    s0: u32,
    s1: u32,
    done: bool,
}

fn nb_spans(i: u32, xi: real2) -> NbSpans {
    let s0 = i * CAND_SLOTS;
    return NbSpans(xi, s0, s0 + min(counts[params.n + i], CAND_SLOTS), false);
}

// The next span; false at the end.
fn nb_span(w: ptr<function, NbSpans>) -> bool {
    let first = !(*w).done;
    (*w).done = true;
    return first && (*w).s1 > (*w).s0;
}

fn nb_at(w: NbSpans, s: u32) -> NbHit {
    let e = cand[s];
    let code = e >> PACK_SHIFT;
    return nb_hit(w.xi, e & PACK_MASK, code, image_map_of(code));
}
#else
// The span walk of the 3×3 cells (common/walk.wgsl) over this evaluation's sort.
struct NbSpans {
    walk: Walk,
    s0: u32,
    s1: u32,
}

fn nb_spans(i: u32, xi: real2) -> NbSpans {
    return NbSpans(walk_begin(xi, 3u, false), 0u, 0u);
}

// The next non-empty span; false at the end.
fn nb_span(w: ptr<function, NbSpans>) -> bool {
    var walk = (*w).walk;
    let more = walk_next(&walk);
    (*w).walk = walk;
    (*w).s0 = walk.s0;
    (*w).s1 = walk.s1;
    return more;
}

fn nb_at(w: NbSpans, s: u32) -> NbHit {
    return nb_hit(w.walk.xi, slot_at(s, w.walk.phys), w.walk.code, w.walk.map);
}
#endif
#endif

#ifdef TRACKING
#ifdef MASK_CANDS
// The tracking iterator over the candidate mask: the set bits in increasing order, each
// located on the build's walk (ordinals only grow, so the walk only moves forward), under the
// exact distance test at the current positions.
fn nb_next_mask(it: ptr<function, Nb>) -> bool {
    loop {
        if (*it).mask == 0u {
            (*it).word += 1u;
            if (*it).word >= CAND_WORDS || !(*it).live {
                return false;
            }
            (*it).mask = cand_word((*it).i, (*it).word);
            continue;
        }
        let b = 32u * (*it).word + firstTrailingBit((*it).mask);
        (*it).mask &= (*it).mask - 1u;
        (*it).m += 1u;
        var walk = (*it).walk;
        let j = walk_to(&walk, b);
        (*it).walk = walk;
        if j == 0xFFFFFFFFu {
            return false;
        }
        let code = walk.code;
        let xj = image_apply(walk.map, pos[j]);
        let d = (*it).xi - xj;
        if d.x * d.x + d.y * d.y < params.support2 {
            (*it).j = j;
            (*it).code = code;
            (*it).xj = xj;
            return true;
        }
    }
    return false;
}
#endif
#endif
