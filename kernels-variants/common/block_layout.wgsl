// block_layout.wgsl: the thesis's one-particle-per-multiple-threads layout (§6.4.1): workgroups of
// 16 × 32 threads, each of the 32 rows (local y) a particle, each of the 16 columns (local x)
// one neighbour slot; 4 workgroups in y cover the 64 slots of the explicit list, N/32 in x
// (spread over x and z beyond the per-dimension limit).
// NOTE: 512 invocations per workgroup exceeds WebGPU's default limit of 256; the context
// requests the adapter's limit and `VariantSpec::support` refuses block variants where it is
// below 512. Shared include of block/atomic.wgsl and block/tree.wgsl; no entry points.

#import common/pair_terms
#import common/accum

const ROWS: u32 = 32u;
const COLS: u32 = 16u;

// Particle of this thread (the particle blocks are spread over x and z: common/dispatch; one
// dispatch per list chunk: common/variant_bindings).
fn block_particle(wg: vec3<u32>, nwg: vec3<u32>, lid: vec3<u32>) -> u32 {
    return chunk_particle(linear_group_xz(wg, nwg) * ROWS + lid.y);
}

// Slot index k (0..63) of this thread in its particle's list.
fn block_k(wg: vec3<u32>, lid: vec3<u32>) -> u32 {
    return wg.y * COLS + lid.x;
}

// True when (i, k) names a list entry.
fn block_has(i: u32, k: u32) -> bool {
    return i < params.n && k < list_len(i);
}

// Per-slot term of number_density (zero when the slot is empty).
fn block_density(i: u32, k: u32) -> real2 {
    if !block_has(i, k) {
        return real2(real(0.0), real(0.0));
    }
    return density_pair(i, params_kernel(params), list_pair(i, pos[i], k));
}

// Per-slot term of colour_gradient.
fn block_gradient(i: u32, k: u32) -> Grad2 {
    if !block_has(i, k) || colour[i] < 0 {
        return Grad2(real2(real(0.0), real(0.0)), real2(real(0.0), real(0.0)));
    }
    return grad_pair(colour[i], params_kernel(params), list_pair(i, pos[i], k));
}

// Per-slot term of acceleration (fluid particles only).
fn block_acceleration(i: u32, k: u32) -> real2 {
    if !block_has(i, k) || i >= params.n_fluid {
        return real2(real(0.0), real(0.0));
    }
    // PERF: every column rebuilds the particle context (a few loads, ≤ 4 walls).
    let c = acc_ctx(i);
    return acc_pair(i, c, params_kernel(params), list_pair(i, c.xi, k));
}
