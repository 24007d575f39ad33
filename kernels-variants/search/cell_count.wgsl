// cell_count.wgsl: first pass of the counting sort of the `cells` search: the cell of every
// particle (clamped into the grid like `CellGrid::cell_of`) and the per-cell counts (atomic).
// `cell_count` is cleared by the host before this pass.

#import common/neighbours

@compute @workgroup_size(64)
fn cell_count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    let c = cell_index(pos[i]);
    cell_of[i] = c;
    atomicAdd(&cell_counts[c], 1u);
}
