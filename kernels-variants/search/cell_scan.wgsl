// cell_scan.wgsl: exclusive prefix sum of the cell counts into `cell_start` (n_cells + 1
// entries) over blocks of SCAN_BLOCK cells, one workgroup per block (no workgroup waits for
// another, so no forward-progress assumption). The block sums are counted by
// search/cell_count.wgsl itself (kept after the counts, at cell_counts[n_cells + b]).
// `scan_blocks` (one workgroup, dispatched only when there are more than SCAN_BLOCK blocks)
// scans the block sums in place and writes the total to cell_start[n_cells]; with at most
// SCAN_BLOCK blocks `scan_add` sums the block sums before its own in workgroup memory instead
// (the last block writes the total). `scan_add` scans each block (Hillis–Steele) and adds its
// block's offset. It also resets the counts to zero: they are the scatter cursors next. Twin
// of `SCAN_BLOCK` / `scan_blocks` in core/src/gpu/plan.rs. Every start written keeps the one it
// replaces after the new ones (`keep_start`, common/neighbours.wgsl) for the merge of
// search/cell_scatter.wgsl. The stage table's `cell_scan` stage as a pass of its own (the
// unfused engine, or the search's own scan when no integrator stage scanned the counts).

#import common/bindings
#import common/neighbours

const SCAN_BLOCK: u32 = 256u;
var<workgroup> part: array<u32, SCAN_BLOCK>;

fn scan_cells() -> u32 {
    return params.grid_nx * params.grid_ny;
}

// The count of cell c (0 past the end).
fn count_or_zero(c: u32, cells: u32) -> u32 {
    if c < cells {
        return atomicLoad(&cell_counts[c]);
    }
    return 0u;
}

@compute @workgroup_size(256)
fn scan_blocks(@builtin(local_invocation_index) t: u32) {
    let cells = scan_cells();
    let blocks = (cells + SCAN_BLOCK - 1u) / SCAN_BLOCK;
    let chunk = (blocks + SCAN_BLOCK - 1u) / SCAN_BLOCK;
    let a = min(t * chunk, blocks);
    let e = min(a + chunk, blocks);
    var s = 0u;
    for (var k = a; k < e; k++) {
        s += atomicLoad(&cell_counts[cells + k]);
    }
    part[t] = s;
    workgroupBarrier();
    if t == 0u {
        var run = 0u;
        for (var k = 0u; k < SCAN_BLOCK; k++) {
            let v = part[k];
            part[k] = run;
            run += v;
        }
        scan_total(cells, run);
    }
    workgroupBarrier();
    var run = part[t];
    for (var k = a; k < e; k++) {
        let v = atomicLoad(&cell_counts[cells + k]);
        atomicStore(&cell_counts[cells + k], run);
        run += v;
    }
}

@compute @workgroup_size(256)
fn scan_add(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let cells = scan_cells();
    let b = linear_group_xy(wg, nwg);
    let c = b * SCAN_BLOCK + t;
    let blocks = (cells + SCAN_BLOCK - 1u) / SCAN_BLOCK;
    // This block's offset with at most SCAN_BLOCK blocks: the block sums before it, summed in
    // workgroup memory (computed by every workgroup, used only then: the barriers stay uniform).
    part[t] = select(0u, atomicLoad(&cell_counts[cells + min(t, blocks - 1u)]), t < b);
    workgroupBarrier();
    for (var s = SCAN_BLOCK / 2u; s > 0u; s >>= 1u) {
        if t < s {
            part[t] += part[t + s];
        }
        workgroupBarrier();
    }
    var offset = part[0];
    workgroupBarrier();
    if blocks > SCAN_BLOCK {
        offset = atomicLoad(&cell_counts[cells + b]);
    } else if t == 0u && b + 1u == blocks {
        scan_total(cells, offset + atomicLoad(&cell_counts[cells + b]));
    }
    let v = count_or_zero(c, cells);
    part[t] = v;
    workgroupBarrier();
    for (var s = 1u; s < SCAN_BLOCK; s <<= 1u) {
        var add = 0u;
        if t >= s {
            add = part[t - s];
        }
        workgroupBarrier();
        part[t] += add;
        workgroupBarrier();
    }
    if c < cells {
        keep_start(c, offset + part[t] - v);
        atomicStore(&cell_counts[c], 0u);
    }
}
