//! Contact-angle geometry of Mode B (docs/PHYSICS.md §8.3–8.4, thesis T81–T83, Algorithms 1–2).
//! CPU twin of `shaders/contact.wgsl`.

use crate::real::{Real, V2};

/// Corrected outward liquid normal at a contact point (T81): `n̂_θ = (s·sin θ, cos θ)`, where
/// `s = +1` when the liquid lies on the −x side of the contact point.
#[inline(always)]
pub fn contact_normal<T: Real>(theta: T, s: T) -> V2<T> {
    V2::new(s * theta.sin(), theta.cos())
}

/// Side test of the interpolation line (T82, robust form):
/// `s_w = (r_w − r_tp)·n̂_θ`; negative means the liquid side.
#[inline(always)]
pub fn contact_side<T: Real>(r_w: V2<T>, r_tp: V2<T>, n_theta: V2<T>) -> T {
    (r_w - r_tp).dot(n_theta)
}

/// Algorithm 1: keep the magnitude of `g`, replace its direction by `±n̂_θ`
/// (`+` for liquid or LIQUID-typed particles, `−` for gas or GAS-typed ones).
#[inline(always)]
pub fn corrected_normal<T: Real>(g: V2<T>, n_theta: V2<T>, liquid: bool) -> V2<T> {
    let m = g.norm();
    if liquid {
        n_theta * m
    } else {
        -(n_theta * m)
    }
}
