// nbr_list.wgsl: the explicit neighbour lists of the block mappings and of the `cached` kernel
// values (thesis §6.4.1 layout: at most NBR_SLOTS = 64 neighbours per particle; bitmasks with
// `MASK_LISTS`, every search with recomputed values), built every
// evaluation from the variant's search (direct, cells or tracking candidates, through
// common/neighbours.wgsl) after the search kernels ran. counts[i] = neighbour count (may exceed
// 64: the particle is then counted in vctl, the lowest such index noted, and the host reports
// `NeighbourOverflow` with that particle and the most particles that overflowed in one
// evaluation — a count of particles, not of particle-evaluations: `nbr_fold` keeps the
// maximum of the per-evaluation counts; no entry
// beyond slot 63 is written and the stages read min(count, 64), so numbers from an overflowing
// evaluation are never returned as valid). With `CACHED` the kernel values W_ij, F'(r_ij) and
// the image position x_j are stored per slot; they stay valid for this evaluation (positions do not change until
// the integrator runs, and the lists are rebuilt at the next evaluation).

#import common/neighbours

#ifdef MASK_LISTS
#ifdef DIRECT
// Walk ordinal of neighbour j under image code `code`, found by the direct search, on the cells
// walk of the 3 × 3 box around x_i over this evaluation's sort (the search's cell sort, run for
// the masks' storage alone; the walls' static sort): j's slot in its cell, then the span of the
// walk that holds it;
// 0xFFFFFFFF when the walk does not hold it (an overflow, reported like one past the mask).
fn direct_ordinal(xi: real2, j: u32, code: u32) -> u32 {
    let c = cell_of[j];
    var slot = 0xFFFFFFFFu;
    let wall = j >= params.n_fluid;
    let a = select(cell_start[c], wall_start(c), wall);
    let e = select(cell_start[c + 1u], wall_start(c + 1u), wall);
    for (var s = a; s < e; s++) {
        if sorted[s] == j {
            slot = s;
            break;
        }
    }
    var walk = walk_begin(xi, 3u, false);
    while walk_next(&walk) {
        if walk.code == code && slot >= walk.s0 && slot < walk.s1 {
            return walk.ord + (slot - walk.s0);
        }
    }
    return 0xFFFFFFFFu;
}
#endif

// A particle's mask while it is built: the words, the entries kept in them, the neighbours
// found and the most mask bits an entry needed (0xFFFFFFFF: one off the walk).
struct Marks {
    mk: array<u32, NBR_WORDS>,
    kept: u32,
    count: u32,
    need: u32,
}

// Counts a neighbour at ordinal b, setting its bit when the mask holds it.
fn mark(m: ptr<function, Marks>, b: u32) {
    if b < 32u * NBR_WORDS {
        (*m).mk[b / 32u] |= 1u << (b % 32u);
        (*m).kept += 1u;
    }
    (*m).count += 1u;
    (*m).need = max((*m).need, select(b + 1u, 0xFFFFFFFFu, b == 0xFFFFFFFFu));
}

// The compact lists (common/mask_lists.wgsl): bit b of i's mask set when walk ordinal b (cells
// and direct: of the 3 × 3 box of this evaluation's sort) or candidate ordinal b (tracking) is a
// neighbour. counts[i] = the entries the mask holds; a particle with more than NBR_SLOTS
// neighbours (the block layouts' 64 slots) or a neighbour past the mask is counted as
// overflowing (V_NBR_NEED: the most mask bits a particle needed).
@compute @workgroup_size(GROUP_THREADS)
fn nbr_build(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i >= params.n {
        return;
    }
    let xi = pos[i];
    var m: Marks;
#ifdef DIRECT
    var it = nb_begin(i, xi);
    while nb_next(&it) {
        mark(&m, direct_ordinal(xi, it.j, it.code));
    }
#else
#ifdef TRACKING
    var it = nb_begin(i, xi);
    while nb_next(&it) {
        mark(&m, it.m);
    }
#else
    var walk = walk_begin(xi, 3u, false);
    while walk_next(&walk) {
        for (var s = walk.s0; s < walk.s1; s++) {
            if nb_hit(xi, slot_at(s, walk.phys), walk.code, walk.map).hit {
                mark(&m, walk.ord + (s - walk.s0));
            }
        }
    }
#endif
#endif
    for (var w = 0u; w < NBR_WORDS; w++) {
        set_nbr_word(i, w, m.mk[w]);
    }
    counts[i] = m.kept;
    if m.count > NBR_SLOTS || m.need > 32u * NBR_WORDS {
        atomicAdd(&vctl[V_NBR_EVAL], 1u);
        atomicMax(&vctl[V_NBR_MAX], m.count);
        atomicMax(&vctl[V_NBR_NEED], m.need);
        note_overflow(i);
    }
}
#else
#ifdef POOLED_LISTS
// Walks i's neighbours at xi in the search's order, writes the first `kept` as list entries at
// `first + k` (its block's region; with `CACHED`, their kernel values at the same index) and
// returns how many there are. The full layout's build keeps its own loop inline: through this
// function the tracking build ran slower on lavapipe (reports/engine/README.md).
fn list_walk(i: u32, xi: real2, first: u32, kept: u32) -> u32 {
#ifdef CACHED
    let kp = params_kernel(params);
#endif
    var count = 0u;
    var sp = nb_spans(i, xi);
    while nb_span(&sp) {
        for (var t = sp.s0; t < sp.s1; t++) {
            let nb = nb_at(sp, t);
            if !nb.hit {
                continue;
            }
            if count < kept {
                let slot = first + count;
                nbr[slot] = pack_nb(nb.j, nb.code);
#ifdef CACHED
                let x_ij = xi - nb.xj;
                let r = sqrt(x_ij.x * x_ij.x + x_ij.y * x_ij.y);
                cache_wf[slot] = real2(kernel_w(kp, r), kernel_dwdr(kp, r));
#endif
            }
            count += 1u;
        }
    }
    return count;
}

// Pooled lists (`gpu::pooled_lists`): a first walk counts each particle's neighbours, a
// prefix sum over the workgroup's blocks of POOL_BLOCK particles places each list in its
// block's region, and a second walk (the same order) writes the entries and their kernel
// values. A particle over NBR_SLOTS, or a block over its region (V_POOL_NEED: the most
// entries a block needed), is an overflow; no entry past the region is written.
var<workgroup> pool_count: array<u32, GROUP_THREADS>;

@compute @workgroup_size(GROUP_THREADS)
fn nbr_build(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_index) t: u32,
) {
    let i = chunk_particle(linear_id(gid, nwg));
    let live = i < params.n;
    let xi = pos[select(0u, i, live)];
    var count = 0u;
    if live {
        count = list_walk(i, xi, 0u, 0u);
    }
    pool_count[t] = min(count, NBR_SLOTS);
    workgroupBarrier();
    var at = POOL_BLOCK;
    for (var u = t - t % POOL_BLOCK; u < t; u++) {
        at += pool_count[u];
    }
    if !live {
        return;
    }
    let l = i - vchunk.base;
    let r = pool_region(l);
    nbr[r + l % POOL_BLOCK] = at;
    let room = select(0u, POOL_REGION - at, at < POOL_REGION);
    _ = list_walk(i, xi, r + at, min(min(count, NBR_SLOTS), room));
    counts[i] = count;
    let need = at + min(count, NBR_SLOTS);
    if count > NBR_SLOTS || need > POOL_REGION {
        atomicAdd(&vctl[V_NBR_EVAL], 1u);
        atomicMax(&vctl[V_NBR_MAX], count);
        atomicMax(&vctl[V_POOL_NEED], need - POOL_BLOCK);
        note_overflow(i);
    }
}
#else
@compute @workgroup_size(GROUP_THREADS)
fn nbr_build(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = chunk_particle(linear_id(gid, nwg));
    if i >= params.n {
        return;
    }
#ifdef CACHED
    let kp = params_kernel(params);
#endif
    let xi = pos[i];
    var count = 0u;
    var sp = nb_spans(i, xi);
    while nb_span(&sp) {
        for (var t = sp.s0; t < sp.s1; t++) {
            let nb = nb_at(sp, t);
            if !nb.hit {
                continue;
            }
            if count < NBR_SLOTS {
                let slot = nbr_slot(i, count);
                nbr[slot] = pack_nb(nb.j, nb.code);
#ifdef CACHED
                let x_ij = xi - nb.xj;
                let r = sqrt(x_ij.x * x_ij.x + x_ij.y * x_ij.y);
                cache_wf[slot] = real2(kernel_w(kp, r), kernel_dwdr(kp, r));
#endif
            }
            count += 1u;
        }
    }
    counts[i] = count;
    if count > NBR_SLOTS {
        atomicAdd(&vctl[V_NBR_EVAL], 1u);
        atomicMax(&vctl[V_NBR_MAX], count);
        note_overflow(i);
    }
}
#endif
#endif

// One thread, after `nbr_build`: this evaluation's overflowing particles into the maximum.
@compute @workgroup_size(1)
fn nbr_fold() {
    atomicMax(&vctl[V_NBR_OVER], atomicLoad(&vctl[V_NBR_EVAL]));
    atomicStore(&vctl[V_NBR_EVAL], 0u);
}
