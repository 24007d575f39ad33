// cell_scan.wgsl: exclusive prefix sum of the cell counts into `cell_start` (n_cells + 1
// entries), by ONE workgroup of 256 threads: each thread scans a contiguous chunk, thread 0
// scans the 256 chunk sums. Also resets the counts to zero: they are the scatter cursors next.

#import common/bindings

const SCAN_THREADS: u32 = 256u;
var<workgroup> chunk_sum: array<u32, SCAN_THREADS>;

@compute @workgroup_size(256)
fn cell_scan(@builtin(local_invocation_id) lid: vec3<u32>) {
    let t = lid.x;
    let cells = params.grid_nx * params.grid_ny;
    let chunk = (cells + SCAN_THREADS - 1u) / SCAN_THREADS;
    let a = min(t * chunk, cells);
    let b = min(a + chunk, cells);
    var s = 0u;
    for (var c = a; c < b; c++) {
        s += atomicLoad(&cell_counts[c]);
    }
    chunk_sum[t] = s;
    workgroupBarrier();
    if t == 0u {
        var run = 0u;
        for (var k = 0u; k < SCAN_THREADS; k++) {
            let v = chunk_sum[k];
            chunk_sum[k] = run;
            run += v;
        }
        cell_start[cells] = run;
    }
    workgroupBarrier();
    var run = chunk_sum[t];
    for (var c = a; c < b; c++) {
        cell_start[c] = run;
        run += atomicLoad(&cell_counts[c]);
        atomicStore(&cell_counts[c], 0u);
    }
}
