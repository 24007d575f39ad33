// walk.wgsl: the span walk over the cells of a square box around a point (3 × 3: the cells
// search and the lists; 4 × 4: the tracking candidates), code by code (existing image codes in
// order), row by row; the cells of one row are adjacent in the counting sort of the fluids and in
// the walls' static sort, so each row is two contiguous spans of slots, its fluids then its walls
// (DualSPHysics' "range" loops), and the walk numbers the candidates 0, 1, 2, … in that order
// (the ordinals of common/mask_lists.wgsl). Every box is derived from positions by subtraction,
// multiplication and floor only, so every kernel and the host's decoder walk the same spans.
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
    map: ImageMap, // its transform (shaders/geometry.wgsl), applied to every candidate of the code
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
    k.map = image_map_of(0u);
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

// Advances to the next non-empty span; false at the end of the walk. A code whose box lies
// wholly outside the grid, and the wall half of every row when there are no wall particles, are
// passed over without visiting their rows (they hold no slots: the spans are the same).
fn walk_next(k: ptr<function, Walk>) -> bool {
    (*k).ord += (*k).s1 - (*k).s0;
    let walls = params.n > params.n_fluid;
    let nx = i32(params.grid_nx);
    let ny = i32(params.grid_ny);
    let w = i32((*k).w);
    loop {
        (*k).half ^= 1u;
        if (*k).half == 1u && !walls {
            (*k).half = 0u;
        }
        if (*k).half == 0u {
            (*k).row += 1u;
        }
        if (*k).row >= (*k).w {
            var c = (*k).code;
            loop {
                c++;
                if c >= 9u {
                    (*k).s0 = 0u;
                    (*k).s1 = 0u;
                    return false;
                }
                if !image_code_exists(c) {
                    continue;
                }
                let map = image_map_of(c);
                let corner = box_corner(image_unapply(map, (*k).xi), (*k).w);
                if corner.x + w > 0 && corner.x < nx && corner.y + w > 0 && corner.y < ny {
                    (*k).code = c;
                    (*k).map = map;
                    (*k).corner = corner;
                    break;
                }
            }
            (*k).row = 0u;
            (*k).half = 0u;
        }
        let y = (*k).corner.y + i32((*k).row);
        let x0 = max((*k).corner.x, 0);
        let x1 = min((*k).corner.x + w - 1, nx - 1);
        if y < 0 || y >= ny || x0 > x1 {
            continue;
        }
        let r = u32(nx * y);
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
