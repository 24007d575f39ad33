// contact.wgsl: contact-angle geometry of Mode B (docs/PHYSICS.md §8.3–8.4, thesis T81–T83,
// Algorithms 1–2). WGSL twin of src/physics/contact.rs, same names and argument order.
// Library module: functions only (no bindings, no entry points).
// NOTE: GLSL.std.450 Sin/Cos exist for 16/32-bit floats only: the f64 build evaluates them in f32.

// Corrected outward liquid normal at a contact point (T81): n̂_θ = (s·sin θ, cos θ).
fn contact_normal(theta: real, s: real) -> real2 {
#ifdef F64
    return real2(s * real(sin(f32(theta))), real(cos(f32(theta))));
#else
    return real2(s * sin(theta), cos(theta));
#endif
}

// Side test of the interpolation line (T82): s_w = (r_w − r_tp)·n̂_θ; negative = liquid side.
fn contact_side(r_w: real2, r_tp: real2, n_theta: real2) -> real {
    let d = r_w - r_tp;
    return d.x * n_theta.x + d.y * n_theta.y;
}

// Algorithm 1: keep |g|, replace its direction by +n̂_θ (liquid) or −n̂_θ (gas).
fn corrected_normal(g: real2, n_theta: real2, liquid: bool) -> real2 {
    let m = sqrt(g.x * g.x + g.y * g.y);
    if liquid {
        return n_theta * m;
    }
    return -(n_theta * m);
}
