// integrate.wgsl: time-integration updates (docs/PHYSICS.md §7.2): midpoint predictor–corrector and
// velocity Verlet. WGSL twin of src/physics/integrate.rs, same names and argument order; the
// Rust tuples `(r, v)` are returned as `PosVel`. `vt` is the advection velocity (v or XSPH).
// Library module: functions and structs only (no bindings, no entry points).

// A position and a velocity (twin of the Rust `(V2<T>, V2<T>)` return value).
struct PosVel {
    r: real2,
    v: real2,
}

// Midpoint predictor: r* = r + (dt/2) ṽ, v* = v + (dt/2) a.
fn integrate_predict(r: real2, v: real2, vt: real2, a: real2, dt: real) -> PosVel {
    let half = real(0.5) * dt;
    return PosVel(r + vt * half, v + a * half);
}

// Midpoint corrector from the start-of-step state: v = v⁰ + dt a*, r = r⁰ + dt ṽ*.
fn integrate_correct(r0: real2, v0: real2, vt_star: real2, a_star: real2, dt: real) -> PosVel {
    return PosVel(r0 + vt_star * dt, v0 + a_star * dt);
}

// Velocity-Verlet half kick: v + (dt/2) a.
fn integrate_kick(v: real2, a: real2, dt: real) -> real2 {
    return v + a * (real(0.5) * dt);
}

// Velocity-Verlet drift: r + dt ṽ.
fn integrate_drift(r: real2, vt: real2, dt: real) -> real2 {
    return r + vt * dt;
}
