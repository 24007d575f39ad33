// equation_of_state.wgsl (thread mapping): ρ = mσ and the Tait pressure of every particle
// (common/epilogues.wgsl, which the number-density pass runs itself when fused). Twin of
// `cpu::stages::{eos_phase, equation_of_state}`.

#import common/epilogues

@compute @workgroup_size(GROUP_THREADS)
fn equation_of_state(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i < params.n {
        equation_of_state_at(i);
    }
}
