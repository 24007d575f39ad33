//! Mode A's unbalanced Young force (`contact.wall_tension = "unbalanced"`, docs/PHYSICS.md §8.2.5)
//! on the GPU: relax-60 at nx = 33 with the force, on a disordered state whose measured angle is
//! not Young's (so the force is not zero). The CPU's line-force part of the acceleration is far
//! above verify's tolerance; one force evaluation of a variant of each mapping and precision
//! matches the CPU's, contact angles included; verify's stage-by-stage check (outputs poisoned)
//! and its check after steps pass; and a scene without the option dispatches no angle kernel.
//! A GPU path that left the force out, typed the wall at the scene's θ or left a word of the
//! contact list unwritten fails.

mod common;

use common::{assert_variants_match, evaluated_cpu, gpu_or_skip, serial, MAPPING_VARIANTS};
use sphlab::cpu::line_force::{line_force_acc, line_force_weights};
use sphlab::gpu::solver::GpuSolver;
use sphlab::gpu::stages::Domain;
use sphlab::gpu::variant::VariantSpec;
use sphlab::scene::build::{build_layout, Layout};
use sphlab::scene::Scene;
use sphlab::verify::Verifier;
use std::sync::Arc;

/// relax-60 at nx = 33 with the unbalanced Young force (Mode A), no relaxation.
fn scene() -> Scene {
    let (s, _) = common::scene(
        "relax-60",
        &["domain.nx=33", "contact.mode=\"a\"", "contact.wall_tension=\"unbalanced\"", "domain.jitter=0.1"],
    );
    s
}

fn layout(s: &Scene) -> Layout {
    build_layout(s).unwrap()
}

#[test]
fn the_unbalanced_young_force_matches_the_cpu_on_the_gpu() {
    let _g = serial();
    let s = scene();
    let l = layout(&s);
    let (c64, c32) = (evaluated_cpu::<f64>(&s, &l), evaluated_cpu::<f32>(&s, &l));
    assert_eq!(c64.f.contacts.len(), 1, "relax-60's half-drop (mirrored at x = 0) meets the wall once");
    assert_eq!(c64.f.contact_cos.len(), 1);
    // The line force's part of the accelerations: far above verify's rel-L2 tolerance (3e-4).
    let c = c64.ctx();
    let w = line_force_weights(&c, &c64.f);
    let (mut line2, mut all2) = (0.0, 0.0);
    for i in 0..c64.n_fluid {
        line2 += line_force_acc(&c, &c64.f, &w, i).norm2();
        all2 += c64.f.acc[i].norm2();
    }
    let share = (line2 / all2).sqrt();
    println!("cos θ_d {:?}, line force's share of the accelerations (rel-L2) {share:.2e}", c64.f.contact_cos);
    assert!(share > 1e-2, "a GPU without the force would pass: its share is only {share:e}");
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    assert_variants_match("unbalanced", &ctx, (&s, &l), &MAPPING_VARIANTS, &c64, &c32);
    // The contact angles themselves came back and were compared (verify's contacts row).
    let spec: VariantSpec = MAPPING_VARIANTS[0].parse().unwrap();
    let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
    g.evaluate_once().unwrap();
    let f = g.read_fields().unwrap();
    for (a, b) in f.contact_cos.iter().zip(&c32.f.contact_cos) {
        assert!((a - b).abs() < 1e-5, "cos θ_d {a} on the GPU, {b} on the CPU");
    }
    assert_eq!(f.contact_cos.len(), 1);
    assert_eq!(g.groups(Domain::ContactAngles)[0], 1, "the angle kernel runs with the option");
    // Mode B measures no angle: no angle kernel dispatched, no angles read back.
    let (b, lb) = common::scene("relax-60", &["domain.nx=33"]);
    let mut g = GpuSolver::<f32>::new(ctx.clone(), &b, &lb, spec).unwrap();
    assert_eq!(g.groups(Domain::ContactAngles)[0], 0, "no angle kernel without the option");
    g.evaluate_once().unwrap();
    assert!(g.read_fields().unwrap().contact_cos.is_empty());
}

#[test]
fn verify_passes_stage_by_stage_and_after_steps_with_the_unbalanced_young_force() {
    let _g = serial();
    let s = scene();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let v = Verifier::new(&s, 20, true);
    for id in ["cells.thread.recomputed.f32", "cells.thread.recomputed.f64"] {
        let spec: VariantSpec = id.parse().unwrap();
        if let Err(why) = spec.support(&ctx) {
            println!("unsupported on this adapter: {why}");
            continue;
        }
        let r = v.variant(&ctx, spec);
        for c in &r.checks {
            println!(
                "{id} {} {} {:.2e}/{:.2e} (tol {:.1e}) {}",
                c.kind, c.name, c.max_rel, c.rel_l2, c.tolerance, c.pass
            );
        }
        assert_eq!(r.status, "pass", "{id}: {}", r.reason);
        assert!(r.checks.iter().any(|c| c.kind == "stage" && c.name.contains("contacts")), "{id}: no contact check");
    }
}
