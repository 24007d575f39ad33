//! What only the CPU reference models: the scene options a GPU variant refuses, each with exit 2
//! and the option to change.

use super::super::GpuError;
use crate::model::Model;
use crate::real::Real;
use crate::scene::{Integrator, LineForceSpread, Scene};

/// Refuses, with the option to change, what only the CPU reference models.
pub(super) fn refuse_cpu_only<T: Real>(model: &Model<T>, scene: &Scene) -> Result<(), GpuError> {
    if model.single_field_colour {
        return Err(GpuError::Unsupported(
            "surface_tension.colour_gradient = \"single-field\" is CPU only (the WGSL stages sum the \
             thesis's T71 form); use --backend cpu or colour_gradient = \"thesis\""
                .into(),
        ));
    }
    if model.young_unbalanced && model.line_force_spread != LineForceSpread::Kernel {
        return Err(GpuError::Unsupported(
            "contact.line_force_spread = \"interface\" is CPU only (the WGSL unbalanced Young force spreads \
             by the kernel of the distance to the contact point); use --backend cpu, or line_force_spread = \"kernel\""
                .into(),
        ));
    }
    if model.line_force != T::zero() && !model.young_unbalanced {
        return Err(GpuError::Unsupported(
            "Mode A's contact-line force (contact.line_force = true, or contact.wall_tension = \"line\", \
             with σ_GS ≠ σ_LS) is CPU only (the WGSL stages have the wall bands alone); use --backend cpu, \
             or contact.line_force = false and contact.wall_tension = \"bands\""
                .into(),
        ));
    }
    if model.liquid_gas_free_at_wall {
        return Err(GpuError::Unsupported(
            "contact.liquid_gas_at_wall = \"free\" (Mode A) is CPU only (the WGSL stages hand every \
             fluid–wall pair the fluid's whole tensor); use --backend cpu or liquid_gas_at_wall = \"shared\""
                .into(),
        ));
    }
    if model.tangential_stress {
        return Err(GpuError::Unsupported(
            "surface_tension.tensor = \"tangential\" is CPU only (the WGSL stages carry the traceless \
             Hu–Adams tensor alone); use --backend cpu or tensor = \"traceless\""
                .into(),
        ));
    }
    if model.transport_p_b.is_some() {
        return Err(GpuError::Unsupported(
            "time.background = \"transport\" (transport-velocity formulation) is CPU only (the WGSL \
             stages add p_b to the EOS pressure); use --backend cpu or background = \"momentum\""
                .into(),
        ));
    }
    if scene.time.integrator == Integrator::VerletPec {
        return Err(GpuError::Unsupported(
            "time.integrator = \"verlet-pec\" is CPU only (the WGSL Verlet evaluates at the predicted \
             velocity); use --backend cpu or integrator = \"verlet\""
                .into(),
        ));
    }
    Ok(())
}
