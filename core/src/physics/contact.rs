//! Contact-angle geometry of Mode B (docs/PHYSICS.md §8.3–8.4, thesis T81–T83, Algorithms 1–2),
//! CPU twin of `shaders/contact.wgsl`, and Mode A's line force at a contact point (§8.2.1,
//! §8.2.5), which both executors take from here.

use crate::fields::ContactPoint;
use crate::model::Model;
use crate::physics::kernel::kernel_w;
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

/// The line force of `m` at a contact point whose measured cos θ_d is `cos` (None: no angle
/// measured there, `model.line_force`).
#[inline(always)]
pub fn line_force_of<T: Real>(m: &Model<T>, cos: Option<T>) -> T {
    cos.map_or(m.line_force, |cos| m.line_force - m.sigma[0][1] * cos)
}

/// The cos θ at which the unbalanced Young force of `m` is zero, (σ_GS − σ_LS)/σ_LG: where the
/// angle cannot be measured the line is left there, at rest (zero without a liquid–gas tension).
pub fn rest_cos<T: Real>(m: &Model<T>) -> T {
    let sigma_lg = m.sigma[0][1];
    if sigma_lg > T::zero() {
        m.line_force / sigma_lg
    } else {
        T::zero()
    }
}

/// The line force of contact point `cp` per unit of the kernel spread's weight, `F s / Σ_i
/// W(|x_i − x_cp|)` over the fluid positions `fluid` (zero when no particle weighs): what
/// the GPU's contact list carries for the acceleration to spread (kernels-variants/thread/
/// contact_angle.wgsl).
pub fn line_force_per_weight<T: Real>(m: &Model<T>, cp: &ContactPoint<T>, cos: Option<T>, fluid: &[V2<T>]) -> T {
    let total = fluid.iter().fold(T::zero(), |a, &p| a + kernel_w(&m.kernel, (p - cp.r).norm()));
    if total > T::zero() {
        line_force_of(m, cos) * cp.s / total
    } else {
        T::zero()
    }
}
