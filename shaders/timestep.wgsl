// timestep.wgsl: the adaptive time step (docs/PHYSICS.md §7.3, thesis T52–T54 and the Brackbill
// capillary limit). WGSL twin of `DtLimits::compute(...).min()` in src/physics/timestep.rs, same
// argument order and the same operations in the same order; a limit whose physics is absent
// (ν = 0, |a| = 0, σ = 0) is infinite there and skipped here (WGSL has no infinity literal).
// Library module: functions only (no bindings, no entry points).

// min(CFL, viscous, force, capillary) of the state with max |v| = v_max and max |a| = a_max.
fn dt_limits_min(h: real, cfl: real, c_max: real, v_max: real, nu_max: real, a_max: real, rho_mean: real,
    sigma_max: real) -> real {
    var dt = cfl * h / (c_max + v_max);
    if nu_max > real(0.0) {
        dt = min(dt, real(0.125) * h * h / nu_max);
    }
    if a_max > real(0.0) {
        dt = min(dt, real(0.125) * sqrt(h / a_max));
    }
    if sigma_max > real(0.0) {
        dt = min(dt, real(0.25) * sqrt(rho_mean * h * h * h / (real(2.0) * real(3.141592653589793) * sigma_max)));
    }
    return dt;
}
