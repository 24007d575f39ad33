//! The physics definition: pure functions, no loops over particles, no I/O.
//!
//! Each Rust function has a WGSL twin of the same name in `shaders/` (tested together in
//! `tests/wgsl_twins.rs`):
//!
//! | Rust (`core/src/physics/`) | WGSL (`shaders/`) | equations |
//! |---|---|---|
//! | `kernel::kernel_f`, `kernel_df`, `kernel_w`, `kernel_dwdr` | `kernel.wgsl` | T40–T43 |
//! | `eos::eos_pressure` | `eos.wgsl` | T34–T36 |
//! | `pair::grad_w_ij`, `pressure_acc_ij`, `harmonic_viscosity`, `viscous_fac_ij`, `viscous_acc_ij`, `viscous_projected_acc_ij`, `colour_gradient_ij`, `colour_gradient_single_ij`, `surface_acc_ij`, `xsph_ij` | `pair.wgsl` | T67–T71, T76, T51 |
//! | `stress::stress_tensor` | `stress.wgsl` | T73–T74 |
//! | `wall::noslip_beta`, `wall_relative_velocity`, `holmes_beta`, `lj_wall_acc` | `wall.wgsl` | T44–T49 |
//! | `contact::contact_normal`, `contact_side`, `corrected_normal` | `contact.wgsl` | T81–T83 |
//! | `integrate::integrate_predict`, `integrate_correct`, `integrate_kick`, `integrate_drift` | `integrate.wgsl` | §7.2 |
//!
//! The CPU-only options have no twin, and the GPU backend refuses them with exit 2
//! (`gpu::solver::cpu_only`): `pair::artificial_stress_acc_ij` (the transport-velocity form),
//! `pair::surface_isotropic_acc_ij` and `stress::stress_isotropic` (the tangential stress form).

pub mod contact;
pub mod eos;
pub mod integrate;
pub mod kernel;
pub mod pair;
pub mod stress;
pub mod timestep;
pub mod wall;
