//! Mode A's contact-line force (docs/PHYSICS.md §8.2.1, §8.2.3, §8.2.5): a force `F` per unit
//! length along the wall at each contact point, `(1 − s_w)(σ_GS − σ_LS)` beside the wall bands,
//! the whole `σ_GS − σ_LS` without them, or the unbalanced `σ_GS − σ_LS − σ_LG cos θ_d`, shared among fluid particles near the contact point by weights
//! that sum to one (`contact.line_force_spread`): the kernel of the distance to the point, or
//! the liquid–gas interface where it meets the wall. CPU only (the GPU refuses a scene where it
//! is non-zero).

use super::stages::{colour_slot, Ctx};
use crate::fields::{ContactPoint, Fields};
use crate::neighbours::unpack;
use crate::physics::contact::line_force_of;
use crate::physics::kernel::kernel_w;
use crate::real::{Real, V2};
use crate::scene::LineForceSpread;

/// The weight of fluid particle `i` at contact point `cp`, before normalising: `W(|x_i − x_cp|)`
/// (kernel), or `|∇C_i^{LG}| Σ_{wall j} W_ij` within two supports of the point (interface: the
/// liquid–gas band where the wall's kernel reach cuts it).
#[inline(always)]
fn weight<T: Real>(c: &Ctx<T>, f: &Fields<T>, cp: &ContactPoint<T>, i: usize) -> T {
    let r = (c.pos[i] - cp.r).norm();
    match c.m.line_force_spread {
        LineForceSpread::Kernel => kernel_w(&c.m.kernel, r),
        LineForceSpread::Interface => {
            let k = f.colour[i];
            if r * r >= T::c(4.0) * c.m.support2 || !(k == 0 || k == 1) {
                return T::zero();
            }
            let mut wall = T::zero();
            for &e in c.nbrs.of(i) {
                let (j, code) = unpack(e);
                if j >= c.n_fluid {
                    wall += kernel_w(&c.m.kernel, (c.pos[i] - c.m.images.image_pos(code, c.pos[j])).norm());
                }
            }
            f.grad[i][colour_slot(k, 1 - k)].norm() * wall
        }
    }
}

/// Per contact point, every fluid particle's weight divided by their sum (all zero when none
/// weighs), summed in index order so every execution mode gives the same bits.
pub fn line_force_weights<T: Real>(c: &Ctx<T>, f: &Fields<T>) -> Vec<Vec<T>> {
    f.contacts
        .iter()
        .map(|cp| {
            let mut w: Vec<T> = (0..c.n_fluid).map(|i| weight(c, f, cp, i)).collect();
            let s = w.iter().fold(T::zero(), |a, &x| a + x);
            let inv = if s > T::zero() { T::one() / s } else { T::zero() };
            w.iter_mut().for_each(|x| *x *= inv);
            w
        })
        .collect()
}

/// The line force at contact point `k`: `model.line_force`, less `σ_LG cos θ_d` of the angle
/// measured there under the unbalanced Young force (§8.2.5).
#[inline(always)]
pub fn line_force_at<T: Real>(c: &Ctx<T>, f: &Fields<T>, k: usize) -> T {
    line_force_of(c.m, f.contact_cos.get(k).copied())
}

/// The line-force acceleration of fluid particle `i`: `a_i = Σ_cp F_cp s_cp x̂ w_i^cp / m_i`,
/// with `F_cp` of [`line_force_at`], `w^cp` the normalised weights of [`line_force_weights`] and
/// `s_cp = +1` when the liquid lies on the −x side (so `F > 0` pulls the liquid outwards). The
/// forces of one contact point sum to `F_cp s_cp x̂`.
pub fn line_force_acc<T: Real>(c: &Ctx<T>, f: &Fields<T>, weights: &[Vec<T>], i: usize) -> V2<T> {
    let mut a = V2::zero();
    for (k, (cp, w)) in f.contacts.iter().zip(weights).enumerate() {
        a += V2::new(line_force_at(c, f, k) * cp.s * w[i], T::zero());
    }
    a / f.mass[i]
}
