// cell_scatter.wgsl: last passes of the counting sort: `cell_scatter` puts every particle in
// its cell's segment of `sorted` (atomic cursor, so the order inside a cell is arbitrary), then
// `cell_sort` (one thread per cell) sorts each segment by index so the neighbour order, hence
// every sum, is the same on every run. `cell_merge` does both in one kernel when the particles
// were counted (and the starts scanned) right after they moved, since the last search built its
// lists: one thread per cell takes, from the last search's lists of the 3×3 cells around it
// (kept after the current ones: `sorted[n + s]`, `prev_start`), the particles now in its cell,
// and sorts them by index, the same list as scatter and sort. A cell that finds fewer than its
// count (a particle came from farther: a periodic wrap, a jump) takes them from every particle
// in index order instead.

#import common/bindings
#import common/neighbours

@compute @workgroup_size(GROUP_THREADS)
fn cell_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let c = cell_of[i];
    let k = atomicAdd(&cell_counts[c], 1u);
    sorted[cell_start[c] + k] = i;
}

@compute @workgroup_size(GROUP_THREADS)
fn cell_sort(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let c = linear_id(gid, nwg);
    if c >= params.grid_nx * params.grid_ny {
        return;
    }
    sort_segment(cell_start[c], cell_start[c + 1u]);
}

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

// Cell q's neighbour along one axis of n cells: coordinate x + d, wrapped when the axis has at
// least 3 cells (so the three are distinct), or -1 outside.
fn merge_axis(x: i32, d: i32, n: i32) -> i32 {
    let y = x + d;
    if n >= 3 {
        return (y + n) % n;
    }
    return select(-1, y, y >= 0 && y < n);
}

@compute @workgroup_size(GROUP_THREADS)
fn cell_merge(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let c = linear_id(gid, nwg);
    let nx = i32(params.grid_nx);
    let ny = i32(params.grid_ny);
    if c >= u32(nx * ny) {
        return;
    }
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
    for (var j = 0u; j < params.n && k < b; j += 8u) {
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

// Particle j into slot *k of cell c's list (ending at b) when it is in c.
fn merge_take(j: u32, c: u32, b: u32, k: ptr<function, u32>) {
    if j < params.n && *k < b && cell_of[j] == c {
        sorted[*k] = j;
        *k += 1u;
    }
}
