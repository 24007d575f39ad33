// cell_count.wgsl: first pass of the counting sort of the `cells` search: the cell of every
// particle (clamped into the grid like `CellGrid::cell_of`), the per-cell counts and the
// scan's per-block sums (atomic; the scan needs no reduce pass).
// `cell_count` is cleared by the host before this pass.

#import common/neighbours

const SCAN_BLOCK: u32 = 256u; // twin of search/cell_scan.wgsl

@compute @workgroup_size(GROUP_THREADS)
fn cell_count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let c = cell_index(pos[i]);
    cell_of[i] = c;
    atomicAdd(&cell_counts[c], 1u);
    // The block sums of the scan (search/cell_scan.wgsl), kept after the counts.
    atomicAdd(&cell_counts[params.grid_nx * params.grid_ny + c / SCAN_BLOCK], 1u);
}
