//! Scenes: everything a run needs to know about the physics and the geometry, as plain data
//! that reads from and writes to TOML (`sphlab scene show NAME`). Built-in scenes are in
//! [`builtin`], the particle lattice is laid out by [`build`], and `--set KEY=VALUE` overrides
//! go through [`overrides`]. Validation ([`validate`]) names the offending field and its range.

pub mod build;
pub mod builtin;
pub mod capillary;
pub mod dt_policy;
pub mod initial;
pub(crate) mod lattice;
pub mod overrides;
pub mod validate;
mod viscosity;
mod walls;
pub mod wave;

pub use viscosity::ViscousForm;
pub use walls::*;
pub use wave::InterfaceWave;

use crate::physics::kernel::KernelKind;
use serde::{Deserialize, Serialize};

/// The largest number of fluid phases a scene may declare (liquid and gas in the thesis).
pub const MAX_FLUID_PHASES: usize = 2;

/// A complete scene description.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Scene name (used in outputs).
    pub name: String,
    /// One line saying what the scene is and where it comes from.
    #[serde(default)]
    pub description: String,
    /// The viscous pair form ([`ViscousForm`]; docs/PHYSICS.md §4.1): `laplacian` (T70, the
    /// default) or `projected`. Not written when `laplacian`, so summaries of earlier runs
    /// still match (`validate --reuse`).
    #[serde(default, skip_serializing_if = "ViscousForm::is_laplacian")]
    pub viscous_form: ViscousForm,
    /// Box, resolution and the type of each side.
    pub domain: Domain,
    /// Smoothing kernel.
    pub kernel: KernelCfg,
    /// Fluid phases (1 or 2). Phase 0 is "the liquid" for diagnostics.
    pub phases: Vec<Phase>,
    /// The phase of every fluid lattice point not covered by a shape.
    pub fill: String,
    /// Shapes painted over the fill, in order (a later shape wins).
    #[serde(default)]
    pub shapes: Vec<Shape>,
    /// Surface tension between the two fluid phases (absent: no surface tension).
    #[serde(default)]
    pub surface_tension: Option<SurfaceTension>,
    /// Contact-angle model at the bottom wall.
    #[serde(default)]
    pub contact: Contact,
    /// Wall treatment.
    #[serde(default)]
    pub walls: Walls,
    /// Body acceleration (gravity), [gx, gy].
    #[serde(default)]
    pub gravity: [f64; 2],
    /// Time stepping.
    pub time: Time,
    /// Optional relaxation run before t = 0 (then velocities are reset and `initial_velocity` applied).
    #[serde(default)]
    pub relax: Option<Relax>,
    /// Optional analytic initial velocity field applied at t = 0.
    #[serde(default)]
    pub initial_velocity: Option<InitialVelocity>,
    /// Optional standing wave on the interface `y = y0`: the lattice is displaced at build
    /// ([`wave`]). Not written when absent, so summaries of earlier runs still match.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interface_wave: Option<InterfaceWave>,
    /// The capillary rule for every phase's p_b and c0 (docs/PHYSICS.md §3.1), applied by the
    /// built-ins and again after every `--set` override that does not name that p_b or c0
    /// ([`capillary::apply`]). Not written when absent, so summaries of earlier runs still match.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capillary_rule: Option<capillary::CapillaryRule>,
    /// Output cadence.
    #[serde(default)]
    pub output: Output,
}

/// The type of one side of the domain box.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// Fixed ghost-particle wall with Morris no-slip (§6.1–6.2).
    NoSlip,
    /// Fixed ghost-particle wall, free-slip (§6.3).
    FreeSlip,
    /// Symmetry plane: mirror images (§6.5).
    Mirror,
    /// Periodic: images shifted by the box length (both opposite sides must be periodic).
    Periodic,
}

impl Side {
    /// True for the two wall types (ghost-particle lattices).
    pub fn is_wall(self) -> bool {
        matches!(self, Side::NoSlip | Side::FreeSlip)
    }
}

/// The domain box `[x0,x1] × [y0,y1]`, its resolution and its four sides.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// [x0, x1].
    pub x: [f64; 2],
    /// [y0, y1].
    pub y: [f64; 2],
    /// Particles across the x extent: Δx = (x1 − x0)/nx. The y extent must be a whole number of Δx.
    pub nx: u32,
    /// Left side (x = x0).
    pub left: Side,
    /// Right side (x = x1).
    pub right: Side,
    /// Bottom side (y = y0); the contact-angle wall.
    pub bottom: Side,
    /// Top side (y = y1).
    pub top: Side,
    /// Lattice jitter: every fluid particle displaced by up to this fraction of Δx along x and
    /// along y (uniform, drawn from `seed`), for realisations of one set-up; 0 (the default)
    /// keeps the lattice. Walls stay on it.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub jitter: f64,
    /// The jitter's seed: one realisation per seed.
    #[serde(default, skip_serializing_if = "is_zero_u64")]
    pub seed: u64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_zero_u64(x: &u64) -> bool {
    *x == 0
}

impl Domain {
    /// Lattice spacing Δx.
    pub fn dx(&self) -> f64 {
        (self.x[1] - self.x[0]) / self.nx as f64
    }
    /// Number of rows, ny = (y1 − y0)/Δx rounded.
    pub fn ny(&self) -> u32 {
        ((self.y[1] - self.y[0]) / self.dx()).round() as u32
    }
}

/// Kernel choice and smoothing length.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KernelCfg {
    /// Kernel function.
    pub kind: KernelKind,
    /// h / Δx.
    pub h_ratio: f64,
}

/// One fluid phase.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Phase {
    /// Name used by shapes, `fill` and `contact`.
    pub name: String,
    /// Rest density ρ0.
    pub rho0: f64,
    /// Dynamic viscosity μ (η).
    pub mu: f64,
    /// Reference sound speed c0.
    pub c0: f64,
    /// Tait exponent γ.
    pub gamma: f64,
    /// Background pressure p_b.
    #[serde(default)]
    pub p_b: f64,
}

/// A region painted with one phase and an initial velocity: a circle (`centre`, `radius`) or a
/// rectangle (`min`, `max`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Shape {
    /// circle | rect.
    pub kind: ShapeKind,
    /// Circle centre.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre: Option<[f64; 2]>,
    /// Circle radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Rectangle lower-left corner.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<[f64; 2]>,
    /// Rectangle upper-right corner.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<[f64; 2]>,
    /// Phase name.
    pub phase: String,
    /// Initial velocity of the particles inside.
    #[serde(default)]
    pub velocity: [f64; 2],
}

impl Shape {
    /// A circle of `phase`.
    pub fn circle(centre: [f64; 2], radius: f64, phase: &str, velocity: [f64; 2]) -> Self {
        Self {
            kind: ShapeKind::Circle,
            centre: Some(centre),
            radius: Some(radius),
            min: None,
            max: None,
            phase: phase.into(),
            velocity,
        }
    }
    /// True when `(x, y)` lies inside (circle: |r − c| < R; rectangle: min ≤ r < max).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        match self.kind {
            ShapeKind::Circle => {
                let (c, r) = (self.centre.unwrap_or_default(), self.radius.unwrap_or(0.0));
                (x - c[0]).powi(2) + (y - c[1]).powi(2) < r * r
            }
            ShapeKind::Rect => {
                let (a, b) = (self.min.unwrap_or_default(), self.max.unwrap_or_default());
                x >= a[0] && x < b[0] && y >= a[1] && y < b[1]
            }
        }
    }
}

/// Shape kinds.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ShapeKind {
    /// Needs `centre` and `radius`.
    Circle,
    /// Needs `min` and `max`.
    Rect,
}

/// Surface tension between the two fluid phases (Hu–Adams stress tensor, §5).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SurfaceTension {
    /// σ between fluid phases 0 and 1 (σ_LG).
    pub sigma: f64,
    /// Form of the colour gradient: `thesis` (T71, default) or `single-field` (PySPH's).
    /// Not written when `thesis`, so summaries of earlier runs still match (`validate --reuse`).
    #[serde(default, skip_serializing_if = "ColourGradient::is_thesis")]
    pub colour_gradient: ColourGradient,
    /// Isotropic part of the stress tensor: `traceless` (Hu–Adams T73, default) or `tangential`
    /// (`σ|∇C|(I − n̂n̂)`, docs/PHYSICS.md §5.3). Not written when `traceless`.
    #[serde(default, skip_serializing_if = "StressForm::is_traceless")]
    pub tensor: StressForm,
}

impl SurfaceTension {
    /// σ with the thesis's colour gradient.
    pub fn thesis(sigma: f64) -> Self {
        Self { sigma, colour_gradient: ColourGradient::Thesis, tensor: StressForm::Traceless }
    }
}

/// How the colour gradient entering the stress tensor is summed.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ColourGradient {
    /// Thesis T71: `σ_i Σ_{j of the other colour} ∇W_ij/σ_j²`, one gradient per colour pair.
    #[default]
    Thesis,
    /// Adami 2010 eq. 14 as PySPH's `ColorGradientAdami`: one colour field (1 in phase 0,
    /// 0 elsewhere), `σ_i Σ_j (C_i/σ_i² + C_j/σ_j²) ∇W_ij` over every neighbour. CPU only, and
    /// only without a contact-angle mode.
    SingleField,
}

impl ColourGradient {
    /// True for the default, the thesis's form.
    pub fn is_thesis(&self) -> bool {
        *self == ColourGradient::Thesis
    }
}

/// The isotropic part of the surface stress tensor (docs/PHYSICS.md §5.3): the two forms give
/// the same surface force and differ in what the pressure carries.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum StressForm {
    /// Hu–Adams T73: `σ|∇C|(I/2 − n̂n̂)`, traceless. Normal to the interface it compresses by
    /// `σ|∇C|/2`, which the pressure balances by a density deficit in the band.
    #[default]
    Traceless,
    /// `σ|∇C|(I − n̂n̂)`, the tensor of the continuum identity T72: a tension `σ|∇C|` along the
    /// interface and none across it, so the band needs no pressure deficit. CPU only.
    Tangential,
}

impl StressForm {
    /// True for the default, the thesis's traceless form.
    pub fn is_traceless(&self) -> bool {
        *self == StressForm::Traceless
    }
}

/// Time stepping.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Time {
    /// midpoint (predictor–corrector), verlet or verlet-pec ([`Integrator`]; the Verlet form is
    /// written out in `physics::integrate`).
    #[serde(default = "default_integrator")]
    pub integrator: Integrator,
    /// Fixed dt; 0 means "min of the limits" recomputed each step.
    #[serde(default)]
    pub dt: f64,
    /// CFL factor of (T52).
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    /// End time.
    pub t_end: f64,
    /// XSPH ε (0 = off).
    #[serde(default)]
    pub xsph: f64,
    /// What a fixed `dt` above a stability limit does ([`dt_policy`]).
    #[serde(default)]
    pub dt_policy: DtPolicy,
    /// The resolution `domain.nx` at which `dt` was chosen; `dt_policy = "scale"` rescales `dt`
    /// from it to `domain.nx` (0: `domain.nx`, no rescaling).
    #[serde(default)]
    pub dt_nx: u32,
    /// Where the phases' background pressure p_b acts ([`Background`]): `momentum` (default, the
    /// thesis's Hu–Adams form) or `transport` (Adami, Hu & Adams 2013, CPU only). Not written
    /// when `momentum`, so summaries of earlier runs still match (`validate --reuse`).
    #[serde(default, skip_serializing_if = "Background::is_momentum")]
    pub background: Background,
}

/// Where the background pressure `phases.*.p_b` acts.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Background {
    /// Added to the EOS pressure (T66 + p_b), so it enters the momentum equation (T68): the
    /// thesis's form. Its pair sum does not vanish on a disordered particle set and acts on the
    /// particle arrangement like a spring.
    #[default]
    Momentum,
    /// Transport-velocity formulation (Adami, Hu & Adams 2013, JCP 241, eqs. 9–13): the EOS and
    /// the momentum equation see no p_b; particles move with the transport velocity
    /// `ṽ = v + (dt/2)·a_b`, `a_b,i = −(p_b,i/m_i) Σ_j (V_i² + V_j²) ∇_iW_ij` over every
    /// neighbour (walls included), which keeps the particle set regular without a force on the
    /// fluid; and the momentum equation carries their artificial stress `A = ρ v ⊗ (ṽ − v)`
    /// (eq. 12; docs/PHYSICS.md §7.5), the momentum flux of the advection's departure from v.
    /// CPU only.
    Transport,
    /// The same shift without the artificial stress (the form sphlab had before it): kept to
    /// measure what the stress term changes. CPU only.
    TransportShiftOnly,
}

impl Background {
    /// True for the default, p_b in the momentum equation.
    pub fn is_momentum(&self) -> bool {
        *self == Background::Momentum
    }

    /// True for the transport-velocity forms (p_b moves the particles, not the fluid).
    pub fn is_transport(&self) -> bool {
        matches!(self, Background::Transport | Background::TransportShiftOnly)
    }
}

/// What a fixed `dt` does against the stability limits at load (see [`dt_policy`]).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum DtPolicy {
    /// Above a limit: refused (exit 2) naming the limit and the largest safe dt.
    #[default]
    Strict,
    /// Above a limit: a warning, and the run goes ahead.
    Warn,
    /// `dt` keeps the fraction of the tightest limit it has at `dt_nx`, rescaled to `domain.nx`.
    Scale,
}

fn default_integrator() -> Integrator {
    Integrator::Midpoint
}
fn default_cfl() -> f64 {
    0.25
}

/// Integrators (§7.2).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Explicit midpoint predictor–corrector (two force evaluations per step).
    Midpoint,
    /// Velocity Verlet (one force evaluation per step), the evaluation after the drift at the
    /// predicted velocity v_n + dt·a_n: second order with viscosity.
    Verlet,
    /// Velocity Verlet with the evaluation at the half-step velocity v_{n+½} (docs/PHYSICS.md §7.2's
    /// form, PySPH's PEC integrator): the viscous force lags by O(dt), first order with
    /// viscosity. CPU only; for the cross-code check against PySPH (`scenes/pysph-rod.toml`).
    VerletPec,
}

/// Relaxation before t = 0.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Relax {
    /// Relaxation time.
    pub t: f64,
}

/// Analytic initial velocity fields.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum InitialVelocity {
    /// The oscillating-rod field (T84, Adami 2010), applied to one phase.
    RodOscillation {
        /// V0.
        v0: f64,
        /// r0.
        r0: f64,
        /// Drop centre.
        centre: [f64; 2],
        /// Phase it applies to (`"*"`: every fluid particle).
        phase: String,
    },
}

/// Output cadence.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// A `series.csv` row every this many steps.
    pub every: u64,
}

impl Default for Output {
    fn default() -> Self {
        Self { every: 100 }
    }
}

/// A bad-input error: which field, what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("scene field `{field}`: {msg}")]
pub struct SceneError {
    /// TOML path of the field.
    pub field: String,
    /// What is wrong with it.
    pub msg: String,
}

fn err(field: &str, msg: impl Into<String>) -> SceneError {
    SceneError { field: field.to_string(), msg: msg.into() }
}

impl Scene {
    /// Parses a TOML scene (unknown keys are errors).
    pub fn from_toml(text: &str) -> Result<Scene, SceneError> {
        let s: Scene = toml::from_str(text).map_err(|e| err("<file>", e.to_string().trim().to_string()))?;
        s.validate()?;
        Ok(s)
    }

    /// Serialises to TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a Scene always serialises")
    }

    /// Index of a fluid phase by name.
    pub fn phase_index(&self, name: &str) -> Option<usize> {
        self.phases.iter().position(|p| p.name == name)
    }

    /// Smoothing length h.
    pub fn h(&self) -> f64 {
        self.kernel.h_ratio * self.domain.dx()
    }

    /// Support radius κh.
    pub fn support(&self) -> f64 {
        self.kernel.kind.support_factor() * self.h()
    }

    /// Checks every field (ranges in [`validate`]); the error names the first bad one and the
    /// accepted range.
    pub fn validate(&self) -> Result<(), SceneError> {
        validate::validate(self)
    }
}
