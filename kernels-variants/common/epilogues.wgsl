// epilogues.wgsl: the per-particle stages that the stage table lets run at the end of a
// neighbour pass, in the thread that has just written particle i's output (core/src/stage.rs,
// `epilogue_of`): the wall typing and the equation of state after the number density,
// Algorithm 1 and the surface stress after the colour gradient. Of what the pass writes each
// reads only particle i's own output (the contact points come from the pass before), so the
// fused kernel (composed with `FUSE_<STAGE>`, common/pair_terms.wgsl's output functions call
// these) and the stage's own thread kernel (thread/<stage>.wgsl, the unfused debug path)
// compute the same numbers. Twins of `cpu::stages::{wall_typing, equation_of_state,
// normal_correction, surface_stress}`.

#import common/bindings
#import eos
#import contact

// Algorithm 2 on wall particle i: below y_w, the side of the interpolation line through the
// nearest contact point gives the liquid (0) or gas (1) colour; otherwise (or without contact
// points) untyped. Mass per T83.
fn wall_typing_at(i: u32) {
    var c = NO_COLOUR;
    let r = pos[i];
    if r.y < params.y_wall {
        let k = nearest_contact(r);
        if k >= 0 {
            let tp = real2(contacts[CONTACT_WORDS * u32(k)], contacts[CONTACT_WORDS * u32(k) + 1u]);
            c = select(1, 0, contact_side(r, tp, contact_normal_of(k)) < real(0.0));
        }
    }
    colour[i] = c;
    mass[i] = params.mass[select(params.wall_phase, u32(c), c >= 0)];
}

// ρ = mσ and the Tait pressure of particle i, with the EOS of its fluid phase, a wall's typed
// phase or the wall phase.
fn equation_of_state_at(i: u32) {
    var ph = params.wall_phase;
    if i < params.n_fluid {
        ph = phase[i];
    } else if colour[i] == 0 || colour[i] == 1 {
        ph = u32(colour[i]);
    }
    let r = mass[i] * sigma[i].x;
    rho[i] = r;
    pres[i] = eos_pressure(r, params.rho0[ph], params.stiffness[ph], params.gamma[ph], params.p_b[ph]);
}

// Algorithm 1 on particle i: near the wall (fluid with y − y_w ≤ band, or any coloured wall
// particle) the gradient towards the other fluid keeps its magnitude and takes the direction
// ±n̂_θ of the nearest contact point; in place on grad slot 0.
fn normal_correction_at(i: u32) {
    let k = colour[i];
    let g = grad0[i];
    if !(k == 0 || k == 1) || g.x * g.x + g.y * g.y == real(0.0) {
        return;
    }
    if i < params.n_fluid && pos[i].y - params.y_wall > params.band {
        return;
    }
    let cp = nearest_contact(pos[i]);
    if cp < 0 {
        return;
    }
    grad0[i] = corrected_normal(g, contact_normal_of(cp), k == 0);
}

// T73–T75, Π_i = Σ_l σ^{kl} |g^{kl}| (I/2 − n̂n̂) over the gradient slots of particle i's
// colour; zero for uncoloured particles.
fn surface_stress_at(i: u32) {
    let k = colour[i];
    var t = Sym2(real(0.0), real(0.0));
    if k >= 0 {
        for (var slot = 0; slot < 2; slot++) {
            let l = select(slot + 1, slot, slot < k);
            if l < 3 {
                t = sym2_add(t, stress_tensor(grad_at(i, u32(slot)), params_sigma(params, k, l)));
            }
        }
    }
    pi[i] = real2(t.xx, t.xy);
}
