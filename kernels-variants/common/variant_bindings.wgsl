// variant_bindings.wgsl: bind group 1, the buffers of the strategy variants (twin of
// `VBufs::storage` in src/gpu/variant_buffers.rs, binding k there = binding k here): control
// words, per-variant constants, list and candidate counts, the explicit neighbour lists and
// the tracking candidates (`MASK_LISTS`: bitmasks over the cell walk, common/mask_lists.wgsl;
// otherwise the thesis's 64 slots, packed j | code << 28 like `neighbours::pack`, and 96
// candidate slots), cached kernel values, the tracking reference positions. The accumulator
// (binding 8, and binding 4 for the high words of a fixed-point one without cached values) is
// declared by common/accum.wgsl, since its element type depends on the accumulation. Variants
// that do not use a buffer get a one-element stand-in. Library module: no entry points.

#import common/bindings

@group(1) @binding(0) var<storage, read_write> vctl: array<atomic<u32>>;
@group(1) @binding(1) var<storage, read_write> vparams: array<real>;
@group(1) @binding(2) var<storage, read_write> counts: array<u32>;    // list count (0..n), candidates (n..2n)
@group(1) @binding(3) var<storage, read_write> nbr: array<u32>;       // slot k of i at nbr_slot(i, k)
#ifdef CACHED
@group(1) @binding(4) var<storage, read_write> cache_wf: array<real2>; // (W_ij, F'(r_ij)) per slot
#else
// Binding 4 holds the high words of a fixed-point accumulation (common/accum.wgsl).
#endif
@group(1) @binding(5) var<storage, read_write> cand_hi: array<u32>;    // tracking mask words CAND_LO_WORDS..
@group(1) @binding(6) var<storage, read_write> cand: array<u32>;       // slot k of i at i*CAND_SLOTS + k
@group(1) @binding(7) var<storage, read_write> ref_pos: array<real2>;  // positions at the last build

// The particles whose list slots (`nbr` with slot lists, `cache_wf`) this bind group holds: a
// slot list beyond the adapter's per-binding limit is split by particle into chunks, one
// buffer and one bind group each, and its kernels are dispatched once per chunk (twin of
// `gpu::list_chunks`); one chunk of every particle otherwise.
struct ChunkRange {
    base: u32,
    len: u32,
    pad0: u32,
    pad1: u32,
}
@group(1) @binding(9) var<uniform> vchunk: ChunkRange;

const NBR_SLOTS: u32 = 64u;   // thesis §6.4.1: at most 64 neighbours (4 blocks of 16 threads)
const CAND_SLOTS: u32 = 96u;  // tracking candidates within support + skin
const NBR_WORDS_CELLS: u32 = 6u; // mask words of a list over the 3 × 3 cells (common/mask_lists.wgsl)
const NBR_WORDS_TRACK: u32 = 5u; // mask words of a list over the tracking candidates
const CAND_WORDS: u32 = 9u;      // mask words of the tracking candidates
const CAND_LO_WORDS: u32 = 4u;   // of which in `cand` (the rest in `cand_hi`)
const PACK_SHIFT: u32 = 28u;  // twin of neighbours::IMAGE_SHIFT
const PACK_MASK: u32 = 0x0FFFFFFFu;

// Words of `vctl` (twin of `vctl::*` in src/gpu/variant_buffers.rs).
const V_NBR_OVER: u32 = 0u;   // most particles over NBR_SLOTS neighbours in one evaluation (sticky until read)
const V_NBR_MAX: u32 = 1u;    // largest neighbour count seen
const V_CAND_OVER: u32 = 2u;  // most particles over CAND_SLOTS candidates in one evaluation (sticky until read)
const V_CAND_MAX: u32 = 3u;   // largest candidate count seen
const V_REBUILD: u32 = 4u;    // 1: rebuild the tracking lists in this evaluation
const V_SINCE: u32 = 5u;      // evaluations since the last build
const V_DISP2: u32 = 6u;      // f32 bits of max |x − x_ref|² (this evaluation)
const V_REBUILDS: u32 = 7u;   // builds so far
const V_EVERY: u32 = 8u;      // rebuild at least every this many evaluations (host-written)
const V_FIXED_OVER: u32 = 9u; // fixed-point terms beyond the representable range
const V_CAND_STALE: u32 = 10u; // particles whose current candidate list overflowed (until the next build)
const V_OVER_FIRST: u32 = 11u; // lowest device index whose list overflowed while the device ran (0xFFFFFFFF: none)
const V_NBR_EVAL: u32 = 12u;  // particles over NBR_SLOTS in this evaluation (nbr_fold moves it into V_NBR_OVER)
const V_NBR_NEED: u32 = 13u;  // most mask bits a particle's list needed (MASK_LISTS; past the mask: overflow)
const V_POOL_NEED: u32 = 14u; // most entries a pooled block needed (POOLED_LISTS; past its region: overflow)

// Entries of `vparams` (twin of `vparam::*`).
const VP_INV_Q: u32 = 0u;     // 1/quantum of field f at VP_INV_Q + f (fixed-point accumulation)
const VP_Q: u32 = 4u;         // quantum of field f at VP_Q + f
const VP_CAND_R2: u32 = 8u;   // (support + skin)²
const VP_HALF_SKIN2: u32 = 9u; // (skin / 2)²
const VP_DT: u32 = 12u;       // device clock: dt of the step being taken
const VP_T: u32 = 13u;        // device clock: time t (with the rounding error in VP_T_LO)
const VP_T_LO: u32 = 14u;     // device clock: compensation of t
const VP_CFL: u32 = 16u;      // adaptive dt constants: time.cfl, c_max, ν_max, ρ̄, σ_max
const VP_C_MAX: u32 = 17u;
const VP_NU_MAX: u32 = 18u;
const VP_RHO_MEAN: u32 = 19u;
const VP_SIGMA_MAX: u32 = 20u;
const VP_ADAPTIVE: u32 = 21u;   // 1: adaptive dt (thread/integrate.wgsl `opening_dt`), 0: the host's fixed dt
const VP_PHYSICAL: u32 = 22u;   // 1: particles in physical cell order (slot s = particle s; search/reorder.wgsl)

// Fixed-point field groups (index f above).
const F_DENSITY: u32 = 0u;
const F_GRAD: u32 = 1u;
const F_ACC: u32 = 2u;

// Notes particle i (device index) as overflowing a neighbour or candidate list, unless the
// device has already halted on an earlier failure (then the failing step's particle stays).
fn note_overflow(i: u32) {
    if atomicLoad(&ctl[CTL_BAD_STEP]) == 0xffffffffu && atomicLoad(&ctl[CTL_OVER_STEP]) == 0xffffffffu {
        atomicMin(&vctl[V_OVER_FIRST], i);
    }
}

fn pack_nb(j: u32, code: u32) -> u32 {
    return j | (code << PACK_SHIFT);
}

#ifdef POOLED_LISTS
// Pooled slot lists (`gpu::pooled_lists`): the chunk's particles in blocks of POOL_BLOCK
// share POOL_MEAN entries per particle; a block's region of `nbr` starts with one word per
// particle (its first entry, relative to the region) and `cache_wf` holds each entry's kernel
// values at the same index.
const POOL_BLOCK: u32 = 64u;
const POOL_MEAN: u32 = 48u;
const POOL_REGION: u32 = POOL_BLOCK * (1u + POOL_MEAN);

// The first word of the region of the chunk's particle l.
fn pool_region(l: u32) -> u32 {
    return l / POOL_BLOCK * POOL_REGION;
}
#endif

// Index of list slot k of particle i in its chunk's `nbr` and `cache_wf`: pooled
// (`POOLED_LISTS`: after the particle's first entry in its block's region), slot-major
// (`SLOT_MAJOR`, the thread mapping: neighbouring threads read neighbouring words) or
// particle-major (the block layouts: a row of 16 threads reads 16 consecutive slots of one
// particle).
fn nbr_slot(i: u32, k: u32) -> u32 {
    let l = i - vchunk.base;
#ifdef POOLED_LISTS
    let r = pool_region(l);
    return r + nbr[r + l % POOL_BLOCK] + k;
#else
#ifdef SLOT_MAJOR
    return k * vchunk.len + l;
#else
    return l * NBR_SLOTS + k;
#endif
#endif
}

// The particle of thread (or row) l of a kernel over the list slots, dispatched once per chunk:
// the chunk's particle l, or 0xFFFFFFFF (past every bound) beyond the chunk.
fn chunk_particle(l: u32) -> u32 {
    return select(0xFFFFFFFFu, vchunk.base + l, l < vchunk.len);
}

// `cell_start` holds this search's fluid starts (cells + 1), the last search's (kept for the
// merge) and the walls' static starts (cells + 1, absolute slots from n_fluid; twin of
// `gpu::solver_buffers::wall_cells`).
fn wall_start(c: u32) -> u32 {
    return cell_start[2u * (params.grid_nx * params.grid_ny + 1u) + c];
}

// True while the particles are in physical cell order (read once per walk, not per candidate).
fn physical_order() -> bool {
    return vparams[VP_PHYSICAL] != real(0.0);
}

// The particle in slot s of the sort: s itself in physical cell order (`phys`), else `sorted[s]`.
fn slot_at(s: u32, phys: bool) -> u32 {
    if phys {
        return s;
    }
    return sorted[s];
}

// The transform of image code c (shaders/geometry.wgsl), for an entry whose code changes from
// one to the next (lists, tracking candidates): built from the uniform's two side vectors, with
// no call that takes `Params` by value.
fn image_map_of(c: u32) -> ImageMap {
    return image_map_of_sides(params.image_kind, params.image_value, c);
}

// True when image code c exists in this scene (shaders/geometry.wgsl's `image_exists`, from the
// uniform's side kinds).
fn image_code_exists(c: u32) -> bool {
    return image_exists_of_sides(params.image_kind, c);
}
