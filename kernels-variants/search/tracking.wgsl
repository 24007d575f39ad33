// tracking.wgsl: the thesis's tracking lists on the GPU (§6.3; twin of the `Tracking` arm of
// `neighbours::Search::update`). Each particle keeps the candidates within support + skin
// (skin = 0.25·support) found on the cell grid, and the neighbours are then found among them
// by the exact distance test (common/neighbours.wgsl, `TRACKING`). The lists are rebuilt when
// the largest displacement since the last build exceeds skin/2 or every k evaluations.
// The decision stays on the device (no read-back per evaluation): `track_check` reduces the
// max displacement² (a workgroup reduction, then one atomicMax on f32 bits per workgroup, valid
// for non-negative floats), `track_every` turns it and the evaluation counter into the flag `vctl[V_REBUILD]`, `track_build` rebuilds only
// when the flag is set (every thread returns at once otherwise) and `track_clear` lowers it.
// PERF: the cell sort of search/cell_*.wgsl still runs every evaluation (cheap next to the
// pair stages); indirect dispatch could skip it too. With `MASK_CANDS` the candidates are a
// bitmask over the build's cell walk (common/mask_lists.wgsl; a candidate past the mask
// overflows, V_CAND_MAX then holding the mask bits needed). Candidates beyond CAND_SLOTS are counted
// in vctl and reported as `NeighbourOverflow` by the host, never dropped silently; the
// truncated lists stay flagged (V_CAND_STALE: particles, counted by the build) for every
// evaluation until the next build, and `track_clear` keeps their most in V_CAND_OVER.

#import common/neighbours

var<workgroup> wg_disp2: array<u32, GROUP_THREADS>;

@compute @workgroup_size(GROUP_THREADS)
fn track_check(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = linear_id(gid, nwg);
    var bits = 0u;
    if i < params.n {
        let d = pos[i] - ref_pos[i];
        let d2 = f32(d.x * d.x + d.y * d.y);
        if d2 > 0.0 {
            bits = bitcast<u32>(d2);
        }
    }
    wg_disp2[t] = bits;
    workgroupBarrier();
    for (var s = GROUP_THREADS / 2u; s > 0u; s >>= 1u) {
        if t < s {
            wg_disp2[t] = max(wg_disp2[t], wg_disp2[t + s]);
        }
        workgroupBarrier();
    }
    if t == 0u && wg_disp2[0] > 0u {
        atomicMax(&vctl[V_DISP2], wg_disp2[0]);
    }
}

@compute @workgroup_size(1)
fn track_every() {
    let d2 = bitcast<f32>(atomicLoad(&vctl[V_DISP2]));
    atomicStore(&vctl[V_DISP2], 0u);
    var rebuild = atomicLoad(&vctl[V_REBUILD]) != 0u;
    rebuild = rebuild || d2 > f32(vparams[VP_HALF_SKIN2]);
    rebuild = rebuild || atomicLoad(&vctl[V_SINCE]) >= atomicLoad(&vctl[V_EVERY]);
    if rebuild {
        atomicStore(&vctl[V_REBUILD], 1u);
        atomicStore(&vctl[V_SINCE], 0u);
        atomicStore(&vctl[V_CAND_STALE], 0u);
        atomicAdd(&vctl[V_REBUILDS], 1u);
    }
    atomicAdd(&vctl[V_SINCE], 1u);
}

@compute @workgroup_size(GROUP_THREADS)
fn track_build(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n || atomicLoad(&vctl[V_REBUILD]) == 0u {
        return;
    }
    let xi = pos[i];
    let r2 = vparams[VP_CAND_R2];
#ifdef MASK_CANDS
    // The candidate mask over the 4 × 4 box (common/mask_lists.wgsl) and the copy of the sort
    // it refers to (the next evaluation's counting sort overwrites `sorted` and `cell_start`).
    cand[CAND_LO_WORDS * params.n + i] = sorted[i];
    let cells = params.grid_nx * params.grid_ny;
    for (var c = i; c <= cells; c += params.n) {
        cand[(CAND_LO_WORDS + 1u) * params.n + c] = cell_start[c];
    }
    var mk: array<u32, CAND_WORDS>;
    var count = 0u;
    var need = 0u;
    var walk = walk_begin(xi, 4u, false);
    while walk_next(&walk) {
        for (var s = walk.s0; s < walk.s1; s++) {
            let d = xi - image_apply(walk.map, pos[slot_at(s, walk.phys)]);
            if d.x * d.x + d.y * d.y < r2 {
                let b = walk.ord + (s - walk.s0);
                if b < 32u * CAND_WORDS {
                    mk[b / 32u] |= 1u << (b % 32u);
                }
                count += 1u;
                need = b + 1u;
            }
        }
    }
    for (var w = 0u; w < CAND_WORDS; w++) {
        set_cand_word(i, w, mk[w]);
    }
    counts[params.n + i] = count;
    ref_pos[i] = xi;
    if need > 32u * CAND_WORDS {
        atomicAdd(&vctl[V_CAND_STALE], 1u);
        atomicMax(&vctl[V_CAND_MAX], need);
        note_overflow(i);
    }
#else
    // Cell size ≥ support and support + skin ≤ 2 cells: the 5×5 block around the cell of the
    // (inversely imaged) query point holds every candidate.
    var count = 0u;
    let phys = physical_order();
    for (var code = 0u; code < 9u; code++) {
        if !image_code_exists(code) {
            continue;
        }
        let map = image_map_of(code);
        let c = cell_coords(image_unapply(map, xi));
        // A block wholly outside the grid holds no cells (common/walk.wgsl passes it over too).
        if c.x + 2 < 0 || c.y + 2 < 0 || c.x - 2 >= i32(params.grid_nx) || c.y - 2 >= i32(params.grid_ny) {
            continue;
        }
        for (var k = 0u; k < 25u; k++) {
            let x = c.x - 2 + i32(k % 5u);
            let y = c.y - 2 + i32(k / 5u);
            if x < 0 || y < 0 || x >= i32(params.grid_nx) || y >= i32(params.grid_ny) {
                continue;
            }
            let cell = u32(x + i32(params.grid_nx) * y);
            // The cell's fluid slots, then its wall slots.
            for (var h = 0u; h < 2u; h++) {
                let a = select(wall_start(cell), cell_start[cell], h == 0u);
                let e = select(wall_start(cell + 1u), cell_start[cell + 1u], h == 0u);
                for (var s = a; s < e; s++) {
                    let j = slot_at(s, phys);
                    let d = xi - image_apply(map, pos[j]);
                    if d.x * d.x + d.y * d.y < r2 {
                        if count < CAND_SLOTS {
                            cand[i * CAND_SLOTS + count] = pack_nb(j, code);
                        }
                        count += 1u;
                    }
                }
            }
        }
    }
    counts[params.n + i] = count;
    ref_pos[i] = xi;
    if count > CAND_SLOTS {
        atomicAdd(&vctl[V_CAND_STALE], 1u);
        atomicMax(&vctl[V_CAND_MAX], count);
        note_overflow(i);
    }
#endif
}

@compute @workgroup_size(1)
fn track_clear() {
    atomicMax(&vctl[V_CAND_OVER], atomicLoad(&vctl[V_CAND_STALE]));
    atomicStore(&vctl[V_REBUILD], 0u);
}
