//! The stages of one force evaluation on the CPU (docs/PHYSICS.md §12), one function per stage of
//! [`crate::stage::TABLE`], named as the stage. Every stage is a
//! gather over the neighbour list of each particle, so `Exec::Serial` and `Exec::Parallel`
//! give identical bits. Boundary images enter through `model.images`.

use super::contact_angle::measured_contact_cos;
use super::momentum::{acceleration, xsph};
use crate::exec::{self, Exec};
pub use crate::fields::{ContactPoint, Fields};
use crate::model::{Model, COLOUR_WALL, MAX_CONTACTS, NO_COLOUR, SIDE_WALL_HALF_DX};
use crate::neighbours::{unpack, NeighbourList};
use crate::physics::contact::rest_cos;
use crate::physics::contact::{contact_normal, contact_side, corrected_normal};
use crate::physics::eos::eos_pressure;
use crate::physics::kernel::{kernel_dwdr, kernel_w};
use crate::physics::pair::*;
use crate::physics::stress::{stress_isotropic, stress_tensor};
use crate::real::{Real, Sym2, V2};
use crate::scene::ContactMode;
use crate::stage::Stage;

/// A CPU evaluation stage: reads the context, updates the fields.
pub type StageFn<T> = fn(&Ctx<T>, &mut Fields<T>);

/// The CPU function of an evaluation stage of [`crate::stage::TABLE`] (each named as its stage);
/// `None` for the neighbour search (the solver's `Search::update`) and the step stages (methods
/// of `CpuSolver`).
pub fn evaluation_fn<T: Real>(stage: Stage) -> Option<StageFn<T>> {
    Some(match stage {
        Stage::NumberDensity => number_density,
        Stage::ContactLine => contact_line,
        Stage::WallTyping => wall_typing,
        Stage::EquationOfState => equation_of_state,
        Stage::WallPressure => wall_pressure,
        Stage::ColourGradient => colour_gradient,
        Stage::NormalCorrection => normal_correction,
        Stage::SurfaceStress => surface_stress,
        Stage::Acceleration => acceleration,
        Stage::Xsph => xsph,
        _ => return None,
    })
}

/// The nearest particle found so far on one side: (distance key, index).
type Nearest<T> = Option<(T, u32)>;

/// Read-only inputs shared by the stages.
pub struct Ctx<'a, T> {
    /// Constants.
    pub m: &'a Model<T>,
    /// Positions.
    pub pos: &'a [V2<T>],
    /// Velocities.
    pub vel: &'a [V2<T>],
    /// Fluid phase or WALL.
    pub phase: &'a [u32],
    /// Fluid particles come first.
    pub n_fluid: usize,
    /// Neighbour lists.
    pub nbrs: &'a NeighbourList,
    /// Execution mode.
    pub exec: Exec,
}

/// Slot of colour `l` among the others of colour `k`.
#[inline(always)]
pub fn colour_slot(k: i32, l: i32) -> usize {
    if l < k {
        l as usize
    } else {
        (l - 1) as usize
    }
}

/// The other colour held in `slot` for colour `k`.
#[inline(always)]
pub fn slot_colour(k: i32, slot: usize) -> i32 {
    if (slot as i32) < k {
        slot as i32
    } else {
        slot as i32 + 1
    }
}

/// `number_density`: σ_i = Σ_j W_ij, self and images included (T66); χ_i (T46–T48) when active.
pub fn number_density<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let kp = c.m.kernel;
    let holmes = c.m.stages.holmes_chi;
    let out: Vec<(T, T)> = exec::map(c.exec, c.pos.len(), |i| {
        let (mut s, mut same) = (T::zero(), T::zero());
        let fluid_i = i < c.n_fluid;
        for &e in c.nbrs.of(i) {
            let (j, code) = unpack(e);
            let r = (c.pos[i] - c.m.images.image_pos(code, c.pos[j])).norm();
            let w = kernel_w(&kp, r);
            s += w;
            if holmes && (j < c.n_fluid) == fluid_i {
                same += w;
            }
        }
        (s, if holmes { same / s } else { T::zero() })
    });
    for (i, (s, chi)) in out.into_iter().enumerate() {
        f.sigma[i] = s;
        f.chi[i] = chi;
    }
}

/// Static colours and masses: fluids by phase; walls S in Mode A, uncoloured otherwise, with the
/// mass of the reference wall phase. `wall_typing` overwrites the walls in Mode B.
pub fn assign_colours<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    for i in 0..c.pos.len() {
        if i < c.n_fluid {
            f.colour[i] = c.phase[i] as i32;
            f.mass[i] = c.m.phases[c.phase[i] as usize].mass;
        } else {
            f.colour[i] = if c.m.contact_mode == ContactMode::A { COLOUR_WALL } else { NO_COLOUR };
            f.mass[i] = c.m.phases[c.m.wall_phase].mass;
        }
    }
}

#[inline(always)]
fn in_band<T: Real>(m: &Model<T>, y: T) -> bool {
    let d = y - m.y_wall;
    d > T::zero() && d <= m.band
}

/// True when a side wall (a wall line across x) faces `p` on the side `side` (+1: +x) nearer
/// than [`SIDE_WALL_HALF_DX`] half Δx: a band particle with no band neighbour on that side then
/// meets the wall, it is no free edge (§8.4 step 2). Twin of `at_side_wall` in
/// kernels-variants/thread/contact_line.wgsl.
#[inline(always)]
pub fn at_side_wall<T: Real>(m: &Model<T>, p: V2<T>, side: T) -> bool {
    let reach = T::c(0.5 * SIDE_WALL_HALF_DX as f64) * m.dx;
    m.walls.iter().any(|w| w.axis == 0 && w.sign * side < T::zero() && w.wall_distance(p) < reach)
}

/// `contact_line`: contact points of the liquid (phase 0) in the first-row band (§8.4 step 2).
/// For each liquid band particle, its predecessor and successor are the nearest band particles
/// (images included) on either side among its neighbours; a gas neighbour there makes a contact
/// point at the midpoint, no neighbour at all a point Δx/2 beyond the particle (a free edge),
/// unless a side wall stands there ([`at_side_wall`]). The point lies on
/// the wall surface (docs/PHYSICS.md §8 ambiguity 2): anchoring the line at the first row's height or
/// at a particle centre moved relax-60's equilibrium by less than the run-to-run scatter
/// (`reports/validation/relax-60/anchor-check/README.md`).
pub fn contact_line<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    let half = T::c(0.5);
    let found: Vec<Vec<ContactPoint<T>>> = exec::map(c.exec, c.n_fluid, |i| {
        if c.phase[i] != 0 || !in_band(m, c.pos[i].y) {
            return Vec::new();
        }
        let xi = c.pos[i].x;
        let (mut pred, mut succ): (Nearest<T>, Nearest<T>) = (None, None);
        for &e in c.nbrs.of(i) {
            let (j, code) = unpack(e);
            if j >= c.n_fluid {
                continue;
            }
            let pj = m.images.image_pos(code, c.pos[j]);
            if !in_band(m, pj.y) {
                continue;
            }
            if pj.x > xi && succ.is_none_or(|(x, _)| pj.x < x) {
                succ = Some((pj.x, c.phase[j]));
            }
            if pj.x < xi && pred.is_none_or(|(x, _)| pj.x > x) {
                pred = Some((pj.x, c.phase[j]));
            }
        }
        let mut out = Vec::new();
        let free_edge = |side: T| !at_side_wall(m, c.pos[i], side);
        match succ {
            None if free_edge(T::one()) => {
                out.push(ContactPoint { r: V2::new(xi + half * m.dx, m.y_wall), s: T::one() })
            }
            Some((x, ph)) if ph != 0 => out.push(ContactPoint { r: V2::new(half * (xi + x), m.y_wall), s: T::one() }),
            _ => {}
        }
        match pred {
            None if free_edge(-T::one()) => {
                out.push(ContactPoint { r: V2::new(xi - half * m.dx, m.y_wall), s: -T::one() })
            }
            Some((x, ph)) if ph != 0 => out.push(ContactPoint { r: V2::new(half * (xi + x), m.y_wall), s: -T::one() }),
            _ => {}
        }
        out
    });
    let mut all: Vec<ContactPoint<T>> = found.into_iter().flatten().collect();
    all.sort_by(|a, b| {
        a.r.x
            .partial_cmp(&b.r.x)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(a.s.partial_cmp(&b.s).unwrap_or(std::cmp::Ordering::Equal))
    });
    f.contact_overflow = all.len().saturating_sub(MAX_CONTACTS);
    all.truncate(MAX_CONTACTS);
    f.contact_cos = if m.young_unbalanced {
        // Where the angle cannot be measured the line is left at rest: cos θ_d = cos θ_Y.
        all.iter().map(|cp| measured_contact_cos(c, cp).unwrap_or_else(|| rest_cos(m))).collect()
    } else {
        Vec::new()
    };
    f.contacts = all;
}

/// The outward liquid normal the typed wall and Algorithm 1 use at contact point `k`: n̂_θ of
/// the scene's θ_d (T81), or of the angle measured there (§8.2.5).
#[inline(always)]
fn typing_normal<T: Real>(m: &Model<T>, f: &Fields<T>, k: usize) -> V2<T> {
    let cp = &f.contacts[k];
    match f.contact_cos.get(k) {
        Some(&cos) => V2::new(cp.s * (T::one() - cos * cos).max(T::zero()).sqrt(), cos),
        None => contact_normal(m.theta, cp.s),
    }
}

/// The contact point nearest to `r`, the first in (x, s) order on ties whatever the order of
/// `contacts` (the GPU's are in the order they were found).
#[inline(always)]
pub fn nearest_contact<T: Real>(contacts: &[ContactPoint<T>], r: V2<T>) -> Option<&ContactPoint<T>> {
    nearest_contact_index(contacts, r).map(|k| &contacts[k])
}

/// The index in `contacts` of [`nearest_contact`].
pub fn nearest_contact_index<T: Real>(contacts: &[ContactPoint<T>], r: V2<T>) -> Option<usize> {
    let mut best: Option<usize> = None;
    let mut bd = T::infinity();
    for (k, cp) in contacts.iter().enumerate() {
        let d = (r - cp.r).norm2();
        let before = |b: usize| cp.r.x < contacts[b].r.x || (cp.r.x == contacts[b].r.x && cp.s < contacts[b].s);
        if d < bd || (d == bd && best.is_some_and(before)) {
            bd = d;
            best = Some(k);
        }
    }
    best
}

/// `wall_typing` (Algorithm 2): bottom-wall particles (y < y_w) take the liquid or gas colour
/// by the side of the interpolation line through the nearest contact point; mass per T83.
/// Without a contact point every wall is untyped (neutral).
pub fn wall_typing<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    for i in c.n_fluid..c.pos.len() {
        let mut colour = NO_COLOUR;
        if c.pos[i].y < m.y_wall {
            if let Some(k) = nearest_contact_index(&f.contacts, c.pos[i]) {
                let n = typing_normal(m, f, k);
                colour = if contact_side(c.pos[i], f.contacts[k].r, n) < T::zero() { 0 } else { 1 };
            }
        }
        f.colour[i] = colour;
        f.mass[i] = m.phases[if colour >= 0 { colour as usize } else { m.wall_phase }].mass;
    }
}

/// Phase whose EOS a particle uses: its fluid phase, a wall's typed phase, or the wall phase.
#[inline(always)]
pub fn eos_phase<T: Real>(m: &Model<T>, i: usize, n_fluid: usize, phase: &[u32], colour: &[i32]) -> usize {
    if i < n_fluid {
        phase[i] as usize
    } else if colour[i] == 0 || colour[i] == 1 {
        colour[i] as usize
    } else {
        m.wall_phase
    }
}

/// `equation_of_state`: ρ = mσ and the Tait pressure for every particle (T-wall for walls).
pub fn equation_of_state<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    for i in 0..c.pos.len() {
        let ph = &c.m.phases[eos_phase(c.m, i, c.n_fluid, c.phase, &f.colour)];
        f.rho[i] = f.mass[i] * f.sigma[i];
        f.p[i] = eos_pressure(f.rho[i], ph.rho0, ph.stiffness, ph.gamma, ph.p_b);
    }
}

/// `wall_pressure` (R-wall, Adami 2012): `p_w = [Σ_f p_f W + g·Σ_f ρ_f (r_w − r_f) W] / Σ_f W`.
pub fn wall_pressure<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    let kp = m.kernel;
    let pw: Vec<T> = exec::map(c.exec, c.pos.len() - c.n_fluid, |k| {
        let i = c.n_fluid + k;
        let (mut num, mut den) = (T::zero(), T::zero());
        for &e in c.nbrs.of(i) {
            let (j, code) = unpack(e);
            if j >= c.n_fluid {
                continue;
            }
            let xj = m.images.image_pos(code, c.pos[j]);
            let w = kernel_w(&kp, (c.pos[i] - xj).norm());
            num += (f.p[j] + m.gravity.dot(c.pos[i] - xj) * f.rho[j]) * w;
            den += w;
        }
        if den > T::zero() {
            num / den
        } else {
            m.phases[m.wall_phase].p_b
        }
    });
    f.p[c.n_fluid..].copy_from_slice(&pw);
}

/// `colour_gradient` (T71): for each coloured particle, `σ_i Σ_{j of colour l} ∇_iW_ij/σ_j²`
/// towards every other colour l with σ^{kl} > 0, stored by slot; or the single-field form
/// ([`single_field_gradient`]) when the scene selects it.
pub fn colour_gradient<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    let kp = m.kernel;
    let (colour, sigma) = (&f.colour, &f.sigma);
    let out: Vec<[V2<T>; 2]> = exec::map(c.exec, c.pos.len(), |i| {
        let k = colour[i];
        let mut g = [V2::zero(); 2];
        if k < 0 {
            return g;
        }
        if m.single_field_colour {
            return single_field_gradient(c, colour, sigma, i);
        }
        for &e in c.nbrs.of(i) {
            let (j, code) = unpack(e);
            let l = colour[j];
            if l < 0 || l == k || m.sigma[k as usize][l as usize] == T::zero() {
                continue;
            }
            let x_ij = c.pos[i] - m.images.image_pos(code, c.pos[j]);
            let r = x_ij.norm();
            let gw = grad_w_ij(kernel_dwdr(&kp, r), x_ij, r);
            g[colour_slot(k, l)] += colour_gradient_ij(inv_sigma2(sigma[j]), gw);
        }
        [g[0] * sigma[i], g[1] * sigma[i]]
    });
    f.grad = out;
}

/// The single-field colour gradient of a coloured particle (PySPH's `ColorGradientAdami`):
/// `σ_i Σ_j (C_i/σ_i² + C_j/σ_j²) ∇_iW_ij` over every neighbour, C = 1 for colour 0 (the
/// liquid) and 0 for anything else, walls included. Stored in slot 0, which for colours 0 and 1
/// is the slot of the liquid–gas pair, so the stress stage uses σ_LG.
fn single_field_gradient<T: Real>(c: &Ctx<T>, colour: &[i32], sigma: &[T], i: usize) -> [V2<T>; 2] {
    let kp = c.m.kernel;
    let col = |k: i32| if k == 0 { T::one() } else { T::zero() };
    let (c_i, inv_s2_i) = (col(colour[i]), inv_sigma2(sigma[i]));
    let mut g = V2::zero();
    for &e in c.nbrs.of(i) {
        let (j, code) = unpack(e);
        let x_ij = c.pos[i] - c.m.images.image_pos(code, c.pos[j]);
        let r = x_ij.norm();
        let gw = grad_w_ij(kernel_dwdr(&kp, r), x_ij, r);
        g += colour_gradient_single_ij(c_i, inv_s2_i, col(colour[j]), inv_sigma2(sigma[j]), gw);
    }
    [g * sigma[i], V2::zero()]
}

/// `normal_correction` (Algorithm 1): near the wall (fluid with y − y_w ≤ 1.2Δx, or a typed wall
/// particle) the gradient towards the other fluid keeps its magnitude and takes the direction
/// ±n̂_θ of the nearest contact point. The band holds the first row only (ambiguity 3), with no
/// κh restriction (ambiguity 4); correcting two rows stops relax-60 further from 60°, the
/// restriction changes nothing measurable (`reports/validation/relax-60/anchor-check/`).
pub fn normal_correction<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    if f.contacts.is_empty() {
        return;
    }
    for i in 0..c.pos.len() {
        let k = f.colour[i];
        if !(k == 0 || k == 1) || f.grad[i][0].norm2() == T::zero() {
            continue;
        }
        let near = if i < c.n_fluid { c.pos[i].y - m.y_wall <= m.band } else { true };
        if !near {
            continue;
        }
        let cp = nearest_contact_index(&f.contacts, c.pos[i]).expect("contacts non-empty");
        f.grad[i][0] = corrected_normal(f.grad[i][0], typing_normal(m, f, cp), k == 0);
    }
}

/// `surface_stress` (T73–T75): Π_i = Σ_l σ^{kl} |g^{kl}| (I/2 − n̂n̂); with
/// `surface_tension.tensor = "tangential"` also its isotropic part s_i = Σ_l σ^{kl}|g^{kl}|/2
/// (§5.3), so that Π_i + s_i I = Σ_l σ^{kl}|g^{kl}|(I − n̂n̂).
pub fn surface_stress<T: Real>(c: &Ctx<T>, f: &mut Fields<T>) {
    let m = c.m;
    let n = c.pos.len();
    if m.tangential_stress {
        f.pi_iso.resize(n, T::zero());
    }
    for i in 0..n {
        let k = f.colour[i];
        let (mut pi, mut iso) = (Sym2::zero(), T::zero());
        if k >= 0 {
            for slot in 0..2 {
                let l = slot_colour(k, slot);
                if (l as usize) < crate::model::N_COLOURS {
                    let sigma_kl = m.sigma[k as usize][l as usize];
                    pi = pi + stress_tensor(f.grad[i][slot], sigma_kl);
                    if m.tangential_stress {
                        iso += stress_isotropic(f.grad[i][slot], sigma_kl);
                    }
                }
            }
        }
        f.pi[i] = pi;
        if m.tangential_stress {
            f.pi_iso[i] = iso;
        }
    }
}
