// pair_sums.wgsl (subgroup mapping, beyond the thesis): one SUBGROUP per particle over its
// explicit 64-slot list. Lane l of a subgroup of size S takes slots l, l + S, l + 2S, …, the
// lanes' partial sums are added by `subgroupAdd` (no atomics, no workgroup memory, no
// barrier), and lane 0 applies the per-particle prefactors and writes the field
// (common/pair_terms.wgsl, as in every mapping). A 64-thread workgroup holds `num_subgroups`
// particles (64/S); the host dispatches for the adapter's largest subgroup size, so workgroups
// past N do nothing. Needs Features::SUBGROUP and S ≤ 64 (`VariantSpec::support`). Every lane
// reaches `subgroupAdd` (no early return), so the sum covers the whole subgroup.

#import common/pair_terms

// Particle of this subgroup.
fn sg_particle(wg: vec3<u32>, nwg: vec3<u32>, sid: u32, nsg: u32) -> u32 {
    return linear_group_xy(wg, nwg) * nsg + sid;
}

@compute @workgroup_size(64)
fn number_density(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(subgroup_id) sid: u32, @builtin(num_subgroups) nsg: u32, @builtin(subgroup_invocation_id) lane: u32, @builtin(subgroup_size) size: u32) {
    let i = sg_particle(wg, nwg, sid, nsg);
    var s = real2(real(0.0), real(0.0));
    if i < params.n {
        let kp = params_kernel(params);
        let xi = pos[i];
        for (var k = lane; k < list_len(i); k += size) {
            s += density_pair(i, kp, list_pair(i, xi, k));
        }
    }
    let t = subgroupAdd(s);
    if lane == 0u && i < params.n {
        density_out(i, t);
    }
}

@compute @workgroup_size(64)
fn colour_gradient(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(subgroup_id) sid: u32, @builtin(num_subgroups) nsg: u32, @builtin(subgroup_invocation_id) lane: u32, @builtin(subgroup_size) size: u32) {
    let i = sg_particle(wg, nwg, sid, nsg);
    var g0 = real2(real(0.0), real(0.0));
    var g1 = real2(real(0.0), real(0.0));
    if i < params.n && colour[i] >= 0 {
        let kp = params_kernel(params);
        let xi = pos[i];
        let c = colour[i];
        for (var k = lane; k < list_len(i); k += size) {
            let t = grad_pair(c, kp, list_pair(i, xi, k));
            g0 += t.g0;
            g1 += t.g1;
        }
    }
    let a = subgroupAdd(g0);
    let b = subgroupAdd(g1);
    if lane == 0u && i < params.n {
        grad_out(i, Grad2(a, b));
    }
}

@compute @workgroup_size(64)
fn acceleration(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(subgroup_id) sid: u32, @builtin(num_subgroups) nsg: u32, @builtin(subgroup_invocation_id) lane: u32, @builtin(subgroup_size) size: u32) {
    let i = sg_particle(wg, nwg, sid, nsg);
    var sum = real2(real(0.0), real(0.0));
    if i < params.n_fluid {
        let kp = params_kernel(params);
        let c = acc_ctx(i);
        for (var k = lane; k < list_len(i); k += size) {
            sum += acc_pair(i, c, kp, list_pair(i, c.xi, k));
        }
    }
    let t = subgroupAdd(sum);
    if lane == 0u && i < params.n {
        acc_out(i, t);
    }
}
