//! The momentum stages of the CPU evaluation (docs/PHYSICS.md §12): the pair forces of the
//! acceleration (pressure, viscosity, surface stress, walls, background pressure), the
//! Lennard-Jones boundary repulsion, and XSPH; named as their stages of [`crate::stage::TABLE`].

use super::line_force::{line_force_acc, line_force_weights};
use super::stages::{colour_slot, Ctx};
use crate::exec;
use crate::fields::Fields;
use crate::model::Model;
use crate::neighbours::unpack;
use crate::physics::kernel::{kernel_dwdr, kernel_w};
use crate::physics::pair::*;
use crate::physics::stress::{stress_isotropic, stress_tensor};
use crate::physics::wall::{holmes_beta, lj_wall_acc, noslip_beta, wall_relative_velocity};
use crate::real::{Real, Sym2, V2};
use crate::scene::{ViscousForm, WallVelocity};

/// Lennard-Jones repulsion of the boundary points (spacing Δx/2 on each wall line, r0 = Δx/2);
/// twin of WGSL `lennard_jones` in shaders/geometry.wgsl.
#[inline(always)]
pub fn lennard_jones<T: Real>(m: &Model<T>, x: V2<T>) -> V2<T> {
    let r0 = T::c(0.5) * m.dx;
    let mut a = V2::zero();
    for w in &m.walls {
        if w.wall_distance(x) >= r0 {
            continue;
        }
        let (t, t0) = if w.axis == 0 { (x.y, m.lo.y) } else { (x.x, m.lo.x) };
        let k0 = ((t - t0) / r0).round();
        for dk in [-1.0, 0.0, 1.0] {
            let tb = t0 + (k0 + T::c(dk)) * r0;
            let b = if w.axis == 0 { V2::new(w.coord, tb) } else { V2::new(tb, w.coord) };
            a += lj_wall_acc(x - b, r0, m.lj_strength);
        }
    }
    a
}

/// A term of the pair sum of [`acceleration`], as [`acceleration_pairs`] hands it out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairTerm {
    /// Pressure (T68).
    Pressure,
    /// Viscous (T70, with the wall ghost velocities of §6.2–6.4).
    Viscous,
    /// Surface stress (T76).
    Surface,
    /// The transport-velocity shift a_b (not a force; zero unless `time.background` is a
    /// transport form).
    TransportShift,
    /// The transport-velocity formulation's artificial stress `½(A_i + A_j)·∇_iW_ij` with
    /// `A = ρ v ⊗ (ṽ − v)` (fluid pairs; zero unless `time.background = "transport"`).
    ArtificialStress,
}

/// The pair terms of fluid particle `i`'s acceleration, handed to `sink(j, x_j, term, value)`
/// (`x_j` the partner's position, or its image's) in the
/// order [`acceleration`] sums them. A value is a force on `i` (`m_i a`, per unit depth); the
/// acceleration is their sum over Pressure, Viscous and Surface divided by `m_i`, plus gravity
/// and the Lennard-Jones walls. The one walk over the neighbours, so the force balance
/// (`sphlab::forces::balance`) splits the very sums the solver adds.
#[inline(always)]
pub fn acceleration_pairs<T: Real>(
    c: &Ctx<T>,
    fr: &Fields<T>,
    i: usize,
    mut sink: impl FnMut(usize, V2<T>, PairTerm, V2<T>),
) {
    let m = c.m;
    let kp = m.kernel;
    let st = m.stages;
    let xi = c.pos[i];
    let vi = c.vel[i];
    let inv_s2_i = inv_sigma2(fr.sigma[i]);
    let (pi_i_wall, iso_i_wall) = tensor_towards_wall(m, fr, i);
    let iso = !fr.pi_iso.is_empty();
    let iso_i = if iso { fr.pi_iso[i] } else { T::zero() };
    let eta_i = m.phases[c.phase[i] as usize].eta;
    let wall = m.nearest_wall(xi);
    let d_i = wall.map_or(T::zero(), |w| w.wall_distance(xi));
    // Transport-velocity shift a_b (Adami, Hu & Adams 2013, eq. 13): the pressure term (T68)
    // of a uniform p_b, summed in the same walk.
    let p_b = m.transport_p_b.as_ref().map_or(T::zero(), |p| p[c.phase[i] as usize]);
    // Artificial stress (their eq. 12) from the lagged ṽ − v of the last advection.
    let stress = m.artificial_stress && fr.shift_dv.len() == c.n_fluid;
    for &e in c.nbrs.of(i) {
        let (j, code) = unpack(e);
        let xj = m.images.image_pos(code, c.pos[j]);
        let x_ij = xi - xj;
        let r2 = x_ij.norm2();
        if r2 == T::zero() {
            continue;
        }
        let r = r2.sqrt();
        let dwdr = kernel_dwdr(&kp, r);
        let gw = grad_w_ij(dwdr, x_ij, r);
        let inv_s2_j = inv_sigma2(fr.sigma[j]);
        sink(j, xj, PairTerm::Pressure, pressure_acc_ij(fr.p[i], inv_s2_i, fr.p[j], inv_s2_j, gw));
        if p_b != T::zero() {
            sink(j, xj, PairTerm::TransportShift, pressure_acc_ij(p_b, inv_s2_i, p_b, inv_s2_j, gw));
        }
        if stress && j < c.n_fluid {
            let (v_j, dv_j) = (m.images.image_vec(code, c.vel[j]), m.images.image_vec(code, fr.shift_dv[j]));
            let (a_i, a_j) = (vi * (fr.rho[i] * fr.shift_dv[i].dot(gw)), v_j * (fr.rho[j] * dv_j.dot(gw)));
            sink(j, xj, PairTerm::ArtificialStress, artificial_stress_acc_ij(a_i, inv_s2_i, a_j, inv_s2_j));
        }
        if st.viscosity {
            let fac = viscous_fac_ij(dwdr, r, kp.h);
            let (eta_ij, v_ij) = if j < c.n_fluid {
                let eta_j = m.phases[c.phase[j] as usize].eta;
                (harmonic_viscosity(eta_i, eta_j), vi - m.images.image_vec(code, c.vel[j]))
            } else if let Some(w) = wall {
                let beta = match m.wall_velocity {
                    WallVelocity::Morris => noslip_beta(d_i, -w.wall_distance(xj), m.beta_max, m.dx),
                    WallVelocity::Holmes => holmes_beta(fr.chi[i], fr.chi[j], m.chi_floor, m.beta_max),
                };
                (eta_i, wall_relative_velocity(vi, beta, w.free_slip, w.wall_normal()))
            } else {
                (eta_i, vi)
            };
            let a = match m.viscous_form {
                ViscousForm::Laplacian => viscous_acc_ij(eta_ij, inv_s2_i, inv_s2_j, fac, v_ij),
                ViscousForm::Projected => viscous_projected_acc_ij(eta_ij, inv_s2_i, inv_s2_j, fac, v_ij, x_ij, r2),
            };
            sink(j, xj, PairTerm::Viscous, a);
        }
        if st.surface_tension {
            let (pi_i, s_i) = if j < c.n_fluid { (fr.pi[i], iso_i) } else { (pi_i_wall, iso_i_wall) };
            let mut a = surface_acc_ij(pi_i, inv_s2_i, m.images.image_sym(code, fr.pi[j]), inv_s2_j, gw);
            if iso {
                a += surface_isotropic_acc_ij(s_i, inv_s2_i, fr.pi_iso[j], inv_s2_j, gw);
            }
            sink(j, xj, PairTerm::Surface, a);
        }
    }
}

/// The part of fluid particle `i`'s stress tensor its pairs with wall particles carry, as its
/// traceless part and its isotropic part (zero unless the tangential form): the whole Π_i, or
/// with `contact.liquid_gas_at_wall = "free"` (Mode A, §8.2.2) Π_i less its liquid–gas part, so
/// that the wall pairs take back none of that interface's pull.
#[inline(always)]
fn tensor_towards_wall<T: Real>(m: &Model<T>, fr: &Fields<T>, i: usize) -> (Sym2<T>, T) {
    let k = fr.colour[i];
    let iso = fr.pi_iso.get(i).copied().unwrap_or(T::zero());
    if !m.liquid_gas_free_at_wall || !(k == 0 || k == 1) {
        return (fr.pi[i], iso);
    }
    let (g, sigma) = (fr.grad[i][colour_slot(k, 1 - k)], m.sigma[k as usize][(1 - k) as usize]);
    let iso_lg = if fr.pi_iso.is_empty() { T::zero() } else { stress_isotropic(g, sigma) };
    (fr.pi[i] - stress_tensor(g, sigma), iso - iso_lg)
}

/// `acceleration` (T65): pressure (T68) + viscous (T70, wall ghost velocities §6.2–6.4) +
/// surface (T76) + gravity + optional Lennard-Jones + Mode A's contact-line force (§8.2.1), for
/// fluid particles; the pair sums are those of [`acceleration_pairs`].
pub fn acceleration<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    let fr = &*f;
    let line = (m.line_force != T::zero() || m.young_unbalanced) && !fr.contacts.is_empty();
    let weights = if line { line_force_weights(c, fr) } else { Vec::new() };
    let out: Vec<(V2<T>, V2<T>)> = exec::map(c.exec, c.n_fluid, |i| {
        let (mut sum, mut shift) = (V2::zero(), V2::zero());
        acceleration_pairs(c, fr, i, |_, _, term, v| match term {
            PairTerm::TransportShift => shift += v,
            _ => sum += v,
        });
        let mut a = sum / fr.mass[i] + m.gravity;
        if m.stages.lennard_jones {
            a += lennard_jones(m, c.pos[i]);
        }
        if line {
            a += line_force_acc(c, fr, &weights, i);
        }
        (a, shift / fr.mass[i])
    });
    for (k, (a, _)) in out.iter().enumerate() {
        f.acc[k] = *a;
    }
    f.shift = if m.transport_p_b.is_some() { out.into_iter().map(|o| o.1).collect() } else { Vec::new() };
}

/// `xsph` (T51): ṽ_i = v_i + ε Σ_{j same fluid phase} 2m_j/(ρ_i+ρ_j) (v_j − v_i) W_ij.
pub fn xsph<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    let kp = m.kernel;
    let fr = &*f;
    let vt: Vec<V2<T>> = exec::map(c.exec, c.n_fluid, |i| {
        let mut s = V2::zero();
        for &e in c.nbrs.of(i) {
            let (j, code) = unpack(e);
            if j >= c.n_fluid || c.phase[j] != c.phase[i] {
                continue;
            }
            let xj = m.images.image_pos(code, c.pos[j]);
            let w = kernel_w(&kp, (c.pos[i] - xj).norm());
            let v_ji = m.images.image_vec(code, c.vel[j]) - c.vel[i];
            s += xsph_ij(fr.mass[j], fr.rho[i], fr.rho[j], v_ji, w);
        }
        c.vel[i] + s * m.xsph
    });
    f.vt[..c.n_fluid].copy_from_slice(&vt);
}
