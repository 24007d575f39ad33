// cell_scatter.wgsl: last passes of the fluids' counting sort (walls are sorted once, by the
// host): `cell_scatter` puts every fluid particle in its cell's segment of `sorted` (atomic
// cursor, so the order inside a cell is arbitrary), then `cell_sort` (one thread per cell)
// sorts each segment by index. `cell_merge` does both in one kernel when the particles were
// counted (and the starts scanned) right after they moved, since the last search built its
// lists (common/cell_lists.wgsl). When the particles are renumbered in this search,
// search/reorder.wgsl's `reorder_sort` / `reorder_merge` run instead of `cell_sort` /
// `cell_merge`.

#import common/bindings
#import common/cell_lists

@compute @workgroup_size(GROUP_THREADS)
fn cell_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n_fluid {
        return;
    }
    let c = cell_of[i];
    let k = atomicAdd(&cell_counts[c], 1u);
    sorted[cell_start[c] + k] = i;
}

@compute @workgroup_size(GROUP_THREADS)
fn cell_sort(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let c = linear_id(gid, nwg);
    if c < params.grid_nx * params.grid_ny {
        sort_cell(c);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn cell_merge(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let c = linear_id(gid, nwg);
    if c < params.grid_nx * params.grid_ny {
        merge_cell(c);
    }
}
