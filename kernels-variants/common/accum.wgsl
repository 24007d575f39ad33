// accum.wgsl: atomic accumulation of the block mappings (thesis §6.4.1.1), 4 components per
// particle (σ and χ sums; two colour-gradient slots; acceleration), chosen by define:
// * `ACC_CAS`: compare-and-swap loop on the f32 bits (`atomic<u32>`, portable; f32 only);
// * `ACC_NATIVE`: `atomic<f32>` + atomicAdd (SHADER_FLOAT32_ATOMIC; f32 only);
// * otherwise fixed point: each term is rounded to an integer multiple of the field's quantum
//   q_f (a power of two, vparams[VP_Q + f], chosen on the host from the field's expected
//   magnitude) and added as a 64-bit two's-complement integer held in two u32 words (low word
//   atomicAdd, carry into the high word; the high words in binding 4 unless values are
//   cached). Integer addition is associative, so the result does not depend on the order of
//   the adds: bit-reproducible run to run.
// The host zeroes the buffers before each block stage (0 bits = 0.0 = fixed 0); the finalize
// kernels read it back with `acc_get`. Zero terms are skipped (they change nothing).
// Library module: declares binding 8 of group 1 (its element type depends on the define).

#import common/variant_bindings

#ifdef ACC_NATIVE
@group(1) @binding(8) var<storage, read_write> accum: array<atomic<f32>>;
#else
@group(1) @binding(8) var<storage, read_write> accum: array<atomic<u32>>;
#ifndef ACC_CAS
#ifndef CACHED
// Fixed point without cached kernel values: the high words in binding 4 (which holds the
// cached kernel values otherwise), so neither buffer passes 4 words per particle.
@group(1) @binding(4) var<storage, read_write> accum_hi: array<atomic<u32>>;
#endif
#endif
#endif

const TWO32: f32 = 4294967296.0;

// Word of component c of particle i: in its list chunk's accumulator (split like the list slots
// when they pass one binding, common/variant_bindings; the finalize kernels run per chunk too).
fn acc_word(i: u32, c: u32) -> u32 {
    return 4u * (i - vchunk.base) + c;
}

// Adds v to component c (0..3) of particle i, field group f (F_* of variant_bindings).
fn acc_add(i: u32, c: u32, f: u32, v: real) {
    if v == real(0.0) {
        return;
    }
#ifdef ACC_NATIVE
    atomicAdd(&accum[acc_word(i, c)], v);
#else
#ifdef ACC_CAS
    let a = acc_word(i, c);
    var old = atomicLoad(&accum[a]);
    loop {
        let r = atomicCompareExchangeWeak(&accum[a], old, bitcast<u32>(bitcast<f32>(old) + v));
        if r.exchanged {
            break;
        }
        old = r.old_value;
    }
#else
    // t = round(v/q) (exact scaling: q is a power of two). |t| splits exactly into
    // hi·2³² + lo (lo = the bits of |t| below 2³², a multiple of its ulp), then the sign is
    // applied as a 64-bit two's-complement negation in integers (splitting t itself would need
    // lo = 2³² − small, not representable in f32).
    // Beyond 2⁶² quanta (2¹⁴ times the field's expected scale) the sum could wrap: count it
    // (the host reports the evaluation as invalid) instead of returning wrong numbers.
    let lim = real(4.0e18);
    var t = round(v * vparams[VP_INV_Q + f]);
    if abs(t) > lim {
        atomicAdd(&vctl[V_FIXED_OVER], 1u);
        t = clamp(t, -lim, lim);
    }
    let m = abs(t);
    let mh = floor(m / real(TWO32));
    var lo = u32(m - mh * real(TWO32));
    var hi = u32(mh);
    if t < real(0.0) {
        hi = ~hi + select(0u, 1u, lo == 0u);
        lo = 0u - lo;
    }
#ifdef CACHED
    let a = 2u * acc_word(i, c);
    let old = atomicAdd(&accum[a], lo);
    let carry = select(0u, 1u, old + lo < old);
    atomicAdd(&accum[a + 1u], hi + carry);
#else
    let a = acc_word(i, c);
    let old = atomicAdd(&accum[a], lo);
    let carry = select(0u, 1u, old + lo < old);
    atomicAdd(&accum_hi[a], hi + carry);
#endif
#endif
#endif
}

// The accumulated component c of particle i (field group f).
fn acc_get(i: u32, c: u32, f: u32) -> real {
#ifdef ACC_NATIVE
    return atomicLoad(&accum[acc_word(i, c)]);
#else
#ifdef ACC_CAS
    return real(bitcast<f32>(atomicLoad(&accum[acc_word(i, c)])));
#else
    // Magnitude and sign in integers first (real(hi)·2³² + real(lo) would lose a small
    // negative total to rounding), then one conversion.
#ifdef CACHED
    let a = 2u * acc_word(i, c);
    var lo = atomicLoad(&accum[a]);
    var hi = atomicLoad(&accum[a + 1u]);
#else
    let a = acc_word(i, c);
    var lo = atomicLoad(&accum[a]);
    var hi = atomicLoad(&accum_hi[a]);
#endif
    let neg = bitcast<i32>(hi) < 0;
    if neg {
        hi = ~hi + select(0u, 1u, lo == 0u);
        lo = 0u - lo;
    }
    let m = (real(hi) * real(TWO32) + real(lo)) * vparams[VP_Q + f];
    return select(m, -m, neg);
#endif
#endif
}
