// equation_of_state.wgsl (thread mapping): ρ = mσ and the Tait pressure of every particle,
// with the EOS of its fluid phase, a wall's typed phase or the wall phase. Twin of
// `cpu::stages::{eos_phase, equation_of_state}`.

#import common/bindings
#import eos

@compute @workgroup_size(64)
fn equation_of_state(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i >= params.n {
        return;
    }
    var ph = params.wall_phase;
    if i < params.n_fluid {
        ph = phase[i];
    } else if colour[i] == 0 || colour[i] == 1 {
        ph = u32(colour[i]);
    }
    let r = mass[i] * sigma[i];
    rho[i] = r;
    pres[i] = eos_pressure(r, params.rho0[ph], params.stiffness[ph], params.gamma[ph], params.p_b[ph]);
}
