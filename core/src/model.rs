//! The scene turned into solver constants in the working precision: kernel, per-phase
//! constants (mass, EOS, viscosity), the colour/σ table, wall lines, boundary images and the
//! list of active stages. Constants are computed in f64 and stored as `T`. The GPU uniform
//! buffer is filled from the same struct, so both backends see identical numbers.

use crate::physics::kernel::{kernel_w, lattice_sum, KernelKind, KernelParams};
use crate::real::{Real, Sym2, V2};
use crate::scene::{
    ColourGradient, ContactMode, LineForceSpread, LiquidGasAtWall, Scene, Side, StressForm, ViscousForm, WallPressure,
    WallTension, WallVelocity,
};

/// Number of colours: fluid phases 0 and 1, and the wall phase S (Mode A).
pub const N_COLOURS: usize = 3;
/// Colour index of the wall phase S in Mode A.
pub const COLOUR_WALL: i32 = 2;
/// "No colour" (untyped wall, or walls in a scene without a contact-angle model).
pub const NO_COLOUR: i32 = -1;
/// Most contact points one evaluation may hold.
pub const MAX_CONTACTS: usize = 32;

/// Words per contact point in the GPU's contact list: x, y, s, the cos θ_d measured there and the
/// point's line force per unit weight (docs/PHYSICS.md §8.2.5).
pub const CONTACT_WORDS: usize = 5;
/// A first-row particle nearer a side wall than this many half Δx has no room for another
/// particle beside it on that side (the nearest fluid column stands Δx/2 off a wall, the next
/// one Δx further): with no band neighbour there it meets the wall, it is no free edge of the
/// liquid, so no contact point is made there (docs/PHYSICS.md §8.4 step 2).
pub const SIDE_WALL_HALF_DX: u32 = 3;
/// The share of a Mode A wall band's tension its fluid side carries (docs/PHYSICS.md §8.2.1):
/// ½ for every kernel, the wall lattice being the fluid lattice mirrored in the wall surface;
/// `tests/force_balance.rs` measures it on a flat layer.
pub const WALL_BAND_SHARE: f64 = 0.5;

/// Per-phase constants.
#[derive(Clone, Copy, Debug)]
pub struct PhaseConst<T> {
    /// Rest density ρ0.
    pub rho0: T,
    /// Particle mass `ρ0 / σ_lattice` (lattice-normalised, docs/PHYSICS.md §2).
    pub mass: T,
    /// EOS stiffness B = ρ0c0²/γ.
    pub stiffness: T,
    /// γ.
    pub gamma: T,
    /// Background pressure.
    pub p_b: T,
    /// Dynamic viscosity η.
    pub eta: T,
}

/// One axis-aligned wall line, the boundary of a wall side.
#[derive(Clone, Copy, Debug)]
pub struct WallLine<T> {
    /// 0: wall normal along x, 1: along y.
    pub axis: usize,
    /// Coordinate of the line.
    pub coord: T,
    /// +1 when the fluid lies on the + side (left/bottom walls), −1 otherwise.
    pub sign: T,
    /// Free-slip (else no-slip).
    pub free_slip: bool,
}

impl<T: Real> WallLine<T> {
    /// Signed distance of `p` in front of the line (positive on the fluid side; twin of WGSL
    /// `wall_distance` in shaders/geometry.wgsl).
    #[inline(always)]
    pub fn wall_distance(&self, p: V2<T>) -> T {
        let c = if self.axis == 0 { p.x } else { p.y };
        (c - self.coord) * self.sign
    }
    /// Unit normal pointing into the fluid.
    #[inline(always)]
    pub fn wall_normal(&self) -> V2<T> {
        if self.axis == 0 {
            V2::new(self.sign, T::zero())
        } else {
            V2::new(T::zero(), self.sign)
        }
    }
}

/// The map of one box side for images: a mirror plane or a periodic shift.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AxisMap<T> {
    /// Reflection about the plane `coord`.
    Mirror(T),
    /// Translation by `shift`.
    Shift(T),
}

impl<T: Real> AxisMap<T> {
    #[inline(always)]
    fn apply(self, c: T) -> T {
        match self {
            AxisMap::Mirror(p) => p + p - c,
            AxisMap::Shift(s) => c + s,
        }
    }
    #[inline(always)]
    fn inverse(self, c: T) -> T {
        match self {
            AxisMap::Mirror(p) => p + p - c,
            AxisMap::Shift(s) => c - s,
        }
    }
    #[inline(always)]
    fn sign(self) -> T {
        match self {
            AxisMap::Mirror(_) => -T::one(),
            AxisMap::Shift(_) => T::one(),
        }
    }
}

/// Boundary images (mirror ghosts and periodic copies) as transforms, not stored particles.
/// Image code `c = ax + 3·ay`, `a ∈ {0: identity, 1: image across the low side, 2: across the
/// high side}`. The image of particle j under code c is `image_pos(c, x_j)`; its velocity,
/// colour gradient and Π_xy change sign per mirrored axis. `image_pos`, `inverse_pos`,
/// `image_vec`, `image_sym` are twins of the same names in shaders/geometry.wgsl.
#[derive(Clone, Copy, Debug)]
pub struct Images<T> {
    /// `[x-low, x-high]` maps.
    pub x: [Option<AxisMap<T>>; 2],
    /// `[y-low, y-high]` maps.
    pub y: [Option<AxisMap<T>>; 2],
}

impl<T: Real> Images<T> {
    fn axis(m: &[Option<AxisMap<T>>; 2], a: u32) -> Option<AxisMap<T>> {
        match a {
            0 => None,
            _ => m[a as usize - 1],
        }
    }
    /// True when code `c` names an existing transform (identity always does).
    #[inline(always)]
    pub fn exists(&self, c: u32) -> bool {
        let (ax, ay) = (c % 3, c / 3);
        (ax == 0 || Self::axis(&self.x, ax).is_some()) && (ay == 0 || Self::axis(&self.y, ay).is_some())
    }
    /// The codes that exist, identity first.
    pub fn codes(&self) -> Vec<u32> {
        (0..9).filter(|&c| self.exists(c)).collect()
    }
    /// Position of the image of `p`.
    #[inline(always)]
    pub fn image_pos(&self, c: u32, p: V2<T>) -> V2<T> {
        let (ax, ay) = (c % 3, c / 3);
        let x = Self::axis(&self.x, ax).map_or(p.x, |m| m.apply(p.x));
        let y = Self::axis(&self.y, ay).map_or(p.y, |m| m.apply(p.y));
        V2::new(x, y)
    }
    /// Inverse transform (where to look for particles whose image lands near `p`).
    #[inline(always)]
    pub fn inverse_pos(&self, c: u32, p: V2<T>) -> V2<T> {
        let (ax, ay) = (c % 3, c / 3);
        let x = Self::axis(&self.x, ax).map_or(p.x, |m| m.inverse(p.x));
        let y = Self::axis(&self.y, ay).map_or(p.y, |m| m.inverse(p.y));
        V2::new(x, y)
    }
    /// Component signs (±1) applied to vectors (velocity, colour gradient).
    #[inline(always)]
    pub fn signs(&self, c: u32) -> V2<T> {
        let (ax, ay) = (c % 3, c / 3);
        V2::new(
            Self::axis(&self.x, ax).map_or(T::one(), |m| m.sign()),
            Self::axis(&self.y, ay).map_or(T::one(), |m| m.sign()),
        )
    }
    /// Image of a vector.
    #[inline(always)]
    pub fn image_vec(&self, c: u32, v: V2<T>) -> V2<T> {
        let s = self.signs(c);
        V2::new(v.x * s.x, v.y * s.y)
    }
    /// Image of a symmetric traceless tensor (Π_xy flips once per mirrored axis).
    #[inline(always)]
    pub fn image_sym(&self, c: u32, t: Sym2<T>) -> Sym2<T> {
        let s = self.signs(c);
        Sym2 { xx: t.xx, xy: t.xy * s.x * s.y }
    }
}

/// Which stages a scene needs (docs/PHYSICS.md §12); the stage list follows from it in
/// [`crate::stage`]. Printed and written into the run summary.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct ActiveStages {
    /// Holmes state ratio χ (with the density summation).
    pub holmes_chi: bool,
    /// Contact-line detection (Mode B).
    pub contact_line: bool,
    /// Wall typing by the interpolation line (Mode B, Algorithm 2).
    pub wall_typing: bool,
    /// Adami wall pressure (R-wall).
    pub wall_pressure: bool,
    /// Colour gradients and the surface stress tensor.
    pub surface_tension: bool,
    /// Algorithm 1 (Mode B).
    pub normal_correction: bool,
    /// Viscous term (any μ > 0).
    pub viscosity: bool,
    /// Lennard-Jones wall repulsion.
    pub lennard_jones: bool,
    /// XSPH advection velocity.
    pub xsph: bool,
    /// Automatic dt (max |v|, |a| reductions).
    pub adaptive_dt: bool,
}

/// All solver constants of a scene.
#[derive(Clone, Debug)]
pub struct Model<T> {
    /// Kernel constants.
    pub kernel: KernelParams<T>,
    /// Δx.
    pub dx: T,
    /// Support radius squared (neighbour criterion `r² < support²`).
    pub support2: T,
    /// Fluid phase constants (1 or 2 used).
    pub phases: Vec<PhaseConst<T>>,
    /// Phase whose mass and EOS untyped walls use.
    pub wall_phase: usize,
    /// σ between colours (0, 1 fluids; 2 wall S). Zero = no interface force.
    pub sigma: [[T; N_COLOURS]; N_COLOURS],
    /// Contact mode.
    pub contact_mode: ContactMode,
    /// Mode A's contact-line force per unit length: `(1 − s_w)(σ_GS − σ_LS)` with the wall bands
    /// (§8.2.1), `σ_GS − σ_LS` without them (§8.2.3); zero when off or when the wall tensions are
    /// equal.
    pub line_force: T,
    /// Mode A with `contact.liquid_gas_at_wall = "free"`: fluid–wall pairs leave out the
    /// liquid–gas part of the fluid's tensor (§8.2.2).
    pub liquid_gas_free_at_wall: bool,
    /// How the contact-line force is shared near each contact point (§8.2.4).
    pub line_force_spread: LineForceSpread,
    /// Mode A with `contact.wall_tension = "unbalanced"` (§8.2.5): walls typed at each contact
    /// point's measured angle θ_d, and `σ_LG cos θ_d` taken from the line force there.
    pub young_unbalanced: bool,
    /// θ_d in radians.
    pub theta: T,
    /// Contact band height (× Δx).
    pub band: T,
    /// Bottom wall surface y_w.
    pub y_wall: T,
    /// Wall lines (wall sides only).
    pub walls: Vec<WallLine<T>>,
    /// β_max.
    pub beta_max: T,
    /// Holmes χ floor.
    pub chi_floor: T,
    /// LJ strength D and radius r0 = Δx/2.
    pub lj_strength: T,
    /// Gravity.
    pub gravity: V2<T>,
    /// XSPH ε.
    pub xsph: T,
    /// Boundary images.
    pub images: Images<T>,
    /// Domain box.
    pub lo: V2<T>,
    /// Domain box.
    pub hi: V2<T>,
    /// Which stages run.
    pub stages: ActiveStages,
    /// Wall pressure option.
    pub wall_pressure: WallPressure,
    /// Wall velocity option.
    pub wall_velocity: WallVelocity,
    /// Viscous pair form (docs/PHYSICS.md §4.1).
    pub viscous_form: ViscousForm,
    /// Max sound speed (for dt).
    pub c_max: f64,
    /// Max kinematic viscosity (for dt).
    pub nu_max: f64,
    /// Mean rest density (capillary dt).
    pub rho_mean: f64,
    /// Max σ (capillary dt).
    pub sigma_max: f64,
    /// CFL factor.
    pub cfl: f64,
    /// Fixed dt (0 = automatic), after `time.dt_policy` ([`crate::scene::dt_policy::effective_dt`]).
    pub dt_fixed: f64,
    /// Colour gradient by one colour field (PySPH's form) instead of the thesis's T71.
    pub single_field_colour: bool,
    /// `surface_tension.tensor = "tangential"`: every Π^{kl} carries the isotropic part
    /// `σ^{kl}|g|/2` beside the traceless one (docs/PHYSICS.md §5.3), kept in [`Fields::pi_iso`].
    ///
    /// [`Fields::pi_iso`]: crate::fields::Fields::pi_iso
    pub tangential_stress: bool,
    /// Transport-velocity formulation (`time.background = "transport"`): the background
    /// pressure of each phase, by phase, moved out of the EOS (`phases[k].p_b` is then 0) into
    /// the shift acceleration `a_b` ([`crate::scene::Background::Transport`]). `None`: p_b is in
    /// the momentum equation.
    pub transport_p_b: Option<Vec<T>>,
    /// The transport-velocity formulation's artificial stress `A = ρ v ⊗ (ṽ − v)` in the
    /// momentum equation (`time.background = "transport"`; off for `transport-shift-only` and the
    /// momentum form).
    pub artificial_stress: bool,
}

/// χ − ½ of a particle at Δx/2 above a flat wall (lattice sum in f64), the Holmes floor.
fn holmes_floor(kind: KernelKind, h: f64, dx: f64) -> f64 {
    let kp = KernelParams::<f64>::new(kind, h);
    let n = (kp.support / dx).ceil() as i64 + 1;
    let (mut fl, mut all) = (0.0, 0.0);
    for a in -n..=n {
        for b in -n..=n {
            let x = a as f64 * dx;
            let yj = (b as f64 + 0.5) * dx;
            let w = kernel_w(&kp, (x * x + (yj - 0.5 * dx).powi(2)).sqrt());
            all += w;
            if yj > 0.0 {
                fl += w;
            }
        }
    }
    fl / all - 0.5
}

/// σ between colours (0, 1 fluids; 2 the wall in Mode A with its bands, §8.2): σ_LG between the
/// two fluids, σ_LS and σ_GS with the wall unless `contact.wall_tension = "line"` (§8.2.3).
fn colour_tensions<T: Real>(scene: &Scene, st: f64) -> [[T; N_COLOURS]; N_COLOURS] {
    let mut sigma = [[T::zero(); N_COLOURS]; N_COLOURS];
    if scene.phases.len() == 2 {
        sigma[0][1] = T::c(st);
        sigma[1][0] = T::c(st);
    }
    let c = &scene.contact;
    if c.mode == ContactMode::A && c.wall_tension == WallTension::Bands {
        sigma[0][2] = T::c(c.sigma_ls);
        sigma[2][0] = T::c(c.sigma_ls);
        sigma[1][2] = T::c(c.sigma_gs);
        sigma[2][1] = T::c(c.sigma_gs);
    }
    sigma
}

/// Mode A's contact-line force per unit length: the whole σ_GS − σ_LS without the wall bands
/// (§8.2.3; §8.2.5 takes σ_LG cos θ_d of each contact point from it), the part `(1 − s_w)` of
/// it beside them when `contact.line_force` (§8.2.1), else 0.
fn contact_line_force(c: &crate::scene::Contact) -> f64 {
    let wall_pull = c.sigma_gs - c.sigma_ls;
    match (c.mode == ContactMode::A, c.wall_tension) {
        (true, WallTension::Line | WallTension::Unbalanced) => wall_pull,
        (true, WallTension::Bands) if c.line_force => (1.0 - WALL_BAND_SHARE) * wall_pull,
        _ => 0.0,
    }
}

impl<T: Real> Model<T> {
    /// Derives the constants of a validated scene.
    pub fn new(scene: &Scene) -> Self {
        let dx = scene.domain.dx();
        let h = scene.h();
        let kind = scene.kernel.kind;
        let kernel = KernelParams::<T>::new(kind, h);
        let support = scene.support();
        let sigma0 = lattice_sum(kind, h, dx);
        let transport = scene.time.background.is_transport();
        let transport_p_b = transport.then(|| scene.phases.iter().map(|p| T::c(p.p_b)).collect());
        let phases: Vec<PhaseConst<T>> = scene
            .phases
            .iter()
            .map(|p| PhaseConst {
                rho0: T::c(p.rho0),
                mass: T::c(p.rho0 / sigma0),
                stiffness: T::c(crate::physics::eos::eos_stiffness(p.rho0, p.c0, p.gamma)),
                gamma: T::c(p.gamma),
                p_b: if transport { T::zero() } else { T::c(p.p_b) },
                eta: T::c(p.mu),
            })
            .collect();
        let st = scene.surface_tension.as_ref().map_or(0.0, |s| s.sigma);
        let sigma = colour_tensions(scene, st);
        let d = &scene.domain;
        let mut walls = Vec::new();
        let mut push = |side: Side, axis, coord: f64, sign: f64| {
            if side.is_wall() {
                walls.push(WallLine { axis, coord: T::c(coord), sign: T::c(sign), free_slip: side == Side::FreeSlip });
            }
        };
        push(d.left, 0, d.x[0], 1.0);
        push(d.right, 0, d.x[1], -1.0);
        push(d.bottom, 1, d.y[0], 1.0);
        push(d.top, 1, d.y[1], -1.0);
        let lx = d.x[1] - d.x[0];
        let ly = d.y[1] - d.y[0];
        let map = |side: Side, plane: f64, shift: f64| match side {
            Side::Mirror => Some(AxisMap::Mirror(T::c(plane))),
            Side::Periodic => Some(AxisMap::Shift(T::c(shift))),
            _ => None,
        };
        let images = Images {
            x: [map(d.left, d.x[0], -lx), map(d.right, d.x[1], lx)],
            y: [map(d.bottom, d.y[0], -ly), map(d.top, d.y[1], ly)],
        };
        let surface = st > 0.0 && scene.phases.len() == 2;
        let tension = scene.surface_tension.as_ref().filter(|_| surface);
        let mode_b = surface && scene.contact.mode == ContactMode::B;
        let line_force = if surface { contact_line_force(&scene.contact) } else { 0.0 };
        let young_unbalanced =
            surface && scene.contact.mode == ContactMode::A && scene.contact.wall_tension == WallTension::Unbalanced;
        let typed = mode_b || young_unbalanced;
        let stages = ActiveStages {
            holmes_chi: scene.walls.velocity == WallVelocity::Holmes && !walls.is_empty(),
            contact_line: typed || line_force != 0.0,
            wall_typing: typed && scene.contact.wall_typing,
            wall_pressure: scene.walls.pressure == WallPressure::RWall && !walls.is_empty(),
            surface_tension: surface,
            normal_correction: typed && scene.contact.normal_correction,
            viscosity: scene.phases.iter().any(|p| p.mu > 0.0),
            lennard_jones: scene.walls.lj_strength > 0.0 && !walls.is_empty(),
            xsph: scene.time.xsph > 0.0,
            adaptive_dt: scene.time.dt == 0.0,
        };
        let wall_phase = scene.walls.phase.as_deref().and_then(|n| scene.phase_index(n)).unwrap_or(0);
        let mut sigma_max = st;
        if scene.contact.mode == ContactMode::A {
            sigma_max = sigma_max.max(scene.contact.sigma_ls).max(scene.contact.sigma_gs);
        }
        Model {
            kernel,
            dx: T::c(dx),
            support2: T::c(support * support),
            phases,
            wall_phase,
            sigma,
            contact_mode: if surface { scene.contact.mode } else { ContactMode::None },
            line_force: T::c(line_force),
            liquid_gas_free_at_wall: surface
                && scene.contact.mode == ContactMode::A
                && scene.contact.liquid_gas_at_wall == LiquidGasAtWall::Free,
            line_force_spread: scene.contact.line_force_spread,
            young_unbalanced,
            theta: T::c(scene.contact.theta_deg.to_radians()),
            band: T::c(scene.contact.band * dx),
            y_wall: T::c(d.y[0]),
            walls,
            beta_max: T::c(scene.walls.beta_max),
            chi_floor: T::c(holmes_floor(kind, h, dx)),
            lj_strength: T::c(scene.walls.lj_strength),
            gravity: V2::from_f64(scene.gravity[0], scene.gravity[1]),
            xsph: T::c(scene.time.xsph),
            images,
            lo: V2::from_f64(d.x[0], d.y[0]),
            hi: V2::from_f64(d.x[1], d.y[1]),
            stages,
            wall_pressure: scene.walls.pressure,
            wall_velocity: scene.walls.velocity,
            viscous_form: scene.viscous_form,
            c_max: scene.phases.iter().map(|p| p.c0).fold(0.0, f64::max),
            nu_max: scene.phases.iter().map(|p| p.mu / p.rho0).fold(0.0, f64::max),
            rho_mean: scene.phases.iter().map(|p| p.rho0).sum::<f64>() / scene.phases.len() as f64,
            sigma_max,
            cfl: scene.time.cfl,
            dt_fixed: crate::scene::dt_policy::effective_dt(scene),
            single_field_colour: tension.is_some_and(|s| s.colour_gradient == ColourGradient::SingleField),
            tangential_stress: tension.is_some_and(|s| s.tensor == StressForm::Tangential),
            transport_p_b,
            artificial_stress: scene.time.background == crate::scene::Background::Transport,
        }
    }

    /// Support radius.
    pub fn support(&self) -> T {
        self.kernel.support
    }

    /// The wall line nearest to `p` (smallest distance in front of it), if any wall exists
    /// (twin of WGSL `nearest_wall` in shaders/geometry.wgsl, which returns its index).
    #[inline(always)]
    pub fn nearest_wall(&self, p: V2<T>) -> Option<&WallLine<T>> {
        let mut best: Option<&WallLine<T>> = None;
        let mut bd = T::infinity();
        for w in &self.walls {
            let d = w.wall_distance(p);
            if d < bd {
                bd = d;
                best = Some(w);
            }
        }
        best
    }
}
