//! Diagnostics: pure measurements on particle data (docs/PHYSICS.md §9 validation scenes, §10
//! contact-angle measurement, [`wave`]: the capillary wave's amplitude; [`viscous_share`]: what a viscous form takes out of it) and analytic reference
//! solutions. No solver dependency; all
//! inputs are plain `f64` slices with the phase convention of [`crate::scene::build`]
//! (0 = liquid, 1 = gas, [`crate::scene::build::WALL`] = wall particle).

pub mod analytic_flows;
pub mod contact_angle;
pub mod flow;
mod gas_grid;
pub mod rod;
pub mod viscous_share;
pub mod wave;

pub use analytic_flows::{drop_mode2_period, equilibrium_cap, poiseuille_max, poiseuille_velocity, Cap};
pub use contact_angle::{
    area_inversion, circle_fit, contact_half_width, measure_all, two_point, CircleFit, ContactAngles,
};
pub use flow::{
    argmax_density_error, argmax_speed, centroid, kinetic_energy, laplace_jump, mass_per_phase, max_density_error,
    max_normal_deviation, oscillation, wall_shear_profile, Oscillation,
};
