//! Mode A's contact-line force (docs/PHYSICS.md §8.2.1): the part `(1 − s_w)(σ_GS − σ_LS)` of
//! the wall traction that the wall bands hand to the fixed wall particles instead of the fluid,
//! put back on the fluid within the kernel's reach of each contact point. CPU only (the GPU
//! refuses a scene where it is non-zero).

use super::stages::Ctx;
use crate::fields::ContactPoint;
use crate::physics::kernel::kernel_w;
use crate::real::{Real, V2};

/// The kernel weight of fluid particle `x` at contact point `cp`.
#[inline(always)]
fn weight<T: Real>(c: &Ctx<T>, cp: &ContactPoint<T>, x: V2<T>) -> T {
    kernel_w(&c.m.kernel, (x - cp.r).norm())
}

/// Per contact point, `1/Σ_k W(|x_k − x_cp|)` over the fluid particles k (zero when none is in
/// reach), summed in index order so every execution mode gives the same bits.
pub fn line_force_norms<T: Real>(c: &Ctx<T>, contacts: &[ContactPoint<T>]) -> Vec<T> {
    contacts
        .iter()
        .map(|cp| {
            let mut s = T::zero();
            for i in 0..c.n_fluid {
                s += weight(c, cp, c.pos[i]);
            }
            if s > T::zero() {
                T::one() / s
            } else {
                T::zero()
            }
        })
        .collect()
}

/// The line-force acceleration of fluid particle `i`:
/// `a_i = Σ_cp F s_cp x̂ W(|x_i − x_cp|) / (m_i Σ_k W(|x_k − x_cp|))`, with `F` = `model.line_force`
/// and `s_cp = +1` when the liquid lies on the −x side (so `F > 0` pulls the liquid outwards).
/// The forces of one contact point sum to `F s_cp x̂`.
pub fn line_force_acc<T: Real>(c: &Ctx<T>, contacts: &[ContactPoint<T>], norms: &[T], i: usize, mass: T) -> V2<T> {
    let mut a = V2::zero();
    for (cp, &inv) in contacts.iter().zip(norms) {
        let w = weight(c, cp, c.pos[i]) * inv;
        a += V2::new(c.m.line_force * cp.s * w, T::zero());
    }
    a / mass
}
