//! The two fluids of a sessile scene are interchangeable (docs/PHYSICS.md §8): with equal ρ0, μ,
//! c0 and p_b, a liquid cap under gas and a gas cap under liquid with the contact angle taken
//! from the other side (Mode A: σ_LS and σ_GS swapped; Mode B: θ_d → 180° − θ_d) are one flow.
//! Stepped side by side from the same lattice, every particle must follow the same path in
//! both: any term that treats phase 0 or 1 differently (the walls' EOS phase, the colour slots,
//! the wall typing, the corrected normal's side) shows as a difference far above round-off.
//!
//! The second test runs the swapped Mode B scene (liquid against the side wall in the first row)
//! through the GPU's `contact_line` twin: one evaluation of a thread variant in each precision
//! matches the CPU's, contact points included.
//!
//! Cost: 6 runs of 256 fluid particles for 300 steps, about a second each here; two GPU
//! evaluations.

mod common;

use common::{assert_gpu_evaluation_matches, gpu_or_skip, serial};
use sphlab::backend::Backend;
use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::neighbours::SearchKind;
use sphlab::scene::build::build_layout;
use sphlab::scene::{builtin, ContactMode, DtPolicy, Scene};
use std::sync::Arc;

const NX: u32 = 16;
const STEPS: usize = 300;

/// relax-60 at `NX` with a 120° liquid cap (`swapped`: the same cap made of gas in a box of
/// liquid), Mode `mode`, Young's angle 120° inside the cap either way (`perturbed`: the swapped
/// scene's σ of the cap's wall band 2 % larger and θ_d 1° larger, a control that must differ).
fn scene(mode: ContactMode, swapped: bool, perturbed: bool) -> Scene {
    let mut sc = builtin::builtin("relax-60").unwrap();
    sc.domain.nx = NX;
    sc.time.dt_policy = DtPolicy::Scale;
    let r = 0.197;
    sc.shapes[0].centre = Some([0.0, 0.5 * r]);
    sc.shapes[0].radius = Some(r);
    sc.contact.mode = mode;
    // The cap's wall band carries the tension, the other none: cos θ_Y = −σ_cap_wall.
    let (cap_wall, other_wall) = (if perturbed { 0.51 } else { 0.5 }, 0.0);
    if swapped {
        sc.fill = "liquid".into();
        sc.shapes[0].phase = "gas".into();
        sc.contact.sigma_gs = cap_wall;
        sc.contact.sigma_ls = other_wall;
        sc.contact.theta_deg = if perturbed { 61.0 } else { 60.0 };
    } else {
        sc.contact.sigma_ls = cap_wall;
        sc.contact.sigma_gs = other_wall;
        sc.contact.theta_deg = 120.0;
    }
    sc.validate().unwrap();
    sc
}

/// Positions of the fluid particles after `STEPS` steps.
fn run(sc: &Scene) -> Vec<[f64; 2]> {
    let layout = build_layout(sc).unwrap();
    let mut s = CpuSolver::<f64>::new(sc, &layout, Exec::Serial, SearchKind::Cells);
    for _ in 0..STEPS {
        s.step().unwrap();
    }
    s.pos[..s.n_fluid].iter().map(|p| [p.x, p.y]).collect()
}

/// The largest distance between a particle's positions in the two runs, over Δx.
fn max_gap(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    assert_eq!(a.len(), b.len());
    let dx = 0.5 / NX as f64;
    a.iter().zip(b).map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt() / dx).fold(0.0, f64::max)
}

/// How far the particles moved at all (over Δx), so that agreement is not that of a frozen state.
fn max_motion(sc: &Scene, end: &[[f64; 2]]) -> f64 {
    let layout = build_layout(sc).unwrap();
    let s = CpuSolver::<f64>::new(sc, &layout, Exec::Serial, SearchKind::Cells);
    max_gap(&s.pos[..s.n_fluid].iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(), end)
}

#[test]
fn mode_a_and_mode_b_do_not_tell_the_fluids_apart() {
    for mode in [ContactMode::A, ContactMode::B] {
        let liquid_cap = scene(mode, false, false);
        let a = run(&liquid_cap);
        let b = run(&scene(mode, true, false));
        let gap = max_gap(&a, &b);
        let moved = max_motion(&liquid_cap, &a);
        let off = max_gap(&a, &run(&scene(mode, true, true)));
        eprintln!(
            "{mode:?}: swapped vs liquid cap {gap:.3e} Δx after {STEPS} steps (particles moved up to {moved:.3e} Δx; the perturbed control: {off:.3e} Δx)"
        );
        assert!(moved > 1e-3, "{mode:?}: nothing moved ({moved:.3e} Δx), the comparison says nothing");
        assert!(
            gap < 1e-9,
            "{mode:?}: the swapped run departs by {gap:.3e} Δx: the model treats the fluids differently"
        );
        assert!(off > 1e3 * gap.max(1e-12), "{mode:?}: the perturbed control does not show ({off:.3e} Δx)");
    }
}

#[test]
fn gpu_contact_line_makes_no_point_where_the_liquid_meets_a_side_wall() {
    let _g = serial();
    let sc = scene(ContactMode::B, true, false);
    let layout = build_layout(&sc).unwrap();
    let mut c64 = CpuSolver::<f64>::new(&sc, &layout, Exec::Serial, SearchKind::Cells);
    let mut c32 = CpuSolver::<f32>::new(&sc, &layout, Exec::Serial, SearchKind::Cells);
    c64.evaluate().unwrap();
    c32.evaluate().unwrap();
    let xs: Vec<f64> = c64.f.contacts.iter().map(|c| c.r.x).collect();
    assert_eq!(xs.len(), 1, "the gas cap has one contact point, the liquid at the right wall none: {xs:?}");
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    for id in ["cells.thread.recomputed.f32", "cells.thread.recomputed.f64"] {
        assert_gpu_evaluation_matches(&format!("swapped Mode B {id}"), &ctx, &sc, &layout, id, &c64, &c32);
    }
}
