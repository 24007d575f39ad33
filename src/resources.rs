//! The lab's buffers in a run's resource plan: the core's plan of the solver
//! ([`Plan::new`]: particle state, neighbours, read-back frame) plus what the lab allocates
//! beside it, the contact-angle diagnostic and the VTK writer, each counted by the module that
//! allocates it.

use crate::plan::Plan;
use crate::scene::{ContactMode, Scene};

/// The plan of a run of `scene` (`real` = 4 or 8 bytes; `gpu`: the default GPU variant, see
/// [`Plan::new`]) with the contact-angle diagnostic when the scene has a contact model.
pub fn run_plan(scene: &Scene, real: usize, gpu: bool) -> Plan {
    let plan = Plan::new(scene, real, gpu);
    if scene.contact.mode == ContactMode::None {
        return plan;
    }
    let bytes = crate::diagnostics::contact_angle::max_bytes(plan.n_fluid);
    plan.with_buffer("contact-angle gas grid and interface points", "diagnostics", bytes)
}

/// The plan with the VTK writer (`--vtk`): the text of one data array at a time.
pub fn with_vtk(plan: Plan, vtk: bool) -> Plan {
    if !vtk {
        return plan;
    }
    let bytes = crate::output::snapshot::vtk_buffer_bytes(plan.n_total);
    plan.with_buffer("VTK text of one data array", "outputs", bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin::builtin;
    use crate::scene::overrides::apply_overrides;

    #[test]
    fn outputs_and_diagnostics_are_planned() {
        let s = apply_overrides(&builtin("sessile-90").unwrap(), &["domain.nx=40".into()]).unwrap();
        let p = run_plan(&s, 8, false);
        let names: Vec<&str> = p.host.iter().map(|b| b.name).collect();
        assert!(p.diagnostic_bytes > 0.0 && p.output_bytes > 0.0, "{names:?}");
        assert!(names.iter().any(|n| n.contains("contact-angle")) && !names.iter().any(|n| n.contains("VTK")));
        let v = with_vtk(p.clone(), true);
        assert!(v.output_bytes > p.output_bytes && v.total_bytes > p.total_bytes);
        let sum: f64 = v.host.iter().map(|b| b.bytes).sum();
        assert_eq!(v.total_bytes, sphlab_core::plan::BASE_BYTES + sum);
        // No contact model: no contact-angle diagnostic.
        let drop = apply_overrides(&builtin("oscillating-drop").unwrap(), &["domain.nx=40".into()]).unwrap();
        assert_eq!(run_plan(&drop, 8, false).diagnostic_bytes, 0.0);
    }
}
