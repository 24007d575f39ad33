// integrate.wgsl (thread mapping): the integrator stages of §7.2 on fluid particles, each
// followed by the mirror/periodic boundary fix (`boundary_axis` of shaders/geometry.wgsl):
// `midpoint_predict` (saves r⁰, v⁰), `midpoint_correct`, `verlet_drift` (kick + drift, saves
// v_{n+½} in state0[n..]), `verlet_kick`; plus `check` (the FIRST bad particle and step, kept in `ctl` until read back)
// and `reduce_max` (max |v|, |a| as f32 bits by u32 atomicMax, for the adaptive dt).

#import common/bindings
#import integrate

// Stores r, v of fluid particle i after the boundary fix.
fn store_fixed(i: u32, r: real2, v: real2) {
    var x = r.x;
    var y = r.y;
    var vx = v.x;
    var vy = v.y;
    boundary_axis(params, 0u, params.lo_x, params.hi_x, &x, &vx);
    boundary_axis(params, 2u, params.lo_y, params.hi_y, &y, &vy);
    pos[i] = real2(x, y);
    vel[i] = real2(vx, vy);
}

@compute @workgroup_size(64)
fn midpoint_predict(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n_fluid {
        return;
    }
    state0[i] = pos[i];
    state0[params.n + i] = vel[i];
    let s = integrate_predict(pos[i], vel[i], vt[i], acc[i], params.dt);
    store_fixed(i, s.r, s.v);
}

@compute @workgroup_size(64)
fn midpoint_correct(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n_fluid {
        return;
    }
    let s = integrate_correct(state0[i], state0[params.n + i], vt[i], acc[i], params.dt);
    store_fixed(i, s.r, s.v);
}

@compute @workgroup_size(64)
fn verlet_drift(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n_fluid {
        return;
    }
    let v0 = vel[i];
    let vh = integrate_kick(v0, acc[i], params.dt);
    let r = integrate_drift(pos[i], vh + (vt[i] - v0), params.dt);
    // v_{n+½} (with the same mirror fix) waits in state0[n + i] for the closing kick; the
    // evaluation sees the predicted v_n + dt·a_n (second order with viscosity, as the CPU's).
    var x = r.x;
    var y = r.y;
    var hx = vh.x;
    var hy = vh.y;
    boundary_axis(params, 0u, params.lo_x, params.hi_x, &x, &hx);
    boundary_axis(params, 2u, params.lo_y, params.hi_y, &y, &hy);
    state0[params.n + i] = real2(hx, hy);
    store_fixed(i, r, integrate_kick(vh, acc[i], params.dt));
}

@compute @workgroup_size(64)
fn verlet_kick(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n_fluid {
        return;
    }
    // The transport velocity follows the kick (ṽ − v keeps the evaluation's XSPH correction for
    // the next drift), as in the CPU reference's Verlet.
    let vn = integrate_kick(state0[params.n + i], acc[i], params.dt);
    vt[i] = vt[i] + (vn - vel[i]);
    store_fixed(i, pos[i], vn);
}

// Non-finite test on the f32 bits (NaN/inf comparisons may be folded away by the compiler);
// in f64 a magnitude beyond f32 range counts too (such a particle has left the domain anyway).
fn bad_real(x: real) -> bool {
    return (bitcast<u32>(f32(x)) & 0x7f800000u) == 0x7f800000u;
}

fn bad_vec(v: real2) -> bool {
    return bad_real(v.x) || bad_real(v.y);
}

// Blow-up check after a step (step number = params.step): the first step with a bad particle
// wins; within it the smallest 2·i + kind (kind 0 non-finite, 1 left the domain by > Δx/2).
@compute @workgroup_size(64)
fn check(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n_fluid {
        return;
    }
    let p = pos[i];
    let tol = real(0.5) * params.dx;
    var kind = 2u;
    if bad_vec(p) || bad_vec(vel[i]) || bad_vec(acc[i]) {
        kind = 0u;
    } else if p.x < params.lo_x - tol || p.x > params.hi_x + tol || p.y < params.lo_y - tol
        || p.y > params.hi_y + tol {
        kind = 1u;
    }
    if kind == 2u {
        return;
    }
    let prev = atomicMin(&ctl[CTL_BAD_STEP], params.step);
    if prev >= params.step {
        atomicMin(&ctl[CTL_BAD], 2u * i + kind);
    }
}

// max |v| and max |a| over the fluids (non-negative f32 bits order like the floats).
@compute @workgroup_size(64)
fn reduce_max(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.n_fluid {
        return;
    }
    let v = vel[i];
    let a = acc[i];
    atomicMax(&ctl[CTL_VMAX], bitcast<u32>(f32(sqrt(v.x * v.x + v.y * v.y))));
    atomicMax(&ctl[CTL_AMAX], bitcast<u32>(f32(sqrt(a.x * a.x + a.y * a.y))));
}
