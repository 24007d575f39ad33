// stress.wgsl: Hu–Adams surface stress tensor (docs/PHYSICS.md §5.3, thesis T73–T74).
// WGSL twin of src/physics/stress.rs (stress_tensor) and of `Sym2` in src/real.rs.
// Library module: functions and structs only (no bindings, no entry points).

// Symmetric traceless 2×2 tensor [[xx, xy], [xy, −xx]] (twin of `Sym2<T>`).
struct Sym2 {
    xx: real,
    xy: real,
}

// Tensor times vector (twin of `Sym2::mul_vec`).
fn sym2_mul_vec(s: Sym2, v: real2) -> real2 {
    return real2(s.xx * v.x + s.xy * v.y, s.xy * v.x - s.xx * v.y);
}

// s · k (twin of `Sym2 * T`).
fn sym2_scale(s: Sym2, k: real) -> Sym2 {
    return Sym2(s.xx * k, s.xy * k);
}

// a + b (twin of `Sym2 + Sym2`).
fn sym2_add(a: Sym2, b: Sym2) -> Sym2 {
    return Sym2(a.xx + b.xx, a.xy + b.xy);
}

// Π = σ (|g|² I/2 − g⊗g)/|g| for a colour gradient g (T73–T74, 2D, traceless):
// Π_xx = σ(g_y² − g_x²)/(2|g|), Π_xy = −σ g_x g_y/|g|. Zero when g = 0.
fn stress_tensor(g: real2, sigma_kl: real) -> Sym2 {
    let n2 = g.x * g.x + g.y * g.y;
    if n2 > real(0.0) {
        let inv = sigma_kl / sqrt(n2);
        return Sym2(real(0.5) * (g.y * g.y - g.x * g.x) * inv, -(g.x * g.y) * inv);
    }
    return Sym2(real(0.0), real(0.0));
}
