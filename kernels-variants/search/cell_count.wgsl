// cell_count.wgsl: first pass of the counting sort of the `cells` search: the cell of every
// fluid particle (walls are sorted once, by the host; clamped into the grid like
// `CellGrid::cell_of`), the per-cell counts and the scan's per-block sums (atomic; the scan
// needs no reduce pass): `cell_count_at` of common/neighbours.wgsl. `cell_count` is cleared by the host before this pass. The stage
// table's `cell_count` stage: its own pass in the unfused engine, otherwise run at the end of
// the integrator stages (thread/integrate.wgsl) and skipped by the next search.

#import common/neighbours

@compute @workgroup_size(GROUP_THREADS)
fn cell_count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i < params.n_fluid {
        cell_count_at(i);
    }
}
