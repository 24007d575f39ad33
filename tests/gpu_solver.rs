//! The GPU solver against the CPU reference: the `Params`
//! layout (no GPU), one force evaluation per field and scene, every stage alone from CPU inputs
//! with poisoned outputs (all by `sphlab::verify`'s measure and tolerances; neighbour structures
//! exactly), 50-step observables, direct = cells, and bitwise reproducibility.

mod common;

use common::{assert_fields_match, assert_neighbours_match, gpu_or_skip, scene, serial};
use sphlab::backend::{Backend, SolverError};
use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::gpu::compose::{compose_mapped, compose_variant_mapped, validate, F64, VARIANT_FILES};
use sphlab::gpu::params::{field_offsets, Params};
use sphlab::gpu::solver::{EngineMode, GpuSolver};
use sphlab::gpu::variant::VariantSpec;
use sphlab::gpu::GpuContext;
use sphlab::neighbours::SearchKind;
use sphlab::real::Real;
use sphlab::scene::build::Layout;
use sphlab::scene::Scene;
use std::sync::Arc;

#[test]
fn params_layout_matches_wgsl() {
    use sphlab::gpu::compose::compose_mapped as cm;
    for (defs, size, offs) in [
        (&[][..], size_of::<Params<f32>>(), field_offsets::<f32>()),
        (&[F64][..], size_of::<Params<f64>>(), field_offsets::<f64>()),
    ] {
        let module = validate(&cm("<t>", "#import types\n", defs).unwrap()).unwrap();
        let (_, ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("Params")).expect("Params");
        let wgpu::naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("not a struct") };
        assert_eq!(*span as usize, size, "{defs:?}: struct size");
        for (name, off) in offs {
            let m = members.iter().find(|m| m.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("{name}"));
            assert_eq!(m.offset as usize, off, "{defs:?}: offset of {name}");
        }
    }
}

#[test]
fn variant_files_validate_with_every_define_set() {
    for (path, _) in VARIANT_FILES {
        for defs in [&[][..], &["DIRECT"][..], &[F64][..], &[F64, "DIRECT"][..]] {
            let c = compose_variant_mapped(path, defs).unwrap();
            validate(&c).unwrap_or_else(|e| panic!("{path} {defs:?}: {e}"));
        }
    }
    let _ = compose_mapped;
}

const SCENES: &[(&str, &[&str])] = &[
    ("oscillating-drop", &[]),
    ("sessile-90", &["contact.mode=b", "domain.nx=33"]),
    ("sessile-90", &["contact.mode=a", "domain.nx=33"]),
    ("poiseuille", &[]),
];

/// One evaluation on both sides, compared by `sphlab::verify`'s measure and tolerances; the
/// neighbour structures exactly.
fn evaluate_both<T: Real>(ctx: &Arc<GpuContext>, s: &Scene, l: &Layout, id: &str, tag: &str) {
    let mut cpu = CpuSolver::<T>::new(s, l, Exec::Parallel, SearchKind::Cells);
    cpu.evaluate().expect("cpu evaluate");
    let mut gpu = GpuSolver::<T>::new(ctx.clone(), s, l, id.parse().unwrap()).expect("gpu solver");
    gpu.evaluate_once().expect("gpu evaluate");
    let f = gpu.read_fields().expect("read back");
    assert_fields_match(tag, &cpu.model, cpu.n_fluid, &cpu.f, &f, None);
    assert_neighbours_match(tag, &cpu, &gpu);
}

#[test]
fn one_evaluation_matches_cpu_f32() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    for (name, sets) in SCENES {
        let (s, l) = scene(name, sets);
        for id in ["cells.thread.recomputed.f32", "direct.thread.recomputed.f32"] {
            evaluate_both::<f32>(&ctx, &s, &l, id, &format!("{name} {sets:?} {id}"));
        }
    }
}

#[test]
fn one_evaluation_matches_cpu_f64() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if !ctx.has(wgpu::Features::SHADER_F64) {
        eprintln!("SKIP: no SHADER_F64");
        return;
    }
    let ctx = Arc::new(ctx);
    for (name, sets) in &SCENES[1..2] {
        let (s, l) = scene(name, sets);
        evaluate_both::<f64>(&ctx, &s, &l, "cells.thread.recomputed.f64", &format!("{name} {sets:?} f64"));
    }
}

/// Every active stage alone, from the CPU's inputs to that stage (the stage table's order),
/// outputs poisoned before the run; every field compared after it.
#[test]
fn every_stage_alone_matches_cpu() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    for (name, sets) in SCENES {
        let (s, l) = scene(name, sets);
        let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Serial, SearchKind::Cells);
        let stagewise = cpu.evaluate_stagewise().unwrap();
        for id in ["cells.thread.recomputed.f32", "direct.thread.recomputed.f32"] {
            let mut gpu = GpuSolver::<f32>::new(ctx.clone(), &s, &l, id.parse().unwrap()).unwrap();
            for w in stagewise.windows(2) {
                let ((_, before), (stage, after)) = (&w[0], &w[1]);
                let g = gpu.run_stage_from(&cpu.pos, &cpu.vel, before, *stage).unwrap();
                let tag = format!("{name} {sets:?} {id} {stage}");
                assert_fields_match(&tag, &cpu.model, cpu.n_fluid, after, &g, None);
            }
        }
    }
}

fn observables(fr: &sphlab::backend::Frame) -> (f64, [f64; 2], f64, usize) {
    let (mut ke, mut m, mut c) = (0.0, 0.0, [0.0; 2]);
    for i in 0..fr.n_fluid {
        let (v, x) = (fr.vel[i], fr.pos[i]);
        ke += 0.5 * fr.mass[i] * (v[0] * v[0] + v[1] * v[1]);
        m += fr.mass[i];
        c[0] += fr.mass[i] * x[0];
        c[1] += fr.mass[i] * x[1];
    }
    (ke, [c[0] / m, c[1] / m], m, fr.pos.len())
}

/// 50 steps: KE within 1e-3 relative, centroid within 1e-6 of the box size (f32 rounding
/// drifts apart over the steps); mass and particle counts exactly.
#[test]
fn fifty_steps_observables_match_cpu() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    for (name, sets) in [SCENES[0], SCENES[1]] {
        let (s, l) = scene(name, sets);
        let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
        let mut gpu = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        let t0 = std::time::Instant::now();
        for _ in 0..50 {
            gpu.step().unwrap();
        }
        let (fg, ms) = (gpu.frame(), t0.elapsed().as_secs_f64() * 1e3 / 50.0);
        for _ in 0..50 {
            cpu.step().unwrap();
        }
        let fc = cpu.frame();
        let (og, oc) = (observables(&fg), observables(&fc));
        let size = (s.domain.x[1] - s.domain.x[0]).max(s.domain.y[1] - s.domain.y[0]);
        let ke = (og.0 - oc.0).abs() / oc.0.max(1e-300);
        let cen = (og.1[0] - oc.1[0]).abs().max((og.1[1] - oc.1[1]).abs()) / size;
        println!(
            "{name} {sets:?}: 50 steps, {ms:.1} ms/step GPU; KE rel {ke:.2e}, centroid {cen:.2e}, t {} vs {}",
            fg.t, fc.t
        );
        assert_eq!((og.2, og.3), (oc.2, oc.3), "mass and particle count");
        assert!(ke < 1e-3 && cen < 1e-6, "{name}: KE rel {ke:e}, centroid {cen:e}");
        assert!((fg.t - fc.t).abs() <= 1e-6 * fc.t, "time {} vs {}", fg.t, fc.t);
    }
}

/// Fluid positions and velocities of the coarse viscous drop (nx = 16, μ = 0.05) after t = 0.02
/// at `dt` with the GPU's f64 velocity Verlet (`verlet_drift` keeps v_{n+½} in vel0).
fn gpu_verlet_state(ctx: &Arc<GpuContext>, dt: f64) -> [Vec<[f64; 2]>; 2] {
    let dts = format!("time.dt={dt}");
    let (s, l) = scene("oscillating-drop", &["domain.nx=16", "time.integrator=\"verlet\"", &dts]);
    let mut gpu = GpuSolver::<f64>::new(ctx.clone(), &s, &l, "cells.thread.recomputed.f64".parse().unwrap()).unwrap();
    for _ in 0..(0.02 / dt).round() as u64 {
        gpu.step().unwrap();
    }
    let fr = gpu.frame();
    [fr.pos[..fr.n_fluid].to_vec(), fr.vel[..fr.n_fluid].to_vec()]
}

/// The WGSL twin of the CPU's second-order Verlet: successive differences of the
/// positions and velocities at dt = 2e-4, 1e-4, 5e-5 shrink ≈ 4× (observed order ≥ 1.7; the
/// evaluation at v_{n+½} gave 1.0). f64 only: the f32 differences are at rounding level.
#[test]
fn verlet_second_order_in_dt_on_gpu_f64() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if !ctx.has(wgpu::Features::SHADER_F64) {
        eprintln!("SKIP: no SHADER_F64");
        return;
    }
    let ctx = Arc::new(ctx);
    let xs: Vec<[Vec<[f64; 2]>; 2]> = [2e-4, 1e-4, 5e-5].iter().map(|dt| gpu_verlet_state(&ctx, *dt)).collect();
    let diff = |a: &[[f64; 2]], b: &[[f64; 2]]| {
        a.iter().zip(b).map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()).fold(0.0, f64::max)
    };
    for (c, what) in [(0, "position"), (1, "velocity")] {
        let (d0, d1) = (diff(&xs[0][c], &xs[1][c]), diff(&xs[1][c], &xs[2][c]));
        let order = (d0 / d1).log2();
        println!("GPU f64 Verlet {what}: successive differences {d0:.3e}, {d1:.3e}, order {order:.3}");
        assert!(order > 1.7, "GPU Verlet {what}: observed order {order} (need ≥ 1.7)");
    }
}

/// Thread mapping: no atomics in the sums, the cells are sorted: two runs give the same bits.
#[test]
fn thread_runs_are_bitwise_reproducible() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene(SCENES[1].0, SCENES[1].1);
    let run = || {
        let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        g.advance(4).unwrap();
        for _ in 0..6 {
            g.step().unwrap();
        }
        let f = g.frame();
        (f.pos, f.vel, f.acc, f.contacts)
    };
    let (a, b) = (run(), run());
    assert!(a == b, "two runs differ");
}

#[test]
fn unimplemented_and_bad_variants_are_errors() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene("poiseuille", &[]);
    // Every id of `VariantSpec::all()` is implemented (tests/gpu_variants.rs); f64 float
    // atomics are refused with a reason, and so is a precision the solver was not built for.
    for id in ["cells.block-atomic.cas.recomputed.f32", "tracking.block-tree.native.cached.f32"] {
        let spec = VariantSpec { precision: sphlab::real::Precision::F64, ..id.parse::<VariantSpec>().unwrap() };
        assert!(spec.to_string().parse::<VariantSpec>().unwrap_err().contains("not meaningful"), "{spec}");
        let e = GpuSolver::<f64>::new(ctx.clone(), &s, &l, spec).err().expect("error");
        assert!(e.to_string().contains("not meaningful"), "{id}: {e}");
    }
    let e = GpuSolver::<f32>::new(ctx.clone(), &s, &l, "cells.thread.recomputed.f64".parse().unwrap())
        .err()
        .expect("error");
    assert!(e.to_string().contains("solver built for f32"), "{e}");
}

/// `advance(k)` (fixed dt, midpoint and Verlet): k steps in ONE submission with no host write
/// and one readback, from the engine's own counters; the same bits as k single steps.
#[test]
fn advance_k_is_one_submit_and_matches_single_steps() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    for sets in [&[][..], &["time.integrator=verlet"][..]] {
        let (s, l) = scene("oscillating-drop", sets);
        let mut a = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        assert!(a.engine_counters_exclusive(), "the one solver on its context");
        let c0 = a.engine_counters();
        a.advance(8).unwrap();
        a.advance(8).unwrap();
        let c = a.engine_counters().since(&c0);
        println!("{sets:?}: 16 steps in 2 × advance(8): {c:?}");
        assert_eq!((c.steps, c.submits, c.readbacks, c.writes), (16, 2, 2, 0), "{sets:?}: {c:?}");
        // At least one kernel per pass of an evaluation and per integrator stage.
        let passes = a.model.stages.evaluation_passes().len() as u64 + 2;
        assert!(c.dispatches >= 16 * passes, "{sets:?}: every stage is dispatched: {c:?}");
        let mut b = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        // The counters' contract (gpu::counters): with two solvers alive on one context neither
        // count is a solver's own, and the Backend reports none rather than shared ones.
        assert!(!a.engine_counters_exclusive() && !b.engine_counters_exclusive(), "two solvers on one context");
        assert!(Backend::engine_counters(&a).is_none() && Backend::engine_counters(&b).is_none());
        let c0 = b.engine_counters();
        for _ in 0..16 {
            b.step().unwrap();
        }
        let cb = b.engine_counters().since(&c0);
        assert_eq!((cb.submits, cb.readbacks, cb.writes), (16, 0, 0), "step(): no readback between checks");
        let (fa, fb) = (a.frame(), b.frame());
        assert_eq!((fa.step, fa.t), (16, fb.t));
        assert!((fa.pos, fa.vel, fa.acc) == (fb.pos, fb.vel, fb.acc), "{sets:?}: advance(8) ≠ 8 × step()");
        drop((a, b));
        let c = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        assert!(Backend::engine_counters(&c).is_some(), "alone again once the others are dropped");
    }
}

/// Adaptive dt computed on the device (poiseuille, impact): after n steps in one submission
/// (one readback, no host write) dt and t agree with the f32 CPU reference's. Tolerance: the
/// two f32 runs sum in different orders, so |v|max and |a|max drift apart by ~1e-6 per step;
/// dt (∝ |a|^-½ or 1/(c+|v|)) follows within 1e-4 after 20 steps, t (a sum of dts) likewise.
#[test]
fn adaptive_dt_on_the_device_matches_cpu() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    for (name, sets) in [("poiseuille", &[][..]), ("impact", &["domain.nx=40"][..])] {
        let (s, l) = scene(name, sets);
        assert!(s.time.dt <= 0.0, "{name}: adaptive dt");
        let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
        let mut gpu = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
        let n = 20;
        let mut worst: f64 = 0.0;
        for k in [1, n - 1] {
            let c0 = gpu.engine_counters();
            gpu.advance(k).unwrap();
            let c = gpu.engine_counters().since(&c0);
            assert_eq!((c.submits, c.readbacks, c.writes), (1, 1, 0), "{name}: advance({k}): {c:?}");
            for _ in 0..k {
                cpu.step().unwrap();
            }
            let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
            let (dg, dc) = (gpu.frame().dt, cpu.frame().dt);
            let (e_dt, e_t) = (rel(dg, dc), rel(gpu.time(), cpu.time()));
            println!("{name}: after {} steps dt {dg:.6e} vs {dc:.6e} (rel {e_dt:.1e}), t rel {e_t:.1e}", gpu.steps());
            assert_eq!(gpu.steps(), cpu.steps());
            let tol = if gpu.steps() == 1 { 1e-5 } else { 1e-4 };
            assert!(e_dt < tol && e_t < tol, "{name}: dt rel {e_dt:e}, t rel {e_t:e} (tolerance {tol:e})");
            worst = worst.max(e_dt);
        }
        assert!(worst > 0.0 || name == "poiseuille", "{name}: a test that cannot differ proves nothing");
    }
}

/// A blow-up found on the device inside a batch is reported with the same step and particle
/// as single checked steps, and the device halts there: the state read back is the failing
/// step's, bit for bit. The unfused engine (the check and the clock tick as their own kernels
/// after the closing stage, not fused into it) halts at the same step, particle and state.
#[test]
fn a_blow_up_inside_a_batch_reports_and_keeps_the_failing_step() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene("oscillating-drop", &["time.dt=0.02"]);
    let mut a = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
    let ea = a.advance(200).expect_err("dt = 0.02 must blow up within 200 steps");
    let mut b = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
    b.check_every = 1;
    let eb = (0..200).find_map(|_| b.step().err()).expect("single steps blow up too");
    println!("batch: {ea}\nsingle: {eb}");
    let (
        SolverError::BlowUp { step: sa, particle: pa, t: ta, .. },
        SolverError::BlowUp { step: sb, particle: pb, t: tb, .. },
    ) = (&ea, &eb)
    else {
        panic!("expected blow-ups: {ea} / {eb}")
    };
    assert_eq!((sa, pa), (sb, pb), "same failing step and particle");
    assert!(*sa > 1 && *sa < 200, "the failing step is inside the batch: {sa}");
    assert_eq!((a.steps(), b.steps()), (*sa, *sb), "the solvers stop at the failing step");
    assert!((ta - tb).abs() <= 1e-6 * tb.abs(), "t {ta} vs {tb}");
    let (fa, fb) = (a.frame(), b.frame());
    assert!((&fa.pos, &fa.vel) == (&fb.pos, &fb.vel), "the halted state is the failing step's");
    let mut c = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
    c.set_fused(false);
    let ec = c.advance(200).expect_err("unfused: the same blow-up");
    let SolverError::BlowUp { step: sc, particle: pc, .. } = &ec else { panic!("expected a blow-up: {ec}") };
    assert_eq!((sc, pc), (sa, pa), "unfused: same failing step and particle");
    assert_eq!(c.steps(), *sa, "unfused: stops at the failing step");
    let fc = c.frame();
    assert!((&fc.pos, &fc.vel) == (&fa.pos, &fa.vel), "unfused: the same halted state");
    // Batches of 7 steps kept in flight, each read one batch late: the batches after the
    // failing one do nothing, and the report is the same.
    let mut d = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
    Backend::set_steps_per_submit(&mut d, 7);
    let ed = d.advance(200).expect_err("in flight: the same blow-up");
    let SolverError::BlowUp { step: sd, particle: pd, .. } = &ed else { panic!("expected a blow-up: {ed}") };
    assert_eq!((sd, pd, d.steps()), (sa, pa, *sa), "in flight: same failing step, particle and stop");
    let fd = d.frame();
    assert!((fd.pos, fd.vel) == (fa.pos, fa.vel), "in flight: the same halted state");
}

/// A long `advance` split into submissions of k steps keeps batches in flight: one submission
/// and one readback per batch, never a host write, and the same bits (and, adaptive dt, the
/// same clock) as the batches read one at a time.
#[test]
fn batches_in_flight_match_batches_read_one_at_a_time() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    for (name, sets) in [("oscillating-drop", &[][..]), ("poiseuille", &[][..])] {
        let (s, l) = scene(name, sets);
        let run = |in_flight: bool| {
            let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
            let mode = EngineMode { max_steps_per_submit: 3, in_flight, ..EngineMode::AFTER };
            g.set_engine_mode(mode).unwrap();
            let c0 = g.engine_counters();
            g.advance(20).unwrap();
            let c = g.engine_counters().since(&c0);
            let fr = g.frame();
            (c, fr.step, fr.t, fr.dt, fr.pos, fr.vel)
        };
        let (ca, sa, ta, da, pa, va) = run(true);
        let (cb, sb, tb, db, pb, vb) = run(false);
        println!("{name}: in flight {ca:?}; one at a time {cb:?}");
        assert_eq!((ca.steps, ca.submits, ca.readbacks, ca.writes), (20, 7, 7, 0), "{name}: {ca:?}");
        assert_eq!((cb.submits, cb.readbacks), (7, 7), "{name}: {cb:?}");
        assert_eq!((sa, ta, da), (sb, tb, db), "{name}: the clock");
        assert!((pa, va) == (pb, vb), "{name}: the same bits");
    }
}

/// The fused engine (the stage table's passes: epilogues in the neighbour passes, the check, the
/// clock tick and the cell count in the integrator stages) and its unfused debug mode (every
/// stage its own pass) take the same steps bit for bit: midpoint and Verlet, fixed and adaptive
/// dt, Mode B's contact points, wall typing and wall pressure, and the renumbering inside the
/// run. The fused engine's dispatches per step, from its own counters, stay within the bounds
/// reports/engine/ gives (the drop and the impact scene), and below the unfused engine's.
#[test]
fn fused_and_unfused_engines_take_the_same_steps_with_fewer_dispatches() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    // 64 steps: the first evaluation's own cell count and the renumberings (every 16 steps)
    // amortised as in reports/engine/.
    let steps = 64;
    let cells = VariantSpec::default();
    let tracking: VariantSpec = "tracking.thread.recomputed.f32".parse().unwrap();
    let cases: &[(&str, &[&str], VariantSpec, Option<f64>)] = &[
        ("oscillating-drop", &["domain.nx=24"], cells, Some(10.5)),
        ("impact", &["domain.nx=24"], cells, Some(13.5)),
        ("oscillating-drop", &["domain.nx=24", "time.integrator=verlet"], cells, None),
        ("sessile-90", &["contact.mode=b", "domain.nx=24"], cells, None),
        ("impact", &["domain.nx=24"], tracking, None),
    ];
    for &(name, sets, spec, bound) in cases {
        let (s, l) = scene(name, sets);
        let run = |fused: bool| {
            let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
            g.set_fused(fused);
            assert!(g.engine_counters_exclusive(), "the one solver on its context");
            let c0 = g.engine_counters();
            g.advance(steps).unwrap();
            let c = g.engine_counters().since(&c0);
            assert!(g.reorder_count().unwrap() >= 2, "{name}: renumbered inside the run");
            let f = g.frame();
            (c.dispatches as f64 / steps as f64, (f.pos, f.vel, f.acc, f.t))
        };
        let (fused, a) = run(true);
        let (unfused, b) = run(false);
        println!("{name} {sets:?} {spec}: dispatches per step fused {fused:.3}, unfused {unfused:.3}");
        assert!(a == b, "{name} {sets:?} {spec}: the fused and unfused engines differ");
        assert!(fused < unfused, "{name}: fused {fused} vs unfused {unfused} dispatches per step");
        if let Some(most) = bound {
            assert!(fused <= most, "{name}: {fused} dispatches per step (at most {most})");
        }
    }
}

/// The study's `engine` experiment at a small N writes, in one run, the CPU single-thread rows,
/// and before, after AND unfused rows for the fastest variant and `cells.thread.recomputed.f32`;
/// the engine's own counters show the engines differ (before: one submission and one readback
/// per step; after and unfused: one per block of K steps; unfused: more dispatches than after),
/// and summary.md has the before/after and the fused/unfused tables.
#[test]
fn study_engine_experiment_writes_before_and_after_rows() {
    use sphlab::study::engine_ab::THREAD_RECOMPUTED;
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let dir = tempfile::tempdir().expect("tempdir");
    let k = 10; // a whole tracking-list rebuild period (the study raises K to one)
    let other: VariantSpec = "cells.block-tree.cas.recomputed.f32".parse().unwrap();
    let opts = sphlab::study::StudyOptions {
        experiments: vec!["engine".into()],
        engine_nx: 16,
        sizes: vec![],
        protocol: sphlab::study::timing::Protocol { steps: k, repeats: 1, warmup_s: 0.0, latency_samples: 1 },
        // The experiment adds THREAD_RECOMPUTED to the sweep itself.
        variants: vec![other],
        out: dir.path().to_path_buf(),
        ..Default::default()
    };
    let recs = sphlab::study::run_study_on(&opts, Some(&ctx), std::time::Instant::now()).expect("study");
    let rows: Vec<_> = recs.iter().filter(|r| r.experiment == "engine").collect();
    for r in &rows {
        println!(
            "{} {} {} {:?} submits {:?} readbacks {:?}",
            r.variant, r.engine, r.status, r.ms_per_step_median, r.submits_per_step, r.readbacks_per_step
        );
    }
    for cpu in ["cpu1.cells.f64", "cpu1.cells.f32"] {
        let r = rows.iter().find(|r| r.variant == cpu).unwrap_or_else(|| panic!("{cpu} row"));
        // Measured: `ok`, or `loaded` when other work raised this machine's load average.
        let measured = r.status == "ok" || r.status == "loaded";
        assert!(measured && r.ms_per_step_median.is_some() && r.engine == "cpu", "{cpu}: {}", r.reason);
    }
    let after: Vec<_> = rows.iter().filter(|r| r.engine == "after").collect();
    assert_eq!(after.len(), 2, "after rows: `other` and THREAD_RECOMPUTED");
    let best = after.iter().min_by(|a, b| a.ms().total_cmp(&b.ms())).expect("after rows").variant.clone();
    let mut compared = vec![best, THREAD_RECOMPUTED.to_string()];
    compared.dedup();
    assert_eq!(
        rows.iter().filter(|r| r.engine == "before").count(),
        compared.len(),
        "before: the fastest and {THREAD_RECOMPUTED}"
    );
    for v in compared {
        let get = |e: &str| {
            let r = rows.iter().find(|r| r.variant == v && r.engine == e).unwrap_or_else(|| panic!("{v} {e} row"));
            assert!(r.status == "ok" || r.status == "loaded", "{v} {e}: {} {}", r.status, r.reason);
            assert!(r.ms_per_step_median.is_some() && r.n == rows[0].n && r.ke_rel_error.is_some(), "{v} {e}");
            assert!(r.modelled_bytes_per_eval.is_some_and(|b| b > 0.0) && r.device_bytes.is_some(), "{v} {e}");
            (r.submits_per_step.expect("counted"), r.readbacks_per_step.expect("counted"))
        };
        let (before, after, unfused) = (get("before"), get("after"), get("unfused"));
        assert_eq!(before, (1.0, 1.0), "{v}: before = one submission and one readback per step");
        assert_eq!(after, (1.0 / k as f64, 1.0 / k as f64), "{v}: after = one of each per K = {k} steps");
        assert_eq!(unfused, after, "{v}: unfused differs from after only in its passes");
        let dispatches = |e: &str| {
            rows.iter().find(|r| r.variant == v && r.engine == e).and_then(|r| r.dispatches_per_step).expect("counted")
        };
        assert!(dispatches("unfused") > dispatches("after"), "{v}: unfused records more passes");
    }
    assert!(md_has_fused_table(dir.path()), "summary.md: the fused/unfused table");
    let md = std::fs::read_to_string(dir.path().join("summary.md")).expect("summary.md");
    assert!(md.contains("## Engine — legacy against current"), "{md}");
    assert!(md.contains(&format!("| `{THREAD_RECOMPUTED}` |")), "{md}");
    let csv = std::fs::read_to_string(dir.path().join("records.csv")).expect("records.csv");
    assert!(csv.lines().next().is_some_and(|h| h.contains("engine") && h.contains("roofline_fraction")), "{csv}");
}

/// summary.md of a study in `dir` has the fused-against-unfused table with a ratio row.
fn md_has_fused_table(dir: &std::path::Path) -> bool {
    let md = std::fs::read_to_string(dir.join("summary.md")).unwrap_or_default();
    md.contains("Fused against unfused") && md.contains("| unfused ms/step |") && md.lines().any(|l| l.contains("× ["))
}

/// The cell merge's fallback: a particle that moved more than one cell since the last search is
/// not in the previous lists of the 3×3 cells around its new cell, so that cell's merge finds
/// fewer than its count and takes its particles from every particle in index order. One fluid
/// particle is sent three cells to the right within half a step; the search after it (cell
/// lists poisoned first, so a slot it does not write fails) must list every particle once and
/// give the CPU's fields at the same state.
#[test]
fn the_cell_merge_takes_a_particle_that_jumped_cells() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene("oscillating-drop", &["domain.nx=24"]);
    let mut g = GpuSolver::<f32>::new(ctx, &s, &l, VariantSpec::default()).unwrap();
    g.set_reorder_every(0).unwrap();
    g.advance(2).unwrap();
    let f = g.frame();
    let nf = l.n_fluid;
    let cell = g.model.support() as f64;
    let jump = 3.0 * cell;
    // The fluid particle nearest the left third of the box at mid-height jumps right by `jump`.
    let (lo, hi) =
        (f.pos[..nf].iter().fold(f64::MAX, |m, p| m.min(p[0])), f.pos[..nf].iter().fold(f64::MIN, |m, p| m.max(p[0])));
    let y_mid = f.pos[..nf].iter().map(|p| p[1]).sum::<f64>() / nf as f64;
    let target = [lo + 0.25 * (hi - lo), y_mid];
    let d2 = |p: &[f64; 2]| (p[0] - target[0]).powi(2) + (p[1] - target[1]).powi(2);
    let p = (0..nf).min_by(|&a, &b| d2(&f.pos[a]).total_cmp(&d2(&f.pos[b]))).unwrap();
    assert!(f.pos[p][0] + jump < hi, "the jump stays inside the fluid");
    let mut vel = f.vel.clone();
    vel[p] = [jump / (0.5 * s.time.dt), 0.0];
    g.restart_with_velocities(&vel);
    g.step().unwrap();
    g.sync();
    let reached = g.frame();
    let moved = reached.pos[p][0] - f.pos[p][0];
    assert!(moved > 2.0 * cell, "particle {p} moved {moved:e}, not over two cells ({cell:e})");
    g.poison_cell_lists().unwrap();
    g.evaluate_once().unwrap();
    let mut at = l.clone();
    at.pos = reached.pos.clone();
    at.vel = reached.vel.clone();
    let mut cpu = CpuSolver::<f32>::new(&s, &at, Exec::Parallel, SearchKind::Cells);
    cpu.evaluate().unwrap();
    assert_fields_match("jumped", &cpu.model, nf, &cpu.f, &g.read_fields().unwrap(), None);
    // Every particle once in the cell lists (the ranges themselves are on the initial grid,
    // which the CPU's, built around the reached state, need not equal).
    let mut all = g.read_neighbours().unwrap().sorted;
    all.sort_unstable();
    assert!(all.iter().enumerate().all(|(k, &j)| j as usize == k), "the cell lists are not a permutation");
}

/// The cell scan checks its own total: counts that sum to the fluid particle count (the walls
/// are sorted once, by the host) give their exclusive prefix and no flag; one count too many (a particle counted twice, or a fused scan
/// that read the counts before every workgroup's were visible) sets the scan-miss word, and the
/// next step stops with that error instead of searching with wrong lists.
#[test]
fn a_cell_scan_that_does_not_sum_to_n_stops_the_run() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let (s, l) = scene("oscillating-drop", &["domain.nx=24"]);
    let mut g = GpuSolver::<f32>::new(Arc::new(ctx), &s, &l, VariantSpec::default()).unwrap();
    let (cells, n) = (g.cells(), l.n_fluid);
    let mut counts = vec![0u32; cells];
    for k in 0..n {
        counts[(k * 7919) % cells] += 1;
    }
    let prefix: Vec<u32> = std::iter::once(0)
        .chain(counts.iter().scan(0u32, |run, &c| {
            *run += c;
            Some(*run)
        }))
        .collect();
    let (starts, miss) = g.scan_counts(&counts).unwrap();
    assert_eq!((starts, miss), (prefix, u32::MAX), "a scan of n_fluid counts");
    counts[cells / 2] += 1;
    let (starts, miss) = g.scan_counts(&counts).unwrap();
    assert_eq!(starts[cells] as usize, n + 1);
    assert_ne!(miss, u32::MAX, "a total of n_fluid + 1 is flagged");
    let err = g.advance(1).expect_err("the run stops at the flagged scan").to_string();
    assert!(err.contains("did not sum to the"), "{err}");
}
