//! The per-evaluation state both backends share: [`Fields`] (σ, χ, mass, colour, ρ, p, colour
//! gradients, Π, acceleration, ṽ, contact points), the CPU reference's and the GPU's read-back
//! alike, and [`Field`], the name of one of them (stage inputs and outputs in
//! [`crate::stage`], columns and tolerances in [`crate::verify`]).

use crate::model::NO_COLOUR;
use crate::real::{Real, Sym2, V2};

/// One per-evaluation field, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Field {
    /// Number density σ.
    Sigma,
    /// Holmes χ.
    Chi,
    /// Mass.
    Mass,
    /// Colour index.
    Colour,
    /// Density.
    Rho,
    /// Pressure.
    P,
    /// Colour-gradient slots.
    Grad,
    /// Surface stress.
    Pi,
    /// Acceleration (fluids).
    Acc,
    /// Advection velocity (fluids).
    Vt,
    /// Contact points.
    Contacts,
}

impl Field {
    /// Every field.
    pub const ALL: [Field; 11] = [
        Field::Sigma,
        Field::Chi,
        Field::Mass,
        Field::Colour,
        Field::Rho,
        Field::P,
        Field::Grad,
        Field::Pi,
        Field::Acc,
        Field::Vt,
        Field::Contacts,
    ];

    /// Its name in reports and CSV columns.
    pub fn name(self) -> &'static str {
        match self {
            Field::Sigma => "sigma",
            Field::Chi => "chi",
            Field::Mass => "mass",
            Field::Colour => "colour",
            Field::Rho => "rho",
            Field::P => "p",
            Field::Grad => "grad_c",
            Field::Pi => "pi",
            Field::Acc => "acc",
            Field::Vt => "vt",
            Field::Contacts => "contacts",
        }
    }
}

/// A contact point of the liquid (phase 0) on the bottom wall (§8.4 step 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint<T> {
    /// Position (y = y_w).
    pub r: V2<T>,
    /// +1 when the liquid lies on the −x side, −1 otherwise.
    pub s: T,
}

/// Per-evaluation fields (all particles: fluid first, then walls).
#[derive(Clone, Debug, Default)]
pub struct Fields<T> {
    /// Number density σ.
    pub sigma: Vec<T>,
    /// Holmes state ratio χ (when active).
    pub chi: Vec<T>,
    /// Current particle mass (walls take the mass of their typed phase, T83).
    pub mass: Vec<T>,
    /// Colour index (0, 1 fluid phases; 2 wall phase S; −1 none).
    pub colour: Vec<i32>,
    /// Density ρ = mσ.
    pub rho: Vec<T>,
    /// Pressure.
    pub p: Vec<T>,
    /// Colour gradients towards the other colours, by slot.
    pub grad: Vec<[V2<T>; 2]>,
    /// Surface stress Π (its traceless part).
    pub pi: Vec<Sym2<T>>,
    /// The isotropic part `s` of the surface stress, `Π + sI` (`surface_tension.tensor =
    /// "tangential"`, CPU only; empty otherwise).
    pub pi_iso: Vec<T>,
    /// Acceleration (fluids; zero for walls).
    pub acc: Vec<V2<T>>,
    /// Advection velocity ṽ (XSPH or v).
    pub vt: Vec<V2<T>>,
    /// Contact points, sorted by x.
    pub contacts: Vec<ContactPoint<T>>,
    /// Contact points found beyond [`crate::model::MAX_CONTACTS`] in the last evaluation.
    pub contact_overflow: usize,
    /// cos θ_d measured at each contact point, in the order of `contacts` (Mode A with
    /// `contact.wall_tension = "unbalanced"`, CPU only; empty otherwise).
    pub contact_cos: Vec<T>,
    /// Background-pressure shift acceleration a_b of the fluids (transport-velocity formulation,
    /// CPU only; empty otherwise): the drift moves with ṽ + (dt/2)·a_b.
    pub shift: Vec<V2<T>>,
    /// ṽ − v of the fluids' last advection from the shift, `(dt/2)·a_b` (transport-velocity
    /// formulation; empty before the first advection and otherwise): the lagged `ṽ − v` of the
    /// artificial stress `A = ρ v ⊗ (ṽ − v)` the next evaluation sums.
    pub shift_dv: Vec<V2<T>>,
}

impl<T: Real> Fields<T> {
    /// Zeroed fields for `n` particles.
    pub fn new(n: usize) -> Self {
        Self {
            sigma: vec![T::zero(); n],
            chi: vec![T::zero(); n],
            mass: vec![T::zero(); n],
            colour: vec![NO_COLOUR; n],
            rho: vec![T::zero(); n],
            p: vec![T::zero(); n],
            grad: vec![[V2::zero(); 2]; n],
            pi: vec![Sym2::zero(); n],
            pi_iso: Vec::new(),
            acc: vec![V2::zero(); n],
            vt: vec![V2::zero(); n],
            contacts: Vec::new(),
            contact_overflow: 0,
            contact_cos: Vec::new(),
            shift: Vec::new(),
            shift_dv: Vec::new(),
        }
    }
    /// Sum of the colour-gradient slots (the gradient towards every other colour).
    pub fn grad_c(&self, i: usize) -> V2<T> {
        self.grad[i][0] + self.grad[i][1]
    }
}

impl<T: Real> Fields<T> {
    /// The particle-indexed field `which` as flat f64 numbers (vectors as x, y; gradient slots
    /// 0 then 1; Π as xx, xy); fluid rows only for the acceleration and ṽ; contacts as x, y, s.
    pub fn flat(&self, which: Field, n_fluid: usize) -> Vec<f64> {
        let v2 = |v: &V2<T>| [v.x.f64(), v.y.f64()];
        match which {
            Field::Sigma => self.sigma.iter().map(|x| x.f64()).collect(),
            Field::Chi => self.chi.iter().map(|x| x.f64()).collect(),
            Field::Mass => self.mass.iter().map(|x| x.f64()).collect(),
            Field::Colour => self.colour.iter().map(|&c| c as f64).collect(),
            Field::Rho => self.rho.iter().map(|x| x.f64()).collect(),
            Field::P => self.p.iter().map(|x| x.f64()).collect(),
            Field::Grad => self.grad.iter().flat_map(|g| v2(&g[0]).into_iter().chain(v2(&g[1]))).collect(),
            Field::Pi => self.pi.iter().flat_map(|t| [t.xx.f64(), t.xy.f64()]).collect(),
            Field::Acc => self.acc[..n_fluid].iter().flat_map(v2).collect(),
            Field::Vt => self.vt[..n_fluid].iter().flat_map(v2).collect(),
            Field::Contacts => self.contacts.iter().flat_map(|c| [c.r.x.f64(), c.r.y.f64(), c.s.f64()]).collect(),
        }
    }
}
