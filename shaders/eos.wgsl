// eos.wgsl: Tait / Batchelor equation of state (docs/PHYSICS.md §3, thesis T34–T36).
// WGSL twin of src/physics/eos.rs (eos_pressure). Library module: no bindings, no entry points.
//
// NOTE (arithmetic differs from Rust on purpose): Rust uses `powf(γ)`. Here a whole γ in
// 1..=EOS_MAX_INT_GAMMA (the usual 7, or 1 for the linear EOS) is evaluated by repeated
// multiplication, which is exact to a few ulp on every GPU and is the only option in f64
// (GLSL.std.450 Pow exists for 16/32-bit floats only). A non-integer γ uses `pow`: in f32
// natively, in f64 through an f32 `pow` (so f32 accuracy, ~1e-7 relative, for that case).
// The result B[(ρ/ρ0)^γ − 1] cancels for ρ ≈ ρ0, so compare it against B (ρ/ρ0)^γ + B + |p_b|,
// the size of its terms, not against p itself.

const EOS_MAX_INT_GAMMA: u32 = 16u;

// x^γ: repeated multiplication for whole γ ≤ EOS_MAX_INT_GAMMA, `pow` otherwise (see NOTE).
fn eos_pow(x: real, gamma: real) -> real {
    let n = u32(max(gamma, real(0.0)));
    if real(n) == gamma && n >= 1u && n <= EOS_MAX_INT_GAMMA {
        var p = x;
        for (var k = 1u; k < n; k++) {
            p = p * x;
        }
        return p;
    }
#ifdef F64
    return real(pow(f32(x), f32(gamma)));
#else
    return pow(x, gamma);
#endif
}

// Tait / Batchelor pressure `p = B[(ρ/ρ0)^γ − 1] + p_b` with stiffness `B = ρ0 c0²/γ` (T36).
fn eos_pressure(rho: real, rho0: real, stiffness: real, gamma: real, p_b: real) -> real {
    return stiffness * (eos_pow(rho / rho0, gamma) - real(1.0)) + p_b;
}
