// reorder.wgsl: cell-ordered particles. Right after the counting sort of search/cell_*.wgsl
// (so `sorted` and `cell_of` describe the current positions), every `EVERY` evaluations (the
// host records these kernels only then; with `TRACKING` the lists are rebuilt then too, next
// in this stage) the fluid particles are renumbered in cell order and every per-particle array that
// persists across stages (pos, vel, phase, colour, mass, vt, acc, the step's start r⁰ and v⁰) is
// gathered into scratch and put back, two vec2 per particle at a time. Fluids stay in
// 0..n_fluid among themselves; walls are static and keep their indices. Within a cell `sorted`
// lists fluids first (it is sorted by index), so the new index of the fluid in slot s of cell c
// is s − (walls in cells < c): the per-cell wall prefix `wall_before` is computed once (walls
// never move) at the first reorder. `orig_of(new)` keeps the permutation for the host
// (`gpu::reorder`), which maps everything it reads or writes back to the original order.
// Per-evaluation fields (σ, χ, ρ, p, ∇C, Π, lists, candidates, accumulators) are recomputed
// after this point, so they do not move, and two of them are the scratch: `counts` (2n words:
// the source index of each new index, then the gathered `orig_of`) and `grad0`, `grad1` (n vec2
// each: two gathered vec2 fields; zeroed at the end, as they are where no colour gradient is
// computed). Twin of `gpu::reorder::{R_*, RBufs}` (group 2, bound only by these pipelines).



#import common/variant_bindings

// One buffer: the reorder pipelines bind groups 0, 1 and 2, and lavapipe allows 32 storage
// buffers per stage (22 + 9 + 1).
@group(2) @binding(0) var<storage, read_write> rctl: array<atomic<u32>>; // R_* words, wall_before (cells + 1), orig_of (n)

// Words of `rctl` (twin of `gpu::reorder::R_*`).
const R_NOW: u32 = 0u;         // unused (each kernel decides: `now()`)
const R_SINCE: u32 = 1u;       // 1 after a renumbering (the host keeps the cadence)
const R_EVERY: u32 = 2u;       // renumber every this many evaluations (0: never; host-written)
const R_COUNT: u32 = 3u;       // renumberings so far
const R_WALLS_READY: u32 = 4u; // 1 once `wall_before` holds the prefix
const R_WALL_BEFORE: u32 = 8u; // rctl[R_WALL_BEFORE + c]: walls in cells < c (after the scan)

// Word of `rctl` holding orig_of[d] (device index d → original index), after the wall prefix.
fn orig_word(d: u32) -> u32 {
    return R_WALL_BEFORE + params.grid_nx * params.grid_ny + 1u + d;
}

// The scratch in `counts` (module comment).
fn src_at(d: u32) -> u32 {           // old device index of new index d (n_fluid)
    return d;
}
fn orig_tmp_at(d: u32) -> u32 {      // orig_of of the particle that gets new index d (n_fluid)
    return params.n + d;
}


// The host records the reorder kernels only in the evaluations they are due (its cadence of
// `EVERY` evaluations), so the decision here is only the veto of a halted device: it keeps its
// numbering, so the failing particle and the state read back map through the permutation of
// that step; nor does one with an overflowing particle noted and not yet read (a midpoint
// step's second evaluation comes before the step's clock tick). None of these words changes
// while the reorder kernels run, so every kernel takes the same decision.
fn now() -> bool {
    return atomicLoad(&rctl[R_EVERY]) > 0u && atomicLoad(&ctl[CTL_BAD_STEP]) == 0xffffffffu
        && atomicLoad(&ctl[CTL_OVER_STEP]) == 0xffffffffu && atomicLoad(&vctl[V_OVER_FIRST]) == 0xffffffffu;
}

// The bookkeeping of a renumbering (one thread of `reorder_perm`): the count and, with
// `TRACKING`, a rebuild of the candidate lists (counted as a build, as `track_every` counts
// one), which `track_build` does next in this stage.
fn renumbering_noted() {
    atomicStore(&rctl[R_SINCE], 1u);
    atomicAdd(&rctl[R_COUNT], 1u);
#ifdef TRACKING
    if atomicLoad(&vctl[V_REBUILD]) == 0u {
        atomicStore(&vctl[V_REBUILD], 1u);
        atomicStore(&vctl[V_SINCE], 1u);
        atomicStore(&vctl[V_CAND_STALE], 0u);
        atomicAdd(&vctl[V_REBUILDS], 1u);
    }
#endif
}

// Walls per cell (once, whatever the decision: walls are static; the host records this and the
// scan only with the first renumbering).
@compute @workgroup_size(GROUP_THREADS)
fn reorder_wall_count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = params.n_fluid + linear_id(gid, nwg);
    if i >= params.n || atomicLoad(&rctl[R_WALLS_READY]) != 0u {
        return;
    }
    atomicAdd(&rctl[R_WALL_BEFORE + cell_of[i]], 1u);
}

// Exclusive prefix of the wall counts (once), by one workgroup: each thread sums a contiguous
// chunk of cells, thread 0 scans the WALL_SCAN partial sums, each thread writes its chunk's
// prefix. A serial loop over every cell passed lavapipe's cap of 65,535 loop iterations per
// invocation group (silently) from 65,536 cells (about a million particles); here a thread
// iterates cells / WALL_SCAN times.
const WALL_SCAN: u32 = 256u;
var<workgroup> wall_part: array<u32, 256>;
var<workgroup> wall_due: u32;

@compute @workgroup_size(256)
fn reorder_wall_scan(@builtin(local_invocation_index) t: u32) {
    // Read by one thread and shared uniformly (the barriers below need every thread).
    if t == 0u {
        wall_due = select(0u, 1u, atomicLoad(&rctl[R_WALLS_READY]) == 0u);
    }
    if workgroupUniformLoad(&wall_due) == 0u {
        return;
    }
    let cells = params.grid_nx * params.grid_ny;
    let chunk = (cells + WALL_SCAN - 1u) / WALL_SCAN;
    let a = min(t * chunk, cells);
    let e = min(a + chunk, cells);
    var s = 0u;
    for (var c = a; c < e; c++) {
        s += atomicLoad(&rctl[R_WALL_BEFORE + c]);
    }
    wall_part[t] = s;
    workgroupBarrier();
    if t == 0u {
        var run = 0u;
        for (var k = 0u; k < WALL_SCAN; k++) {
            let v = wall_part[k];
            wall_part[k] = run;
            run += v;
        }
        atomicStore(&rctl[R_WALL_BEFORE + cells], run);
    }
    workgroupBarrier();
    var run = wall_part[t];
    for (var c = a; c < e; c++) {
        let v = atomicLoad(&rctl[R_WALL_BEFORE + c]);
        atomicStore(&rctl[R_WALL_BEFORE + c], run);
        run += v;
    }
    if t == 0u {
        atomicStore(&rctl[R_WALLS_READY], 1u);
    }
}

// One thread per slot of `sorted`: the new index of its fluid particle; `sorted` is renumbered
// in place (each thread owns its slot), so it stays the cell sort of the new indices.
@compute @workgroup_size(GROUP_THREADS)
fn reorder_perm(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let s = linear_id(gid, nwg);
    if s >= params.n || !now() {
        return;
    }
    if s == 0u {
        renumbering_noted();
    }
    let j = sorted[s];
    if j >= params.n_fluid {
        return;
    }
    let d = s - atomicLoad(&rctl[R_WALL_BEFORE + cell_of[j]]);
    counts[src_at(d)] = j;
    sorted[s] = d;
}

// Gather (into `grad0[d]`, `grad1[d]`) and put back, one pair of fields at a time: each kernel
// puts back the pair gathered by the kernel before and gathers the next (the same thread reads
// grad0[d], grad1[d] before it overwrites them; no kernel writes what it gathers).
fn gather_index(gid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    let d = linear_id(gid, nwg);
    if d >= params.n_fluid || !now() {
        return 0xffffffffu;
    }
    return d;
}

fn gather_state(d: u32) {
    let o = counts[src_at(d)];
    grad0[d] = pos[o];
    grad1[d] = vel[o];
    counts[orig_tmp_at(d)] = atomicLoad(&rctl[orig_word(o)]);
}

fn put_state(d: u32) {
    pos[d] = grad0[d];
    vel[d] = grad1[d];
    atomicStore(&rctl[orig_word(d)], counts[orig_tmp_at(d)]);
}

// Mass, phase and colour (small integers: exact as reals).
fn gather_tags(d: u32) {
    let o = counts[src_at(d)];
    grad0[d] = real2(mass[o], real(phase[o]));
    grad1[d] = real2(real(colour[o]), real(0.0));
}

fn put_tags(d: u32) {
    mass[d] = grad0[d].x;
    phase[d] = u32(grad0[d].y);
    colour[d] = i32(grad1[d].x);
}

// ṽ and a.
fn gather_rates(d: u32) {
    let o = counts[src_at(d)];
    grad0[d] = vt[o];
    grad1[d] = acc[o];
}

fn put_rates(d: u32) {
    vt[d] = grad0[d];
    acc[d] = grad1[d];
}

// The midpoint start state r⁰, v⁰ (live between predict and correct; Verlet's v_{n+½}), then
// the scratch zeroed.
fn gather_start(d: u32) {
    let o = counts[src_at(d)];
    grad0[d] = pos0[o];
    grad1[d] = vel0[o];
}

fn put_start(d: u32) {
    pos0[d] = grad0[d];
    vel0[d] = grad1[d];
    grad0[d] = real2(real(0.0));
    grad1[d] = real2(real(0.0));
}

@compute @workgroup_size(GROUP_THREADS)
fn reorder_gather_state(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = gather_index(gid, nwg);
    if d != 0xffffffffu {
        gather_state(d);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn reorder_put_state_gather_tags(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = gather_index(gid, nwg);
    if d != 0xffffffffu {
        put_state(d);
        gather_tags(d);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn reorder_put_tags_gather_rates(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = gather_index(gid, nwg);
    if d != 0xffffffffu {
        put_tags(d);
        gather_rates(d);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn reorder_put_rates_gather_start(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = gather_index(gid, nwg);
    if d != 0xffffffffu {
        put_rates(d);
        gather_start(d);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn reorder_put_start(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = gather_index(gid, nwg);
    if d != 0xffffffffu {
        put_start(d);
    }
}
