// cell_scatter.wgsl: last passes of the counting sort: `cell_scatter` puts every particle in
// its cell's segment of `sorted` (atomic cursor, so the order inside a cell is arbitrary), then
// `cell_sort` (one thread per cell) sorts each segment by index so the neighbour order, hence
// every sum, is the same on every run.

#import common/bindings

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
    let a = cell_start[c];
    let b = cell_start[c + 1u];
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
