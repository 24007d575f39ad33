//! Hu–Adams surface stress tensor (docs/PHYSICS.md §5.3, thesis T73–T74).
//! CPU twin of `shaders/stress.wgsl`.

use crate::real::{Real, Sym2, V2};

/// `Π^{kl} = σ^{kl} (|g|² I/2 − g⊗g)/|g|` for a colour gradient `g` (2D, traceless):
/// `Π_xx = σ(g_y² − g_x²)/(2|g|)`, `Π_xy = −σ g_x g_y/|g|`. Zero when `g = 0`.
#[inline(always)]
pub fn stress_tensor<T: Real>(g: V2<T>, sigma_kl: T) -> Sym2<T> {
    let n2 = g.norm2();
    if n2 > T::zero() {
        let inv = sigma_kl / n2.sqrt();
        Sym2 { xx: T::c(0.5) * (g.y * g.y - g.x * g.x) * inv, xy: -(g.x * g.y) * inv }
    } else {
        Sym2::zero()
    }
}

/// The isotropic part `σ^{kl}|g|/2` that `surface_tension.tensor = "tangential"` adds to
/// [`stress_tensor`], so that `Π + sI = σ^{kl}|g|(I − n̂n̂)` (docs/PHYSICS.md §5.3): a tension
/// `σ^{kl}|g|` along the interface and none across it. Zero when `g = 0`. CPU only.
#[inline(always)]
pub fn stress_isotropic<T: Real>(g: V2<T>, sigma_kl: T) -> T {
    T::c(0.5) * sigma_kl * g.norm2().sqrt()
}
