// pair_sums.wgsl (subgroup mapping, beyond the thesis): a GROUP of G = min(LANES, S) lanes of
// a subgroup of S lanes per particle over its explicit 64-slot list (S and LANES powers of two,
// so G divides S and one subgroup holds S / G particles). Lane r of a group takes slots r,
// r + G, r + 2G, …; the group's partial sums are added by a `subgroupShuffleXor` butterfly
// (offsets G/2, …, 1; afterwards every lane of the group holds the group's sum; no atomics, no
// workgroup memory, no barrier), and the group's lane 0 applies the per-particle prefactors
// and writes the field (common/pair_terms.wgsl, as in every mapping). A 64-thread workgroup
// holds 64 / G particles; the host dispatches for G at the adapter's largest subgroup size
// (`GpuSolver::groups`), so a smaller S only puts more particles in a workgroup, and groups
// past N do nothing. Needs Features::SUBGROUP and S ≤ 64 (`VariantSpec::support`). Every lane
// reaches every shuffle (no early return; the butterfly's trip count depends on S alone), so
// each exchange stays inside one particle's group.

#import common/pair_terms

// Lanes per particle (`SUBGROUP_LANES` in core/src/gpu/variant.rs): 16, a group sized to the
// ~30–40 neighbours of a particle (the whole subgroup when S ≤ 16). A test composes 2, 4 or 8
// (`LANES2`, `LANES4`, `LANES8`; `GpuSolver::with_subgroup_lanes`) so that several particles
// share even a small subgroup.
#ifdef LANES2
const LANES: u32 = 2u;
#else
#ifdef LANES4
const LANES: u32 = 4u;
#else
#ifdef LANES8
const LANES: u32 = 8u;
#else
const LANES: u32 = 16u;
#endif
#endif
#endif

// A lane's place: its particle `i` (the workgroup's particles in subgroup order, S / G per
// subgroup), its rank `r` in the particle's group and the group's size `g`.
struct Place {
    i: u32,
    r: u32,
    g: u32,
}

fn sg_place(wg: vec3<u32>, nwg: vec3<u32>, sid: u32, nsg: u32, lane: u32, size: u32) -> Place {
    let g = min(LANES, size);
    let i = chunk_particle((linear_group_xy(wg, nwg) * nsg + sid) * (size / g) + lane / g);
    return Place(i, lane % g, g);
}

// The sum of `v` over the g lanes of this lane's group (g a power of two), in every lane of the
// group: lanes exchange across offsets g/2, …, 1, which never cross a group's bounds.
fn group_sum(v: real2, g: u32) -> real2 {
    var s = v;
    for (var o = g / 2u; o > 0u; o = o / 2u) {
        s += subgroupShuffleXor(s, o);
    }
    return s;
}

@compute @workgroup_size(64)
fn number_density(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(subgroup_id) sid: u32, @builtin(num_subgroups) nsg: u32, @builtin(subgroup_invocation_id) lane: u32, @builtin(subgroup_size) size: u32) {
    let p = sg_place(wg, nwg, sid, nsg, lane, size);
    let i = p.i;
    var s = real2(real(0.0), real(0.0));
    if i < params.n {
        let kp = params_kernel(params);
        let xi = pos[i];
        for (var k = p.r; k < list_len(i); k += p.g) {
            s += density_pair(i, kp, list_pair(i, xi, k));
        }
    }
    let t = group_sum(s, p.g);
    if p.r == 0u && i < params.n {
        density_out(i, t);
    }
}

@compute @workgroup_size(64)
fn colour_gradient(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(subgroup_id) sid: u32, @builtin(num_subgroups) nsg: u32, @builtin(subgroup_invocation_id) lane: u32, @builtin(subgroup_size) size: u32) {
    let p = sg_place(wg, nwg, sid, nsg, lane, size);
    let i = p.i;
    var g0 = real2(real(0.0), real(0.0));
    var g1 = real2(real(0.0), real(0.0));
    if i < params.n && colour[i] >= 0 {
        let kp = params_kernel(params);
        let xi = pos[i];
        let c = colour[i];
        for (var k = p.r; k < list_len(i); k += p.g) {
            let t = grad_pair(c, kp, list_pair(i, xi, k));
            g0 += t.g0;
            g1 += t.g1;
        }
    }
    let a = group_sum(g0, p.g);
    let b = group_sum(g1, p.g);
    if p.r == 0u && i < params.n {
        grad_out(i, Grad2(a, b));
    }
}

@compute @workgroup_size(64)
fn acceleration(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(subgroup_id) sid: u32, @builtin(num_subgroups) nsg: u32, @builtin(subgroup_invocation_id) lane: u32, @builtin(subgroup_size) size: u32) {
    let p = sg_place(wg, nwg, sid, nsg, lane, size);
    let i = p.i;
    var sum = real2(real(0.0), real(0.0));
    if i < params.n_fluid {
        let kp = params_kernel(params);
        let c = acc_ctx(i);
        for (var k = p.r; k < list_len(i); k += p.g) {
            sum += acc_pair(i, c, kp, list_pair(i, c.xi, k));
        }
    }
    let t = group_sum(sum, p.g);
    if p.r == 0u && i < params.n {
        acc_out(i, t);
    }
}
