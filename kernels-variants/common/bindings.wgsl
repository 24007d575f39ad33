// bindings.wgsl: the one bind group every solver stage uses (group 0; twin of `Bufs::storage`
// in src/gpu/solver_buffers.rs). All pipelines share one explicit layout, so a stage
// binds the whole particle state and touches only what it reads or writes. The boundary
// geometry (images, walls, boundary fix) is in shaders/geometry.wgsl, called with `params`.
// Library module: no entry points.

#import types
#import stress
#import geometry
#import common/dispatch

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> pos: array<real2>;
@group(0) @binding(2) var<storage, read_write> vel: array<real2>;
@group(0) @binding(3) var<storage, read_write> phase: array<u32>;
@group(0) @binding(4) var<storage, read_write> pos0: array<real2>;    // r⁰ of the midpoint step
@group(0) @binding(5) var<storage, read_write> vel0: array<real2>;    // v⁰ (midpoint), v_{n+½} (Verlet)
@group(0) @binding(6) var<storage, read_write> sigma: array<real2>;  // (σ, 1/σ²)
@group(0) @binding(7) var<storage, read_write> chi: array<real>;
@group(0) @binding(8) var<storage, read_write> mass: array<real>;
@group(0) @binding(9) var<storage, read_write> colour: array<i32>;
@group(0) @binding(10) var<storage, read_write> rho: array<real>;
@group(0) @binding(11) var<storage, read_write> pres: array<real>;
@group(0) @binding(12) var<storage, read_write> grad0: array<real2>;  // ∇C slot 0 of each particle
@group(0) @binding(13) var<storage, read_write> grad1: array<real2>;  // ∇C slot 1
@group(0) @binding(14) var<storage, read_write> pi: array<real2>;      // (Π_xx, Π_xy)
@group(0) @binding(15) var<storage, read_write> acc: array<real2>;
@group(0) @binding(16) var<storage, read_write> vt: array<real2>;
@group(0) @binding(17) var<storage, read_write> contacts: array<real>; // CONTACT_WORDS × MAX_CONTACTS (types.wgsl)
@group(0) @binding(18) var<storage, read_write> ctl: array<atomic<u32>>;
@group(0) @binding(19) var<storage, read_write> cell_counts: array<atomic<u32>>;
@group(0) @binding(20) var<storage, read_write> cell_start: array<u32>;
@group(0) @binding(21) var<storage, read_write> sorted: array<u32>;
@group(0) @binding(22) var<storage, read_write> cell_of: array<u32>;

// Words of `ctl` (twin of `CTL_*` in src/gpu/solver_buffers.rs).
const CTL_CONTACTS_FOUND: u32 = 0u; // points found in the last contact_line (may exceed 32)
const CTL_CONTACTS: u32 = 1u;       // unused (the points kept are min(found, MAX_CONTACTS))
const CTL_BAD_STEP: u32 = 2u;       // first step with a bad particle (0xFFFFFFFF: none)
const CTL_BAD: u32 = 3u;            // 2·particle + (0 non-finite, 1 left the domain)
const CTL_VMAX: u32 = 4u;           // f32 bits of max |v| (fluids)
const CTL_AMAX: u32 = 5u;           // f32 bits of max |a| (fluids)
const CTL_CONTACTS_MAX: u32 = 6u;   // largest contact count seen since the last read
const CTL_STEP: u32 = 7u;           // device clock: steps completed (src/gpu/clock.rs)
const CTL_OVER_STEP: u32 = 8u;      // first step whose evaluations overflowed (0xFFFFFFFF: none)
const CTL_DONE: u32 = 9u;           // workgroups done in a fused integrator stage or reduce_max (thread/integrate.wgsl)
const CTL_SCAN_MISS: u32 = 10u;     // first step whose cell scan did not sum to n (0xFFFFFFFF: none; common/neighbours.wgsl)

// Colour-gradient slot s (0 or 1) of particle i: one binding per slot, so neither passes the
// storage-binding cap before the per-particle vec2 arrays do (src/plan/gpu.rs).
fn grad_at(i: u32, s: u32) -> real2 {
    if s == 0u {
        return grad0[i];
    }
    return grad1[i];
}

// (x, s) of contact point a before that of point b (the CPU's sort order).
fn contact_before(a: u32, b: u32) -> bool {
    let xa = contacts[CONTACT_WORDS * a];
    let xb = contacts[CONTACT_WORDS * b];
    return xa < xb || (xa == xb && contacts[CONTACT_WORDS * a + 2u] < contacts[CONTACT_WORDS * b + 2u]);
}

// Index of the contact point nearest to r (the first in (x, s) order on ties, whatever order
// the points were appended in), or −1 when there is none. Twin of `cpu::stages::nearest_contact`.
fn nearest_contact(r: real2) -> i32 {
    let count = min(atomicLoad(&ctl[CTL_CONTACTS_FOUND]), MAX_CONTACTS);
    var best = -1;
    var bd = real(0.0);
    for (var k = 0u; k < count; k++) {
        let d = r - real2(contacts[CONTACT_WORDS * k], contacts[CONTACT_WORDS * k + 1u]);
        let d2 = d.x * d.x + d.y * d.y;
        if best < 0 || d2 < bd || (d2 == bd && contact_before(k, u32(best))) {
            best = i32(k);
            bd = d2;
        }
    }
    return best;
}

// Outward liquid normal n̂_θ = (s·sin θ, cos θ) of contact point k (T81; sin, cos from the host),
// or of the angle measured there with the unbalanced Young force (§8.2.5; word 3, `contact_angle`).
// Twin of `cpu::stages::typing_normal`.
fn contact_normal_of(k: i32) -> real2 {
    let base = CONTACT_WORDS * u32(k);
    if params_has(params, STAGE_YOUNG_UNBALANCED) {
        let c = contacts[base + 3u];
        return real2(contacts[base + 2u] * sqrt(max(real(0.0), real(1.0) - c * c)), c);
    }
    return real2(contacts[base + 2u] * params.sin_theta, params.cos_theta);
}

// Mode A's unbalanced Young force on fluid particle i along x (§8.2.5): Σ_cp (F s / Σ_j W_j)_cp
// W(|x_i − x_cp|) / m_i, the per-point factor from `contact_angle` (word 4). Twin of
// `cpu::line_force::line_force_acc` with the kernel spread.
fn young_line_acc(i: u32) -> real {
    let count = min(atomicLoad(&ctl[CTL_CONTACTS_FOUND]), MAX_CONTACTS);
    let kp = params_kernel(params);
    var a = real(0.0);
    for (var k = 0u; k < count; k++) {
        let base = CONTACT_WORDS * k;
        let d = pos[i] - real2(contacts[base], contacts[base + 1u]);
        a += contacts[base + 4u] * kernel_w(kp, sqrt(d.x * d.x + d.y * d.y));
    }
    return a / mass[i];
}
