// cell_lists.wgsl: the per-cell builds of the fluids' counting sort (one thread per cell), shared
// by search/cell_scatter.wgsl (the lists alone) and search/reorder.wgsl (the lists, then the
// particles renumbered in their order). `sort_cell` sorts the segment the scatter filled by
// index, so the neighbour order, hence every sum, is the same on every run. `merge_cell` builds
// the same list without a scatter when the particles were counted (and the starts scanned)
// right after they moved, since the last search built its lists: it takes, from the last
// search's lists of the 3×3 cells around it (kept after the current ones: `sorted[n + s]`,
// `prev_start`), the particles now in its cell, and sorts them by index. A cell that finds
// fewer than its count (a particle came from farther: a periodic wrap, a jump) takes them from
// every fluid particle in index order instead. Library module; no entry points.

#import common/neighbours

// Insertion sort of sorted[a..b] by index.
fn sort_segment(a: u32, b: u32) {
    for (var k = a + 1u; k < b; k++) {
        let v = sorted[k];
        var m = k;
        while m > a && sorted[m - 1u] > v {
            sorted[m] = sorted[m - 1u];
            m--;
        }
        sorted[m] = v;
    }
}

// Cell c's list after the scatter: its segment sorted.
fn sort_cell(c: u32) {
    sort_segment(cell_start[c], cell_start[c + 1u]);
}

// Cell q's neighbour along one axis of n cells: coordinate x + d, wrapped when the axis has at
// least 3 cells (so the three are distinct), or -1 outside.
fn merge_axis(x: i32, d: i32, n: i32) -> i32 {
    let y = x + d;
    if n >= 3 {
        return (y + n) % n;
    }
    return select(-1, y, y >= 0 && y < n);
}

// Cell c's list from the last search's lists (module comment).
fn merge_cell(c: u32) {
    let nx = i32(params.grid_nx);
    let ny = i32(params.grid_ny);
    let a = cell_start[c];
    let b = cell_start[c + 1u];
    var k = a;
    for (var dy = -1; dy <= 1; dy++) {
        let y = merge_axis(i32(c) / nx, dy, ny);
        for (var dx = -1; dx <= 1; dx++) {
            let x = merge_axis(i32(c) % nx, dx, nx);
            if x < 0 || y < 0 {
                continue;
            }
            let q = u32(x + nx * y);
            let e = prev_start(q + 1u);
            for (var s = prev_start(q); s < e; s++) {
                let j = sorted[params.n + s];
                if k < b && cell_of[j] == c {
                    sorted[k] = j;
                    k++;
                }
            }
        }
    }
    if k == b {
        sort_segment(a, b);
        return;
    }
    // Eight particles per iteration in straight-line code (lavapipe's loop cap, as the direct
    // search's DIRECT_CHUNK).
    k = a;
    for (var j = 0u; j < params.n_fluid && k < b; j += 8u) {
        merge_take(j, c, b, &k);
        merge_take(j + 1u, c, b, &k);
        merge_take(j + 2u, c, b, &k);
        merge_take(j + 3u, c, b, &k);
        merge_take(j + 4u, c, b, &k);
        merge_take(j + 5u, c, b, &k);
        merge_take(j + 6u, c, b, &k);
        merge_take(j + 7u, c, b, &k);
    }
}

// Fluid particle j into slot *k of cell c's list (ending at b) when it is in c.
fn merge_take(j: u32, c: u32, b: u32, k: ptr<function, u32>) {
    if j < params.n_fluid && *k < b && cell_of[j] == c {
        sorted[*k] = j;
        *k += 1u;
    }
}
