// integrate.wgsl (thread mapping): the integrator stages of §7.2 on fluid particles, each
// followed by the mirror/periodic boundary fix (`boundary_axis` of shaders/geometry.wgsl):
// `midpoint_predict` (saves r⁰, v⁰), `midpoint_correct`, `verlet_drift` (kick + drift, saves
// v_{n+½} in vel0), `verlet_kick`; plus `check` (the FIRST bad particle and step, kept in `ctl` until read back)
// and `reduce_max` (max |v|, |a| as f32 bits: workgroup reduction, then one u32 atomicMax per
// workgroup, for the adaptive dt).
//
// The device clock (src/gpu/clock.rs): the step counter is `ctl[CTL_STEP]`, dt and the time
// (a compensated sum t + t_lo) are `vparams[VP_DT]`, `vparams[VP_T]`, `vparams[VP_T_LO]`, so many
// steps run in one submission with no host write in between. An adaptive dt is computed from
// `reduce_max`'s maxima by the opening integrator stage (`opening_dt`); `clock_tick` (one thread, first kernel of `check`) ends the
// step, or, with the check fused into the closing stage, the last workgroup of that stage does. Once a step has failed (NaN, escape, neighbour or fixed-point overflow) the device is
// halted: the integrators and the clock stop, so positions, velocities, step and t stay those of
// the failing step until the host reads the flags.

#import common/bindings
#import common/variant_bindings
#import common/neighbours
#import integrate
#import timestep

// True once a step failed (the clock and the integrators stop).
fn halted() -> bool {
    return atomicLoad(&ctl[CTL_BAD_STEP]) != 0xffffffffu || atomicLoad(&ctl[CTL_OVER_STEP]) != 0xffffffffu;
}

// dt of the step being taken (fixed: written once by the host; adaptive: by `opening_dt`).
fn clock_dt() -> real {
    return vparams[VP_DT];
}

// dt in an opening integrator stage. Adaptive: `DtLimits::compute(...).min()` from the maxima
// of `reduce_max`, a pass earlier, so every workgroup's maxima are visible (no last-workgroup
// read of other workgroups' atomics), computed alike by every thread; thread 0 stores it for
// the closing stage and the clock. Fixed dt, or a halted device: the stored dt.
fn opening_dt(i: u32) -> real {
    if vparams[VP_ADAPTIVE] == real(0.0) || halted() {
        return vparams[VP_DT];
    }
    let v_max = real(bitcast<f32>(atomicLoad(&ctl[CTL_VMAX])));
    let a_max = real(bitcast<f32>(atomicLoad(&ctl[CTL_AMAX])));
    let dt = dt_limits_min(params.h, vparams[VP_CFL], vparams[VP_C_MAX], v_max, vparams[VP_NU_MAX], a_max,
        vparams[VP_RHO_MEAN], vparams[VP_SIGMA_MAX]);
    if i == 0u {
        vparams[VP_DT] = dt;
    }
    return dt;
}

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

// With `FUSE_CELL_COUNT` (the stage table's `cell_count` as the epilogue of an integrator
// stage) the kernel runs over every particle: fluids are integrated, then every fluid's cell
// is counted where it now stands (a halted device's particles where they are); with
// `FUSE_CELL_SCAN` the last workgroup then scans the counts into the cell starts (`pass_end`),
// so the integrator stages have no early return.
fn moved_count(i: u32) {
#ifdef FUSE_CELL_COUNT
    if i < params.n_fluid {
        cell_count_at(i);
    }
#endif
}

@compute @workgroup_size(GROUP_THREADS)
fn midpoint_predict(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = linear_id(gid, nwg);
    let dt = opening_dt(i);
    if i < params.n_fluid && !halted() {
        pos0[i] = pos[i];
        vel0[i] = vel[i];
        let s = integrate_predict(pos[i], vel[i], vt[i], acc[i], dt);
        store_fixed(i, s.r, s.v);
    }
    moved_count(i);
    pass_end(t, nwg);
}

// The closing stages (`midpoint_correct`, `verlet_kick`) have no early return: with
// `FUSE_CHECK` (the stage table's `check` as their epilogue, core/src/stage.rs) every thread
// checks its particle right after integrating it and the last workgroup to finish ticks the
// clock (`end_step`), which needs the whole workgroup at its barrier.
@compute @workgroup_size(GROUP_THREADS)
fn midpoint_correct(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = linear_id(gid, nwg);
    if i < params.n_fluid && !closing_halted() {
        let s = integrate_correct(pos0[i], vel0[i], vt[i], acc[i], clock_dt());
        store_fixed(i, s.r, s.v);
        closing_check(i);
    }
    moved_count(i);
    pass_end(t, nwg);
}

@compute @workgroup_size(GROUP_THREADS)
fn verlet_drift(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = linear_id(gid, nwg);
    let dt = opening_dt(i);
    if i < params.n_fluid && !halted() {
        verlet_drift_at(i, dt);
    }
    moved_count(i);
    pass_end(t, nwg);
}

fn verlet_drift_at(i: u32, dt: real) {
    let v0 = vel[i];
    let vh = integrate_kick(v0, acc[i], dt);
    let r = integrate_drift(pos[i], vh + (vt[i] - v0), dt);
    // v_{n+½} (with the same mirror fix) waits in vel0[i] for the closing kick; the
    // evaluation sees the predicted v_n + dt·a_n (second order with viscosity, as the CPU's).
    var x = r.x;
    var y = r.y;
    var hx = vh.x;
    var hy = vh.y;
    boundary_axis(params, 0u, params.lo_x, params.hi_x, &x, &hx);
    boundary_axis(params, 2u, params.lo_y, params.hi_y, &y, &hy);
    vel0[i] = real2(hx, hy);
    store_fixed(i, r, integrate_kick(vh, acc[i], dt));
}

@compute @workgroup_size(GROUP_THREADS)
fn verlet_kick(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = linear_id(gid, nwg);
    if i < params.n_fluid && !closing_halted() {
        // The transport velocity follows the kick (ṽ − v keeps the evaluation's XSPH correction
        // for the next drift), as in the CPU reference's Verlet.
        let vn = integrate_kick(vel0[i], acc[i], clock_dt());
        vt[i] = vt[i] + (vn - vel[i]);
        store_fixed(i, pos[i], vn);
        closing_check(i);
    }
    moved_count(i);
    pass_end(t, nwg);
}

// Non-finite test on the f32 bits (NaN/inf comparisons may be folded away by the compiler);
// in f64 a magnitude beyond f32 range counts too (such a particle has left the domain anyway).
fn bad_real(x: real) -> bool {
    return (bitcast<u32>(f32(x)) & 0x7f800000u) == 0x7f800000u;
}

fn bad_vec(v: real2) -> bool {
    return bad_real(v.x) || bad_real(v.y);
}

// Blow-up check of fluid particle i after step `step`: the first step with a bad particle
// wins; within it the smallest 2·i + kind (kind 0 non-finite, 1 left the domain by > Δx/2).
fn check_at(i: u32, step: u32) {
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
    let prev = atomicMin(&ctl[CTL_BAD_STEP], step);
    if prev >= step {
        atomicMin(&ctl[CTL_BAD], 2u * i + kind);
    }
}

// The check as its own stage, after a step (step number = ctl[CTL_STEP], just advanced by
// clock_tick).
@compute @workgroup_size(GROUP_THREADS)
fn check(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = linear_id(gid, nwg);
    if i < params.n_fluid {
        check_at(i, atomicLoad(&ctl[CTL_STEP]));
    }
}

// True once a step before the one being completed failed (a failure recorded in this step's
// closing kernel, by `check_at` or the tick, does not stop the particles not yet integrated).
// A failure is recorded with the step it happens in, which the clock then reaches, so before
// the check and the tick of a step this is `halted()`.
fn failed_before() -> bool {
    let now = atomicLoad(&ctl[CTL_STEP]);
    return atomicLoad(&ctl[CTL_BAD_STEP]) <= now || atomicLoad(&ctl[CTL_OVER_STEP]) <= now;
}

fn closing_halted() -> bool {
#ifdef FUSE_CHECK
    return failed_before();
#else
    return halted();
#endif
}

// The fused check of particle i, with the number of the step being completed (the clock ticks
// at the end of this kernel).
fn closing_check(i: u32) {
#ifdef FUSE_CHECK
    check_at(i, atomicLoad(&ctl[CTL_STEP]) + 1u);
#endif
}

// End of an integrator kernel with an epilogue that needs every particle done: the clock tick
// of the fused `check`, the fused `cell_scan` (none otherwise).
fn pass_end(t: u32, nwg: vec3<u32>) {
#ifdef FUSE_CHECK
    last_group_end(t, nwg);
#else
#ifdef FUSE_CELL_SCAN
    last_group_end(t, nwg);
#endif
#endif
}

// Each workgroup, once all its threads are done (the barrier), counts itself in ctl[CTL_DONE];
// the last one resets the count, ticks the clock (after every thread of the dispatch has read
// it) and scans the cell counts every workgroup has counted (its whole workgroup: the flag is
// loaded uniformly, so the scan's barriers are uniform).
var<workgroup> last_group: u32;

fn last_group_end(t: u32, nwg: vec3<u32>) {
    storageBarrier();
    if t == 0u {
        var last = 0u;
        if atomicAdd(&ctl[CTL_DONE], 1u) + 1u == nwg.x * nwg.y * nwg.z {
            atomicStore(&ctl[CTL_DONE], 0u);
            last = 1u;
#ifdef FUSE_CHECK
            if !failed_before() {
                tick();
            }
#endif
        }
        last_group = last;
    }
#ifdef FUSE_CELL_SCAN
    if workgroupUniformLoad(&last_group) == 1u {
        scan_cells_in_group(t);
    }
#endif
}

// max |v| and max |a| over the fluids (non-negative f32 bits order like the floats): a tree
// reduction in workgroup memory first, then ONE atomicMax per workgroup and quantity.
var<workgroup> wg_vmax: array<u32, GROUP_THREADS>;
var<workgroup> wg_amax: array<u32, GROUP_THREADS>;

@compute @workgroup_size(GROUP_THREADS)
fn reduce_max(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = linear_id(gid, nwg);
    var vb = 0u;
    var ab = 0u;
    if i < params.n_fluid {
        let v = vel[i];
        let a = acc[i];
        vb = bitcast<u32>(f32(sqrt(v.x * v.x + v.y * v.y)));
        ab = bitcast<u32>(f32(sqrt(a.x * a.x + a.y * a.y)));
    }
    wg_vmax[t] = vb;
    wg_amax[t] = ab;
    workgroupBarrier();
    for (var s = GROUP_THREADS / 2u; s > 0u; s >>= 1u) {
        if t < s {
            wg_vmax[t] = max(wg_vmax[t], wg_vmax[t + s]);
            wg_amax[t] = max(wg_amax[t], wg_amax[t + s]);
        }
        workgroupBarrier();
    }
    if t == 0u {
        atomicMax(&ctl[CTL_VMAX], wg_vmax[0]);
        atomicMax(&ctl[CTL_AMAX], wg_amax[0]);
    }
}

// End of a step (one thread, before `check`): step + 1, t + dt (two-sum: the rounding error of
// each addition is kept in t_lo, so t = t + t_lo stays exact to the precision's square), and the
// first step whose evaluations overflowed a neighbour list, a candidate list or the fixed-point
// range is recorded in ctl[CTL_OVER_STEP]. Nothing moves once halted.
@compute @workgroup_size(1)
fn clock_tick() {
    if !halted() {
        tick();
    }
}

fn tick() {
    let step = atomicLoad(&ctl[CTL_STEP]) + 1u;
    atomicStore(&ctl[CTL_STEP], step);
    let t = vparams[VP_T];
    let dt = vparams[VP_DT];
    let s = t + dt;
    let b = s - t;
    vparams[VP_T] = s;
    vparams[VP_T_LO] = vparams[VP_T_LO] + ((t - (s - b)) + (dt - b));
    let over = atomicLoad(&vctl[V_NBR_OVER]) + atomicLoad(&vctl[V_CAND_OVER]) + atomicLoad(&vctl[V_CAND_STALE])
        + atomicLoad(&vctl[V_FIXED_OVER]);
    if over > 0u {
        atomicMin(&ctl[CTL_OVER_STEP], step);
    }
}
