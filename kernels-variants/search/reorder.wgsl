// reorder.wgsl: cell-ordered particles. Right after the counting sort of search/cell_*.wgsl
// (so `sorted` and `cell_of` describe the current positions), every `EVERY` evaluations (and,
// with `TRACKING`, exactly when the tracking lists are rebuilt, which they are next in this
// stage) the fluid particles are renumbered in cell order and every per-particle array that
// persists across stages (pos, vel, phase, colour, mass, vt, acc, state0's r⁰ and v⁰) is
// gathered into scratch and put back. Fluids stay in 0..n_fluid among themselves; walls are
// static and keep their indices. Within a cell `sorted` lists fluids first (it is sorted by
// index), so the new index of the fluid in slot s of cell c is s − (walls in cells < c): the
// per-cell wall prefix `wall_before` is computed once (walls never move) at the first reorder.
// `orig_of[new]` / `new_of[orig]` keep the permutation for the host (`gpu::reorder`), which maps
// everything it reads or writes back to the original order. Per-evaluation fields (σ, χ, ρ, p,
// ∇C, Π, lists, candidates, accumulators) are recomputed after this point, so they do not move.
// Twin of `gpu::reorder::{R_*, RBufs}` (group 2, bound only by these pipelines).

#import common/variant_bindings

// Three buffers only: the reorder pipelines bind groups 0, 1 and 2, and lavapipe allows 32
// storage buffers per stage.
@group(2) @binding(0) var<storage, read_write> rctl: array<atomic<u32>>; // R_* words, then wall_before (cells + 1)
@group(2) @binding(1) var<storage, read_write> ridx: array<u32>;         // orig_of, new_of, src, tmp_u
@group(2) @binding(2) var<storage, read_write> tmp2: array<real2>;       // 3 n_fluid

// Words of `rctl` (twin of `gpu::reorder::R_*`).
const R_NOW: u32 = 0u;         // 1: renumber in this evaluation
const R_SINCE: u32 = 1u;       // evaluations since the last renumbering (starts at EVERY)
const R_EVERY: u32 = 2u;       // renumber every this many evaluations (0: never; host-written)
const R_COUNT: u32 = 3u;       // renumberings so far
const R_WALLS_READY: u32 = 4u; // 1 once `wall_before` holds the prefix
const R_WALL_BEFORE: u32 = 8u; // rctl[R_WALL_BEFORE + c]: walls in cells < c (after the scan)

// Sections of `ridx` (twin of `gpu::reorder::RBufs::new`).
fn orig_at(d: u32) -> u32 {          // orig_of: device index → original (n)
    return d;
}
fn new_at(o: u32) -> u32 {           // new_of: original → device index (n)
    return params.n + o;
}
fn src_at(d: u32) -> u32 {           // old device index of new index d (n_fluid)
    return 2u * params.n + d;
}
fn tmp_u_at(k: u32) -> u32 {         // scratch: phase, colour, orig (3 n_fluid)
    return 2u * params.n + params.n_fluid + k;
}

fn now() -> bool {
    return atomicLoad(&rctl[R_NOW]) != 0u;
}

@compute @workgroup_size(1)
fn reorder_decide() {
    let every = atomicLoad(&rctl[R_EVERY]);
#ifdef TRACKING
    var due = every > 0u && atomicLoad(&vctl[V_REBUILD]) != 0u;
#else
    var due = every > 0u && atomicLoad(&rctl[R_SINCE]) >= every;
#endif
    // A halted device (a failed step, kernels-variants/thread/integrate.wgsl) keeps its numbering,
    // so the failing particle and the state read back map through the permutation of that step.
    if atomicLoad(&ctl[CTL_BAD_STEP]) != 0xffffffffu || atomicLoad(&ctl[CTL_OVER_STEP]) != 0xffffffffu {
        due = false;
    }
    atomicStore(&rctl[R_NOW], select(0u, 1u, due));
    if due {
        atomicStore(&rctl[R_SINCE], 0u);
        atomicAdd(&rctl[R_COUNT], 1u);
    }
    atomicAdd(&rctl[R_SINCE], 1u);
}

// Walls per cell (once: walls are static).
@compute @workgroup_size(64)
fn reorder_wall_count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = params.n_fluid + linear_id(gid, nwg);
    if i >= params.n || !now() || atomicLoad(&rctl[R_WALLS_READY]) != 0u {
        return;
    }
    atomicAdd(&rctl[R_WALL_BEFORE + cell_of[i]], 1u);
}

// Exclusive prefix of the wall counts, one thread (once).
@compute @workgroup_size(1)
fn reorder_wall_scan() {
    if !now() || atomicLoad(&rctl[R_WALLS_READY]) != 0u {
        return;
    }
    let cells = params.grid_nx * params.grid_ny;
    var run = 0u;
    for (var c = 0u; c < cells; c++) {
        let v = atomicLoad(&rctl[R_WALL_BEFORE + c]);
        atomicStore(&rctl[R_WALL_BEFORE + c], run);
        run += v;
    }
    atomicStore(&rctl[R_WALL_BEFORE + cells], run);
    atomicStore(&rctl[R_WALLS_READY], 1u);
}

// One thread per slot of `sorted`: the new index of its fluid particle; `sorted` is renumbered
// in place (each thread owns its slot), so it stays the cell sort of the new indices.
@compute @workgroup_size(64)
fn reorder_perm(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let s = linear_id(gid, nwg);
    if s >= params.n || !now() {
        return;
    }
    let j = sorted[s];
    if j >= params.n_fluid {
        return;
    }
    let d = s - atomicLoad(&rctl[R_WALL_BEFORE + cell_of[j]]);
    ridx[src_at(d)] = j;
    sorted[s] = d;
}

@compute @workgroup_size(64)
fn reorder_gather_state(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = linear_id(gid, nwg);
    let nf = params.n_fluid;
    if d >= nf || !now() {
        return;
    }
    let o = ridx[src_at(d)];
    tmp2[d] = pos[o];
    tmp2[nf + d] = vel[o];
    tmp2[2u * nf + d] = real2(mass[o], real(0.0));
    ridx[tmp_u_at(d)] = phase[o];
    ridx[tmp_u_at(nf + d)] = bitcast<u32>(colour[o]);
    ridx[tmp_u_at(2u * nf + d)] = ridx[orig_at(o)];
}

@compute @workgroup_size(64)
fn reorder_put_state(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = linear_id(gid, nwg);
    let nf = params.n_fluid;
    if d >= nf || !now() {
        return;
    }
    pos[d] = tmp2[d];
    vel[d] = tmp2[nf + d];
    mass[d] = tmp2[2u * nf + d].x;
    phase[d] = ridx[tmp_u_at(d)];
    colour[d] = bitcast<i32>(ridx[tmp_u_at(nf + d)]);
    let o = ridx[tmp_u_at(2u * nf + d)];
    ridx[orig_at(d)] = o;
    ridx[new_at(o)] = d;
}

// ṽ, a and the midpoint start state r⁰, v⁰ (live between predict and correct).
@compute @workgroup_size(64)
fn reorder_gather_rates(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = linear_id(gid, nwg);
    let nf = params.n_fluid;
    if d >= nf || !now() {
        return;
    }
    let o = ridx[src_at(d)];
    tmp2[d] = vt[o];
    tmp2[nf + d] = acc[o];
    tmp2[2u * nf + d] = state0[o];
}

@compute @workgroup_size(64)
fn reorder_put_rates(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = linear_id(gid, nwg);
    let nf = params.n_fluid;
    if d >= nf || !now() {
        return;
    }
    vt[d] = tmp2[d];
    acc[d] = tmp2[nf + d];
    state0[d] = tmp2[2u * nf + d];
}

@compute @workgroup_size(64)
fn reorder_gather_v0(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = linear_id(gid, nwg);
    if d >= params.n_fluid || !now() {
        return;
    }
    tmp2[d] = state0[params.n + ridx[src_at(d)]];
}

@compute @workgroup_size(64)
fn reorder_put_v0(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = linear_id(gid, nwg);
    if d >= params.n_fluid || !now() {
        return;
    }
    state0[params.n + d] = tmp2[d];
}
