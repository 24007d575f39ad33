//! The `Params` uniform (twin of `shaders/types.wgsl`): every constant the stages need from
//! [`Model<T>`], in the storage precision `T`, plus the grid of the `cells` search. Its `dt` and
//! `step` keep their values at construction (the fixed dt, 0): the kernels read dt and the step
//! from the device clock (`gpu::clock`), which the host never writes between steps. Filled from
//! the same `Model` the CPU uses, so both backends see identical numbers; sin θ and cos θ are
//! computed on the host in `T` (no f64 trig in WGSL). A test compares the Rust offsets with
//! naga's layout of the WGSL struct.

use crate::model::{AxisMap, Model};
use crate::neighbours::cells::CellBox;
use crate::physics::contact::rest_cos;
use crate::real::Real;
use crate::scene::{ContactMode, ViscousForm, WallVelocity};

/// Stage flag bits (`STAGE_*` in `shaders/types.wgsl`).
pub mod flags {
    /// Holmes χ.
    pub const HOLMES: u32 = 1;
    /// Contact line.
    pub const CONTACT_LINE: u32 = 2;
    /// Wall typing.
    pub const WALL_TYPING: u32 = 4;
    /// R-wall pressure.
    pub const WALL_PRESSURE: u32 = 8;
    /// Colour gradient + surface stress.
    pub const SURFACE: u32 = 16;
    /// Normal correction.
    pub const NORMAL_CORRECTION: u32 = 32;
    /// Viscous term.
    pub const VISCOSITY: u32 = 64;
    /// Lennard-Jones.
    pub const LJ: u32 = 128;
    /// XSPH.
    pub const XSPH: u32 = 256;
    /// Mode A's unbalanced Young force at the measured angle (docs/PHYSICS.md §8.2.5).
    pub const YOUNG_UNBALANCED: u32 = 512;
}

/// Codes of the enumerated `Params` words (`IMAGE_*`, `CONTACT_MODE_*`, `WALL_VELOCITY_*`, `VISCOUS_FORM_*` in
/// `shaders/types.wgsl`).
pub mod code {
    /// No image across this side.
    pub const IMAGE_NONE: u32 = 0;
    /// Mirror plane.
    pub const IMAGE_MIRROR: u32 = 1;
    /// Periodic shift.
    pub const IMAGE_SHIFT: u32 = 2;
    /// No contact-angle model.
    pub const CONTACT_MODE_NONE: u32 = 0;
    /// Mode A (wall phase S).
    pub const CONTACT_MODE_A: u32 = 1;
    /// Mode B (contact line, typing, correction).
    pub const CONTACT_MODE_B: u32 = 2;
    /// Morris wall ghost velocities.
    pub const WALL_VELOCITY_MORRIS: u32 = 0;
    /// Holmes wall ghost velocities.
    pub const WALL_VELOCITY_HOLMES: u32 = 1;
    /// T70's viscous sum.
    pub const VISCOUS_FORM_LAPLACIAN: u32 = 0;
    /// The projected viscous sum (docs/PHYSICS.md §4.1).
    pub const VISCOUS_FORM_PROJECTED: u32 = 1;
}

/// The uniform. `#[repr(C)]`, every field a u32 or `T` or `[_; 4]`; the u32 block is 32 words so
/// the reals start 32-byte aligned (vec4<f64> alignment), the real scalars are 24 (a multiple of 4).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct Params<T> {
    pub kernel_kind: u32,
    pub n: u32,
    pub n_fluid: u32,
    pub wall_phase: u32,
    pub contact_mode: u32,
    pub n_walls: u32,
    pub stages: u32,
    pub step: u32,
    pub wall_velocity: u32,
    pub grid_nx: u32,
    pub grid_ny: u32,
    pub n_phases: u32,
    pub viscous_form: u32,
    pub pad0: [u32; 3],
    pub image_kind: [u32; 4],
    pub wall_axis: [u32; 4],
    pub wall_free_slip: [u32; 4],
    pub pad4: [u32; 4],
    pub h: T,
    pub inv_h: T,
    pub alpha: T,
    pub support: T,
    pub support2: T,
    pub dx: T,
    pub sin_theta: T,
    pub cos_theta: T,
    pub band: T,
    pub y_wall: T,
    pub beta_max: T,
    pub chi_floor: T,
    pub lj_strength: T,
    pub xsph: T,
    pub gravity_x: T,
    pub gravity_y: T,
    pub lo_x: T,
    pub lo_y: T,
    pub hi_x: T,
    pub hi_y: T,
    pub dt: T,
    pub grid_origin_x: T,
    pub grid_origin_y: T,
    pub grid_inv_cell: T,
    pub image_value: [T; 4],
    pub wall_coord: [T; 4],
    pub wall_sign: [T; 4],
    pub rho0: [T; 4],
    pub mass: [T; 4],
    pub stiffness: [T; 4],
    pub gamma: [T; 4],
    pub p_b: [T; 4],
    pub eta: [T; 4],
    pub sigma0: [T; 4],
    pub sigma1: [T; 4],
    pub sigma2: [T; 4],
    /// The unbalanced Young force (§8.2.5): σ_GS − σ_LS, σ_LG, the cos θ a point whose angle
    /// cannot be measured is left at (the force is zero there), unused.
    pub young: [T; 4],
}

// SAFETY: repr(C); 32 u32 (128 bytes) followed only by `T` scalars and arrays of `T`, where
// T is f32 or f64 (align ≤ 8 divides 128): no padding anywhere, every bit pattern valid.
unsafe impl<T: Real> bytemuck::Zeroable for Params<T> {}
unsafe impl<T: Real> bytemuck::Pod for Params<T> {}

const _: () = assert!(size_of::<Params<f32>>() == 128 + 24 * 4 + 13 * 16);
const _: () = assert!(size_of::<Params<f64>>() == 128 + 24 * 8 + 13 * 32);

fn axis_map<T: Real>(m: Option<AxisMap<T>>) -> (u32, T) {
    match m {
        None => (code::IMAGE_NONE, T::zero()),
        Some(AxisMap::Mirror(p)) => (code::IMAGE_MIRROR, p),
        Some(AxisMap::Shift(s)) => (code::IMAGE_SHIFT, s),
    }
}

impl<T: Real> Params<T> {
    /// The uniform of `m` for `n` particles (`n_fluid` fluids first) on `grid`.
    pub fn new(m: &Model<T>, n: usize, n_fluid: usize, grid: &CellBox<T>) -> Self {
        let mut p: Self = bytemuck::Zeroable::zeroed();
        let kp = m.kernel;
        p.kernel_kind = kp.kind.id();
        p.n = n as u32;
        p.n_fluid = n_fluid as u32;
        p.wall_phase = m.wall_phase as u32;
        p.contact_mode = match m.contact_mode {
            ContactMode::None => code::CONTACT_MODE_NONE,
            ContactMode::A => code::CONTACT_MODE_A,
            ContactMode::B => code::CONTACT_MODE_B,
        };
        p.n_walls = m.walls.len().min(4) as u32;
        let st = m.stages;
        let bits = [
            (st.holmes_chi, flags::HOLMES),
            (st.contact_line, flags::CONTACT_LINE),
            (st.wall_typing, flags::WALL_TYPING),
            (st.wall_pressure, flags::WALL_PRESSURE),
            (st.surface_tension, flags::SURFACE),
            (st.normal_correction, flags::NORMAL_CORRECTION),
            (st.viscosity, flags::VISCOSITY),
            (st.lennard_jones, flags::LJ),
            (st.xsph, flags::XSPH),
            (m.young_unbalanced, flags::YOUNG_UNBALANCED),
        ];
        p.stages = bits.iter().filter(|b| b.0).fold(0, |a, b| a | b.1);
        p.wall_velocity = match m.wall_velocity {
            WallVelocity::Morris => code::WALL_VELOCITY_MORRIS,
            WallVelocity::Holmes => code::WALL_VELOCITY_HOLMES,
        };
        p.viscous_form = match m.viscous_form {
            ViscousForm::Laplacian => code::VISCOUS_FORM_LAPLACIAN,
            ViscousForm::Projected => code::VISCOUS_FORM_PROJECTED,
        };
        (p.grid_nx, p.grid_ny) = (grid.nx, grid.ny);
        p.n_phases = m.phases.len().min(4) as u32;
        let sides = [m.images.x[0], m.images.x[1], m.images.y[0], m.images.y[1]];
        for (k, s) in sides.iter().enumerate() {
            (p.image_kind[k], p.image_value[k]) = axis_map(*s);
        }
        for (k, w) in m.walls.iter().take(4).enumerate() {
            p.wall_axis[k] = w.axis as u32;
            p.wall_free_slip[k] = w.free_slip as u32;
            p.wall_coord[k] = w.coord;
            p.wall_sign[k] = w.sign;
        }
        (p.h, p.inv_h, p.alpha, p.support) = (kp.h, kp.inv_h, kp.alpha, kp.support);
        p.support2 = m.support2;
        p.dx = m.dx;
        (p.sin_theta, p.cos_theta) = (m.theta.sin(), m.theta.cos());
        p.band = m.band;
        p.y_wall = m.y_wall;
        p.beta_max = m.beta_max;
        p.chi_floor = m.chi_floor;
        p.lj_strength = m.lj_strength;
        p.xsph = m.xsph;
        (p.gravity_x, p.gravity_y) = (m.gravity.x, m.gravity.y);
        (p.lo_x, p.lo_y, p.hi_x, p.hi_y) = (m.lo.x, m.lo.y, m.hi.x, m.hi.y);
        p.dt = T::c(m.dt_fixed);
        (p.grid_origin_x, p.grid_origin_y, p.grid_inv_cell) = (grid.origin.x, grid.origin.y, grid.inv_cell);
        for (k, ph) in m.phases.iter().take(4).enumerate() {
            p.rho0[k] = ph.rho0;
            p.mass[k] = ph.mass;
            p.stiffness[k] = ph.stiffness;
            p.gamma[k] = ph.gamma;
            p.p_b[k] = ph.p_b;
            p.eta[k] = ph.eta;
        }
        for l in 0..3 {
            p.sigma0[l] = m.sigma[0][l];
            p.sigma1[l] = m.sigma[1][l];
            p.sigma2[l] = m.sigma[2][l];
        }
        p.young = [m.line_force, m.sigma[0][1], rest_cos(m), T::zero()];
        p
    }
}

/// `(field name, byte offset)` of every field, in declaration order (for the layout test).
pub fn field_offsets<T: Real>() -> Vec<(&'static str, usize)> {
    macro_rules! offs {
        ($($f:ident),*) => { vec![$((stringify!($f), std::mem::offset_of!(Params<T>, $f))),*] };
    }
    let mut v = offs!(kernel_kind, n, n_fluid, wall_phase, contact_mode, n_walls, stages, step, wall_velocity);
    v.extend(offs!(grid_nx, grid_ny, n_phases, viscous_form, image_kind, wall_axis, wall_free_slip, pad4, h));
    v.extend(offs!(inv_h, alpha));
    v.extend(offs!(support, support2, dx, sin_theta, cos_theta, band, y_wall, beta_max, chi_floor, lj_strength));
    v.extend(offs!(xsph, gravity_x, gravity_y, lo_x, lo_y, hi_x, hi_y, dt, grid_origin_x, grid_origin_y));
    v.extend(offs!(grid_inv_cell, image_value, wall_coord, wall_sign, rho0, mass, stiffness, gamma, p_b, eta));
    v.extend(offs!(sigma0, sigma1, sigma2, young));
    v
}
