// tree.wgsl (block-tree mapping, thesis Fig. 6.5–6.7): the 16 × 32 layout of common/block_layout.wgsl;
// each row's 16 slot terms are summed by Harris' tree reduction in workgroup memory (strides
// 8, 4, 2, 1, sequential addressing), then column 0 adds the row sum to the particle's sums
// with ONE atomic add per component per workgroup (4 per particle: one per block in y), with
// the accumulation of common/accum.wgsl. The finalize kernels are those of block-atomic.

#import common/block_layout

var<workgroup> red_a: array<real2, 512>;
var<workgroup> red_b: array<real2, 512>;

// Tree-reduces each row of red_a (and red_b when `both`); afterwards column 0 holds the sums.
// Called in uniform control flow by every thread of the workgroup.
fn reduce_rows(lid: vec3<u32>, both: bool) {
    let idx = lid.y * COLS + lid.x;
    for (var s = COLS / 2u; s > 0u; s >>= 1u) {
        workgroupBarrier();
        if lid.x < s {
            red_a[idx] += red_a[idx + s];
            if both {
                red_b[idx] += red_b[idx + s];
            }
        }
    }
    workgroupBarrier();
}

@compute @workgroup_size(16, 32)
fn number_density(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let i = block_particle(wg, nwg, lid);
    red_a[lid.y * COLS + lid.x] = block_density(i, block_k(wg, lid));
    reduce_rows(lid, false);
    if lid.x == 0u && i < params.n {
        let t = red_a[lid.y * COLS];
        acc_add(i, 0u, F_DENSITY, t.x);
        acc_add(i, 1u, F_DENSITY, t.y);
    }
}

@compute @workgroup_size(16, 32)
fn colour_gradient(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let i = block_particle(wg, nwg, lid);
    let g = block_gradient(i, block_k(wg, lid));
    red_a[lid.y * COLS + lid.x] = g.g0;
    red_b[lid.y * COLS + lid.x] = g.g1;
    reduce_rows(lid, true);
    if lid.x == 0u && i < params.n {
        let a = red_a[lid.y * COLS];
        let b = red_b[lid.y * COLS];
        acc_add(i, 0u, F_GRAD, a.x);
        acc_add(i, 1u, F_GRAD, a.y);
        acc_add(i, 2u, F_GRAD, b.x);
        acc_add(i, 3u, F_GRAD, b.y);
    }
}

@compute @workgroup_size(16, 32)
fn acceleration(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let i = block_particle(wg, nwg, lid);
    red_a[lid.y * COLS + lid.x] = block_acceleration(i, block_k(wg, lid));
    reduce_rows(lid, false);
    if lid.x == 0u && i < params.n {
        let t = red_a[lid.y * COLS];
        acc_add(i, 0u, F_ACC, t.x);
        acc_add(i, 1u, F_ACC, t.y);
    }
}
