// reorder.wgsl: particles renumbered in cell order. In the evaluations the host says (a `cells`
// search: every one, so slot s of the sort IS particle s and the neighbour loops read no
// `sorted`, `VP_PHYSICAL`; tracking: every `EVERY` evaluations, then the lists are rebuilt)
// `reorder_sort` / `reorder_merge` replace the search's `cell_sort` / `cell_merge`: one thread
// per cell builds its list (common/cell_lists.wgsl) and writes each of its particles, in that
// order, into its slot of the twin arrays: each per-particle array that persists across the
// search (pos, vel, the step's start r⁰ and v⁰, mass) has a twin the evaluation recomputes
// after the search (grad0, grad1, pi, sigma, rho), and after this pass the host swaps their
// roles (the next passes bind the other group 0); phase and the permutation `orig_of` go into
// `counts` and the host copies them back, the fluids' colour being their phase
// (`GpuSolver::record_renumbered`). No binding is added and no kernel. ṽ and a are outputs of
// every evaluation and are not moved. Fluids stay in 0..n_fluid, walls in n_fluid..n: the first
// renumbering puts the walls in their static sort's order (the host's, `wall_start`), and every
// later one copies them to their own slots. Twin of `gpu::reorder::{R_*, RBufs}` (group 2,
// bound only by these pipelines).

#import common/bindings
#import common/cell_lists

// One buffer: the reorder pipelines bind groups 0, 1 and 2, and lavapipe allows 32 storage
// buffers per stage (22 + 9 + 1).
@group(2) @binding(0) var<storage, read_write> rctl: array<atomic<u32>>; // R_* words, orig_of (n)

// Words of `rctl` (twin of `gpu::reorder::R_*`).
const R_NOW: u32 = 0u;         // unused (each kernel decides: `now()`)
const R_SINCE: u32 = 1u;       // 1 after a renumbering (the host keeps the cadence)
const R_EVERY: u32 = 2u;       // renumber every this many evaluations (0: never; host-written)
const R_COUNT: u32 = 3u;       // renumberings so far
const R_ORIG: u32 = 8u;        // rctl[R_ORIG + d]: orig_of[d], the original index of device index d

// The host records these kernels only in the evaluations they are due, so the decision here is
// only the veto of a halted device: it keeps its numbering (every particle is copied to its
// own slot), so the failing particle and the state read back map through the permutation of
// that step; nor does one with an overflowing particle noted and not yet read (a midpoint
// step's second evaluation comes before the step's clock tick). None of these words changes
// while the reorder kernels run, so every thread takes the same decision.
fn now() -> bool {
    return atomicLoad(&rctl[R_EVERY]) > 0u && atomicLoad(&ctl[CTL_BAD_STEP]) == 0xffffffffu
        && atomicLoad(&ctl[CTL_OVER_STEP]) == 0xffffffffu && atomicLoad(&vctl[V_OVER_FIRST]) == 0xffffffffu;
}

// The bookkeeping of a renumbering (one thread): the count and, with `TRACKING`, a rebuild of
// the candidate lists (counted as a build, as `track_every` counts one), which `track_build`
// does next in this stage.
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

// Particle j into slot s of the twins (twin of `GpuSolver::record_renumbered`): r → grad0,
// v → grad1, r⁰ → pi, v⁰ → sigma, m → rho, and in `counts` (2n words) phase and orig_of. A
// fluid's colour is its phase (the host copies the phases over the fluids' colours); the walls'
// colour is the same for every wall, or typed again by every evaluation (Mode A's wall typing).
fn to_scratch(s: u32, j: u32) {
    grad0[s] = pos[j];
    grad1[s] = vel[j];
    pi[s] = pos0[j];
    sigma[s] = vel0[j];
    rho[s] = mass[j];
    counts[s] = phase[j];
    counts[params.n + s] = atomicLoad(&rctl[R_ORIG + j]);
}

// Slot s gets the particle the sort put there (its own when vetoed), and holds it from now on.
fn renumber_slot(s: u32, due: bool) {
    if due {
        to_scratch(s, sorted[s]);
        sorted[s] = s;
    } else {
        to_scratch(s, s);
    }
}

// Cell c's fluid slots, then its wall slots (the walls' static sort: the first renumbering
// puts the walls in its order, every later one keeps them where they are).
fn renumber_cell(c: u32) {
    let due = now();
    if c == 0u && due {
        renumbering_noted();
    }
    for (var s = cell_start[c]; s < cell_start[c + 1u]; s++) {
        renumber_slot(s, due);
    }
    for (var s = wall_start(c); s < wall_start(c + 1u); s++) {
        renumber_slot(s, due);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn reorder_sort(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let c = linear_id(gid, nwg);
    if c < params.grid_nx * params.grid_ny {
        sort_cell(c);
        renumber_cell(c);
    }
}

@compute @workgroup_size(GROUP_THREADS)
fn reorder_merge(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let c = linear_id(gid, nwg);
    if c < params.grid_nx * params.grid_ny {
        merge_cell(c);
        renumber_cell(c);
    }
}
