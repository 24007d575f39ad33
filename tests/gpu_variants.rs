//! Every GPU strategy variant of `VariantSpec::all()` against the CPU reference (docs/STUDY.md §3):
//! compose + naga-validate every kernel of every variant (no GPU); one force evaluation per
//! field on `oscillating-drop` (relax off) and `sessile-90` Mode B at nx = 33 for every
//! variant the adapter supports (the others must give a reason); bitwise reproducibility of
//! the `fixed` accumulation and the `thread` mapping; neighbour overflow reported as
//! `NeighbourOverflow`; tracking lists rebuilt on the CPU's schedule; thread, block and
//! subgroup variants with the workgroups-per-dimension limit forced to 4 (2-D dispatch, the
//! multi-workgroup cell scan) and the memory plan equal to what the solver allocates; the
//! subgroup mapping with 2 and 4 lanes per particle, so that several particles share a subgroup.

mod common;

use common::{assert_fields_match, assert_neighbours_match, gpu_or_skip, scene, serial};
use sphlab::backend::{Backend, SolverError};
use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::fields::{Field, Fields};
use sphlab::gpu::compose::{compose_variant_mapped, validate};
use sphlab::gpu::plan::{GpuPlan, SCAN_BLOCK};
use sphlab::gpu::solver::GpuSolver;
use sphlab::gpu::stages::{defines, kernel_table, Domain};
use sphlab::gpu::variant::{Accumulation, ListFormat, SlotLayout, SumLayout, VariantSpec, SUBGROUP_LANES};
use sphlab::gpu::{GpuContext, GpuError};
use sphlab::neighbours::SearchKind;
use sphlab::real::Precision;
use sphlab::real::{Real, V2};
use sphlab::scene::build::Layout;
use sphlab::scene::Scene;
use sphlab::verify::field_error;
use std::collections::BTreeSet;
use std::sync::Arc;
use std::time::Instant;

/// Fields are compared by `sphlab::verify`'s measure and tolerance table. Beyond it, in f32 the
/// acceleration must be no less accurate than the CPU f32 itself against the CPU f64 (at most
/// 1.25× its rel-L2 + 1e-6): its value depends on the summation order at ~1e-3 of |a| per
/// particle (the exact fixed-point sum differs from the CPU's sequential f32 sum by 3e-5 rel-L2
/// on oscillating-drop, while both are 1e-4 from the f64 truth).
const ACC_VS_F64: (f64, f64) = (1.25, 1e-6);

const SCENES: &[(&str, &[&str])] = &[("oscillating-drop", &[]), ("sessile-90", &["contact.mode=b", "domain.nx=33"])];

/// Every variant of `VariantSpec::all()` (its list format chosen by N), then each one whose list
/// format is a choice with the masks forced (`.masks`; at these sizes the choice is slots), then
/// each cached one in the pooled slot layout (`.pooled`; at these sizes the choice is full).
fn with_both_formats() -> Vec<VariantSpec> {
    let all = VariantSpec::all();
    let masks = all.iter().filter_map(|s| s.with_lists(ListFormat::Masks));
    let pooled = all.iter().filter_map(|s| s.with_slots(SlotLayout::Pooled));
    all.iter().copied().chain(masks).chain(pooled).collect()
}

#[test]
fn every_variant_composes_and_validates() {
    let mut done = BTreeSet::new();
    for spec in with_both_formats() {
        let defs = defines(&spec);
        for (_, kernels) in kernel_table(&spec) {
            for kd in kernels {
                if done.insert((kd.file, defs.clone())) {
                    let c = compose_variant_mapped(kd.file, &defs).unwrap();
                    let m = validate(&c).unwrap_or_else(|e| panic!("{spec} {}: {e}", kd.file));
                    assert!(m.entry_points.iter().any(|e| e.name == kd.entry), "{spec}: no entry {}", kd.entry);
                }
            }
        }
    }
    println!("{} (file, defines) compositions validated", done.len());
}

fn bits<T: Real>(f: &Fields<T>) -> Vec<u64> {
    Field::ALL.iter().flat_map(|&k| f.flat(k, f.acc.len())).map(f64::to_bits).collect()
}

/// rel-L2 of the fluid accelerations against the f64 reference.
fn acc_vs_f64<T: Real>(f: &Fields<T>, truth: &CpuSolver<f64>) -> f64 {
    let nf = truth.n_fluid;
    field_error(&f.flat(Field::Acc, nf), &truth.f.flat(Field::Acc, nf), 0.0).1
}

/// One evaluation of `spec` vs the CPU (and, in f32, the acceleration's accuracy against the
/// f64 reference); for order-independent variants (thread mapping, fixed accumulation) a second
/// evaluation on the same state must give the same bits.
fn check_variant<T: Real>(
    ctx: &Arc<GpuContext>,
    s: &Scene,
    l: &Layout,
    cpu: &CpuSolver<T>,
    truth: &CpuSolver<f64>,
    spec: VariantSpec,
    tag: &str,
) {
    let t0 = Instant::now();
    let mut gpu = GpuSolver::<T>::new(ctx.clone(), s, l, spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
    // At these sizes the slot lists fit any adapter's binding: the plan chooses them unless
    // the id forces the masks; and the full slot layout of the cached values unless forced.
    let want =
        if spec.lists == ListFormat::Auto && spec.list_format_matters() { ListFormat::Slots } else { spec.lists };
    let cached = spec.kernel_values == sphlab::gpu::variant::KernelValues::Cached;
    let slots = if spec.slots == SlotLayout::Auto && cached { SlotLayout::Full } else { spec.slots };
    assert_eq!(gpu.spec(), VariantSpec { lists: want, slots, ..spec }, "{tag}: the list format that ran");
    let t1 = Instant::now();
    gpu.evaluate_once().unwrap_or_else(|e| panic!("{spec}: {e}"));
    let f = gpu.read_fields().unwrap();
    let (mx, l2) = assert_fields_match(tag, &cpu.model, cpu.n_fluid, &cpu.f, &f, None);
    assert_neighbours_match(tag, cpu, &gpu);
    if T::NAME == "f32" {
        let (own, cpu_own) = (acc_vs_f64(&f, truth), acc_vs_f64(&cpu.f, truth));
        assert!(own <= ACC_VS_F64.0 * cpu_own + ACC_VS_F64.1, "{tag}: acc rel-L2 vs f64 {own:e}, CPU f32 {cpu_own:e}");
    }
    if spec.mapping.layout() == SumLayout::Thread || spec.accumulation == Accumulation::Fixed {
        gpu.evaluate_once().unwrap();
        assert!(bits(&f) == bits(&gpu.read_fields().unwrap()), "{tag}: two evaluations differ in bits");
    }
    println!(
        "    worst max-rel {mx:.2e} rel-L2 {l2:.2e}; build {:.1} s, evaluate {:.2} s",
        (t1 - t0).as_secs_f64(),
        t1.elapsed().as_secs_f64()
    );
}

#[test]
fn every_variant_matches_cpu_one_evaluation() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (mut ran, mut refused) = (0, Vec::new());
    for (name, sets) in SCENES {
        let (s, l) = scene(name, sets);
        let mut c32 = CpuSolver::<f32>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
        c32.evaluate().unwrap();
        let mut c64 = CpuSolver::<f64>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
        c64.evaluate().unwrap();
        for spec in with_both_formats() {
            if let Err(why) = spec.support(&ctx) {
                assert!(why.contains(&spec.to_string()) && why.len() > spec.to_string().len() + 5, "{why}");
                refused.push(why);
                continue;
            }
            let tag = format!("{name} {spec}");
            match spec.precision {
                Precision::F32 => check_variant(&ctx, &s, &l, &c32, &c64, spec, &tag),
                Precision::F64 => check_variant(&ctx, &s, &l, &c64, &c64, spec, &tag),
            }
            ran += 1;
        }
    }
    for r in &refused {
        println!("unsupported on this adapter: {r}");
    }
    println!("{ran} variant runs, {} refused with a reason", refused.len());
    assert!(ran > 0);
}

/// Two independent runs of several steps give identical bits for the order-independent
/// variants (fixed-point atomics; thread mapping over tracking candidates and cached lists),
/// with the particles renumbered in cell order every 2 steps.
#[test]
fn fixed_and_thread_variants_are_bitwise_reproducible() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene(SCENES[1].0, SCENES[1].1);
    for id in [
        "cells.block-atomic.fixed.recomputed.f32",
        "tracking.block-tree.fixed.cached.f32",
        "tracking.thread.recomputed.f32",
        "cells.thread.cached.f32",
        "direct.thread.cached.f32",
    ] {
        let run = || {
            let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, id.parse().unwrap()).unwrap();
            g.set_reorder_every(2).unwrap();
            for _ in 0..5 {
                g.step().unwrap();
            }
            let f = g.frame();
            (f.pos, f.vel, f.acc)
        };
        assert!(run() == run(), "{id}: two runs differ");
    }
}

/// More neighbours than the 64 list slots (quintic, h = 2Δx: ~113 neighbours) is an error for
/// every list-based variant, never silently wrong numbers; the thread mapping over cells has no
/// slot limit and still runs.
#[test]
fn neighbour_overflow_is_reported() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene("sessile-90", &["contact.mode=b", "domain.nx=21", "kernel.kind=quintic", "kernel.h_ratio=2.0"]);
    let ids = [
        "cells.block-atomic.cas.recomputed.f32",
        "cells.block-atomic.cas.recomputed.f32.masks",
        "direct.block-tree.fixed.recomputed.f32.masks",
        "tracking.block-tree.fixed.cached.f32",
        "direct.thread.cached.f32",
        "tracking.thread.recomputed.f32",
        "tracking.thread.recomputed.f32.masks",
    ];
    for id in ids {
        let spec: VariantSpec = id.parse().unwrap();
        let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
        match g.evaluate_once() {
            Err(GpuError::Solver(SolverError::NeighbourOverflow { slots, max, variant, .. })) => {
                println!("{id}: overflow of {slots} slots, max {max} ({variant})");
                assert!(max > slots && variant.starts_with(id));
            }
            other => panic!("{id}: expected NeighbourOverflow, got {other:?}"),
        }
        g.check_every = 1;
        let e = g.step().expect_err("step must fail");
        assert!(matches!(e, SolverError::NeighbourOverflow { .. }), "{id}: {e}");
    }
    let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, VariantSpec::default()).unwrap();
    g.evaluate_once().expect("thread/cells has no slot limit");
}

/// Pooled lists (`gpu::pooled_lists`) hold up to 64 neighbours per particle but 48 per
/// particle over each block of 64: with the quintic at h = 1.4Δx (support 4.2Δx, 57 lattice
/// neighbours) no particle passes 64 and the full layout runs, while the pooled blocks
/// overflow, which is an error naming the block's room, never a cut list.
#[test]
fn pooled_block_overflow_is_reported() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene("sessile-90", &["contact.mode=b", "domain.nx=21", "kernel.kind=quintic", "kernel.h_ratio=1.4"]);
    let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Serial, SearchKind::Cells);
    cpu.evaluate().expect("CPU evaluation");
    let max = (0..l.pos.len()).map(|i| cpu.nbrs.of(i).len()).max().unwrap();
    assert!(max > 48 && max <= 64, "{max} neighbours at most");
    for id in ["cells.thread.cached.f32", "cells.block-tree.fixed.cached.f64"] {
        let full: VariantSpec = format!("{id}.full").parse().unwrap();
        if full.support(&ctx).is_err() {
            continue;
        }
        let e = match full.precision {
            Precision::F32 => pooled_overflow::<f32>(&ctx, &s, &l, full),
            Precision::F64 => pooled_overflow::<f64>(&ctx, &s, &l, full),
        };
        println!("{id}.pooled: {e}");
        assert!(e.contains("more than 3072") && e.contains("pooled list block of 64 particles"), "{id}: {e}");
    }
}

/// Runs `full` (it must evaluate), then its pooled layout, whose error it returns.
fn pooled_overflow<T: Real>(ctx: &Arc<GpuContext>, s: &Scene, l: &Layout, full: VariantSpec) -> String {
    let mut g = GpuSolver::<T>::new(ctx.clone(), s, l, full).unwrap();
    g.evaluate_once().expect("64 slots hold every list");
    let pooled = full.with_slots(SlotLayout::Pooled).unwrap();
    let mut g = GpuSolver::<T>::new(ctx.clone(), s, l, pooled).unwrap();
    g.evaluate_once().expect_err("the pooled blocks overflow").to_string()
}

/// The overflow names its particle, by ORIGINAL id through the renumbering: from a start whose
/// fluid particles are numbered in reverse lattice order, with a support where every particle
/// has more than 64 neighbours, the particle `evaluate_once` reports (the first evaluation
/// renumbers) is the one at device index 0 (the lowest overflowing one), mapped back: not 0.
/// A failing `advance` reports the step, a particle and the number of overflowing particles
/// (not particle-evaluations), and the message says the step and the particle.
#[test]
fn neighbour_overflow_names_the_original_particle() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, mut l) =
        scene("sessile-90", &["contact.mode=b", "domain.nx=21", "kernel.kind=quintic", "kernel.h_ratio=1.6"]);
    let nf = l.n_fluid;
    l.pos[..nf].reverse();
    l.vel[..nf].reverse();
    l.phase[..nf].reverse();
    let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Serial, SearchKind::Cells);
    cpu.evaluate().expect("the CPU has no slot limit");
    let over: Vec<usize> = (0..l.pos.len()).filter(|&i| cpu.nbrs.of(i).len() > 64).collect();
    println!("{} of {} particles ({nf} fluid) have more than 64 neighbours", over.len(), l.pos.len());
    let spec: VariantSpec = "cells.block-atomic.cas.recomputed.f32".parse().unwrap();
    let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
    let Err(GpuError::Solver(e)) = g.evaluate_once() else { panic!("expected an overflow") };
    println!("evaluate_once: {e}");
    let SolverError::NeighbourOverflow { particle: Some(p), particles, .. } = e else { panic!("{e}") };
    let orig_of = g.device_order().unwrap();
    let mut new_of = vec![0; orig_of.len()];
    for (d, &o) in orig_of.iter().enumerate() {
        new_of[o as usize] = d;
    }
    let first = *over.iter().min_by_key(|&&o| new_of[o]).expect("overflowing particles");
    assert_eq!((p, particles), (first, over.len()), "the lowest device index, as its original id");
    assert!(p != new_of[p] && over.contains(&p), "mapped through a renumbering: device {} → {p}", new_of[p]);
    assert!(e.to_string().contains(&format!("the first particle {p};")), "{e}");
    let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
    let e = g.advance(4).expect_err("the first step overflows");
    println!("advance(4): {e}");
    let SolverError::NeighbourOverflow { step: 1, particle: Some(p), particles, .. } = e else { panic!("{e}") };
    assert!(over.contains(&p) && e.to_string().starts_with("step 1: "), "{e}");
    // Several evaluations ran before the one readback (the device halts its integrators, not
    // its evaluations): the count is of particles (the most in one evaluation), never the sum
    // of the evaluations' counts.
    assert!(particles <= l.pos.len(), "{particles} overflowing of {} particles: a sum over evaluations", l.pos.len());
    assert_eq!(particles, over.len(), "the overflowing particles, once each");
}

/// GPU tracking lists rebuild on the CPU's schedule (first evaluation, every 20, or after a
/// skin/2 displacement) and keep matching the cells search.
#[test]
fn tracking_rebuilds_like_the_cpu() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene(SCENES[0].0, SCENES[0].1);
    let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Parallel, SearchKind::Tracking);
    let mut gpu =
        GpuSolver::<f32>::new(ctx.clone(), &s, &l, "tracking.thread.recomputed.f32".parse().unwrap()).unwrap();
    for _ in 0..25 {
        cpu.step().unwrap();
        gpu.step().unwrap();
    }
    let (rc, rg) = (cpu.search.rebuilds, gpu.tracking_rebuilds().unwrap());
    println!("tracking rebuilds after 25 steps: CPU {rc}, GPU {rg}");
    assert!(rg >= 2 && rg.abs_diff(rc) <= 1, "CPU {rc} vs GPU {rg}");
}

/// Max |a − b| over the fluid particles, in units of `dx`.
fn max_diff(a: &[[f64; 2]], b: &[[f64; 2]], nf: usize, dx: f64) -> f64 {
    a[..nf].iter().zip(&b[..nf]).map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs())).fold(0.0, f64::max) / dx
}

/// `steps` steps of `spec` renumbering every `every` steps; the GPU solver afterwards.
fn run_reordered<T: Real>(
    ctx: &Arc<GpuContext>,
    s: &Scene,
    l: &Layout,
    spec: VariantSpec,
    every: u64,
    steps: u64,
) -> GpuSolver<T> {
    let mut g = GpuSolver::<T>::new(ctx.clone(), s, l, spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
    g.set_reorder_every(every).unwrap();
    g.check_every = 1;
    for _ in 0..steps {
        g.step().unwrap_or_else(|e| panic!("{spec}: {e}"));
    }
    g
}

/// Cell-ordered particles (renumbered every 3 steps: tracking; at every evaluation, in physical
/// cell order: cells) on a moving drop, per search × mapping family and precision: the device
/// order really differs from the original one (and the renumbering count follows the period),
/// the walls are renumbered among themselves into their cells' order (and the fluids too, in
/// physical order, after an evaluation), the trajectory stays with the CPU reference's and with
/// the same variant run without renumbering, and an evaluation at the reached state, read back
/// through the permutation, matches the CPU's fields (verify's tolerances) and neighbour lists
/// (exactly). The slot-major lists of the thread mapping are read back through the same check.
#[test]
fn reordered_variants_match_cpu_after_steps() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    const STEPS: u64 = 12;
    for (name, sets, ids) in [
        (
            "oscillating-drop",
            &[][..],
            &[
                "cells.thread.recomputed.f32",
                "cells.thread.cached.f64",
                "tracking.thread.cached.f32",
                "cells.block-tree.fixed.cached.f64",
                "tracking.block-atomic.cas.recomputed.f32",
            ][..],
        ),
        (
            "sessile-90",
            &["contact.mode=b", "domain.nx=33", "time.integrator=\"verlet\""][..],
            &["cells.thread.recomputed.f64", "cells.block-atomic.fixed.cached.f32", "tracking.thread.recomputed.f32"][..],
        ),
    ] {
        let (s, l) = scene(name, sets);
        let dx = l.dx;
        for id in ids {
            let spec: VariantSpec = id.parse().unwrap();
            if let Err(why) = spec.support(&ctx) {
                println!("{why}");
                continue;
            }
            let tag = format!("{name} {id} reorder 3");
            match spec.precision {
                Precision::F32 => check_reordered::<f32>(&ctx, &s, &l, spec, STEPS, dx, 1e-4, &tag),
                Precision::F64 => check_reordered::<f64>(&ctx, &s, &l, spec, STEPS, dx, 1e-9, &tag),
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn check_reordered<T: Real>(
    ctx: &Arc<GpuContext>,
    s: &Scene,
    l: &Layout,
    spec: VariantSpec,
    steps: u64,
    dx: f64,
    tol: f64,
    tag: &str,
) {
    let nf = l.n_fluid;
    let mut g = run_reordered::<T>(ctx, s, l, spec, 3, steps);
    let mut off = run_reordered::<T>(ctx, s, l, spec, 0, steps);
    let mut cpu = CpuSolver::<T>::new(s, l, Exec::Parallel, SearchKind::Cells);
    for _ in 0..steps {
        cpu.step().unwrap();
    }
    let order = g.device_order().unwrap();
    let moved = order.iter().enumerate().filter(|(d, o)| **o as usize != *d).count();
    let count = g.reorder_count().unwrap();
    let (fg, foff, fc) = (g.frame(), off.frame(), cpu.frame());
    let (vs_off, vs_cpu) = (max_diff(&fg.pos, &foff.pos, nf, dx), max_diff(&fg.pos, &fc.pos, nf, dx));
    println!("{tag}: {moved} of {} particles renumbered, {count} renumberings; |Δx|/dx vs off {vs_off:.1e}, vs CPU {vs_cpu:.1e}", order.len());
    assert!(moved > nf / 2, "{tag}: the device order is (nearly) the original one");
    let mut walls: Vec<u32> = order[nf..].to_vec();
    walls.sort_unstable();
    assert!(walls.iter().enumerate().all(|(k, &o)| o as usize == nf + k), "{tag}: walls left their range");
    let in_cell_order = |g: &GpuSolver<T>, o: &[u32], pos: &[[f64; 2]], range: std::ops::Range<usize>| {
        let cell = |d: usize| g.cell_of(V2::new(T::c(pos[o[d] as usize][0]), T::c(pos[o[d] as usize][1])));
        range.clone().skip(1).all(|d| cell(d - 1) <= cell(d))
    };
    assert!(in_cell_order(&g, &order, &l.pos, nf..order.len()), "{tag}: walls not in cell order");
    assert!(off.device_order().unwrap().iter().enumerate().all(|(d, &o)| o as usize == d), "{tag}: off renumbered");
    assert_eq!(off.reorder_count().unwrap(), 0, "{tag}");
    // At the first evaluation, then every 3 steps' evaluations (Verlet: one per step, plus the
    // first step's extra evaluation), for every search; tracking rebuilds its lists then too.
    let midpoint = s.time.integrator == sphlab::scene::Integrator::Midpoint;
    let (evals, period) = if midpoint { (2 * steps, 6) } else { (steps + 1, 3) };
    let physical = spec.search.name() == "cells";
    assert_eq!(g.physical_order(), physical, "{tag}");
    assert_eq!(count, if physical { evals } else { evals.div_ceil(period) }, "{tag}: renumberings");
    if spec.search.name() == "tracking" {
        assert!(count <= g.tracking_rebuilds().unwrap(), "{tag}: tracking rebuilds at its renumberings");
    }
    assert!(vs_off <= tol && vs_cpu <= tol, "{tag}: trajectories apart by {vs_off:e} / {vs_cpu:e} Δx (tol {tol:e})");
    // One evaluation at the reached state: GPU (device order) vs CPU (original order).
    let mut at = l.clone();
    at.pos = fg.pos.clone();
    at.vel = fg.vel.clone();
    let mut cpu_at = CpuSolver::<T>::new(s, &at, Exec::Parallel, SearchKind::Cells);
    cpu_at.evaluate().unwrap();
    g.evaluate_once().unwrap();
    if physical {
        let order = g.device_order().unwrap();
        assert!(in_cell_order(&g, &order, &fg.pos, 0..nf), "{tag}: fluids not in physical cell order");
    }
    assert_fields_match(tag, &cpu_at.model, nf, &cpu_at.f, &g.read_fields().unwrap(), None);
    // Neighbour structures in original indices: every particle once in the cell order, each
    // list equal to the CPU's (the cell ranges themselves are checked by the first-evaluation
    // test: the GPU grid is the initial one, the CPU's is rebuilt around the reached state).
    let v = g.read_neighbours().unwrap();
    if !v.cell_start.is_empty() {
        let mut all = v.sorted.clone();
        all.sort_unstable();
        assert!(all.iter().enumerate().all(|(k, &j)| j as usize == k), "{tag}: `sorted` is not a permutation");
    }
    if let Some(lists) = &v.lists {
        for (i, l) in lists.iter().enumerate() {
            assert_eq!(l.as_slice(), cpu_at.nbrs.of(i), "{tag}: neighbour list of particle {i}");
        }
    }
}

/// Dispatches spread over x and y (x and z for the block layout) when x alone would pass the
/// adapter's workgroups-per-dimension limit: with the limit forced to 4, far below what these
/// N need in x, thread and block variants still match the CPU after one evaluation and give the
/// same bits over a few steps as the unforced 1-D dispatch (a skipped or doubled particle
/// would change both).
/// Lists in chunks (`gpu::list_chunks`): on a context whose bindings are capped at 128 KiB the
/// slot arrays are split by particle, the plan still predicts every byte allocated and the chunk
/// count, and the lists read back chunk by chunk and the fields equal the CPU's, with the grids
/// also spread over two dimensions.
#[test]
fn lists_in_chunks_match_the_cpu_and_the_plan() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let cap = 128 << 10;
    let ctx = Arc::new(ctx.with_binding_cap(cap));
    let (s, l) = scene(SCENES[1].0, SCENES[1].1);
    let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
    cpu.evaluate().unwrap();
    // With the pooled layout too (`gpu::pooled_lists`), its blocks of 64 in workgroups of 64
    // and 256 threads spread over two grid dimensions.
    for id in [
        "cells.thread.cached.f32",
        "direct.block-tree.fixed.cached.f32",
        "cells.subgroup.recomputed.f32.slots",
        "cells.thread.cached.f32.pooled",
        "cells.thread.cached.f32.wg256.pooled",
        "direct.block-tree.fixed.cached.f32.pooled",
        "tracking.subgroup.cached.f32.masks.pooled",
    ] {
        let spec: VariantSpec = id.parse().unwrap();
        if spec.support(&ctx).is_err() {
            continue;
        }
        let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
        assert!(g.spec().to_string().starts_with(id), "{id} ran as {}", g.spec());
        let plan = GpuPlan::new(&g.spec(), l.pos.len() as u64, g.cells() as u64);
        assert!(g.list_chunks() > 1, "{id}: {} chunk(s) of {} particles", g.list_chunks(), l.pos.len());
        assert_eq!(g.list_chunks() as u64, plan.list_chunks(cap), "{id}");
        assert_eq!(plan.total_bytes, g.device_bytes(), "{id}: planned vs allocated device bytes");
        g.max_groups_per_dim = 4;
        g.evaluate_once().unwrap();
        assert_neighbours_match(id, &cpu, &g);
        let f = g.read_fields().unwrap();
        assert_fields_match(&format!("{id} (list chunks)"), &cpu.model, cpu.n_fluid, &cpu.f, &f, None);
    }
}

#[test]
fn dispatch_spreads_over_two_dimensions() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    // Resolution for more cells than one scan block holds with the scene's kernel (cells of
    // its support, 3.6Δx for the quintic at 1.2Δx).
    let (s, l) = scene("sessile-90", &["contact.mode=b", "domain.nx=40"]);
    let mut cpu = CpuSolver::<f32>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
    cpu.evaluate().unwrap();
    for id in [
        "cells.thread.recomputed.f32",
        "tracking.thread.cached.f32",
        "cells.block-atomic.fixed.recomputed.f32",
        "direct.block-tree.fixed.cached.f32",
        "cells.subgroup.recomputed.f32",
    ] {
        let spec: VariantSpec = id.parse().unwrap();
        if spec.support(&ctx).is_err() {
            continue;
        }
        let mut forced = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
        forced.max_groups_per_dim = 4;
        let (all, block) = (forced.groups(Domain::All), forced.groups(Domain::Block));
        assert!(all[0] <= 4 && all[1] > 4 && block[0] <= 4 && block[2] > 4, "{id}: grids {all:?} {block:?}");
        assert!(all[0] as usize * all[1] as usize * 64 >= l.pos.len());
        // More than one scan block, so the multi-workgroup cell scan runs (spread too).
        assert!(forced.cells() > SCAN_BLOCK, "{id}: {} cells", forced.cells());
        // The memory plan predicts exactly what the solver allocated.
        let plan = GpuPlan::new(&forced.spec(), l.pos.len() as u64, forced.cells() as u64);
        assert_eq!(plan.total_bytes, forced.device_bytes(), "{id}: planned vs allocated device bytes");
        forced.evaluate_once().unwrap();
        assert_neighbours_match(id, &cpu, &forced);
        assert_fields_match(
            &format!("{id} (≤ 4 groups per dim)"),
            &cpu.model,
            cpu.n_fluid,
            &cpu.f,
            &forced.read_fields().unwrap(),
            None,
        );
        let mut plain = GpuSolver::<f32>::new(ctx.clone(), &s, &l, spec).unwrap();
        for _ in 0..3 {
            forced.step().unwrap();
            plain.step().unwrap();
        }
        let (a, b) = (forced.frame(), plain.frame());
        assert!(a.pos == b.pos && a.vel == b.vel && a.acc == b.acc, "{id}: 2-D and 1-D dispatch differ");
    }
}

/// The direct search finds exactly the CPU's neighbours beyond the sizes of the other tests:
/// at nx = 60 (4,624 particles, 9 image codes scanned per particle), where a nested
/// code-then-index loop lost image neighbours of the wall particles on lavapipe (σ 34 % low at
/// the corner walls). Lists of a cached variant equal the CPU's as sets; σ of the recomputed
/// thread and block variants (whose lists come from the same iterator) match the CPU's.
#[test]
fn direct_search_matches_cpu_at_4624_particles() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (s, l) = scene("oscillating-drop", &["domain.nx=60"]);
    let mut c = CpuSolver::<f32>::new(&s, &l, Exec::Parallel, SearchKind::Cells);
    c.evaluate().unwrap();
    for id in ["direct.thread.cached.f32", "direct.thread.recomputed.f32", "direct.block-atomic.fixed.recomputed.f32"] {
        let mut g = GpuSolver::<f32>::new(ctx.clone(), &s, &l, id.parse().unwrap()).unwrap();
        g.evaluate_once().unwrap();
        assert_fields_match(id, &c.model, c.n_fluid, &c.f, &g.read_fields().unwrap(), Some(&[Field::Sigma]));
        assert_neighbours_match(id, &c, &g);
    }
    // Past lavapipe's loop cap the direct search is refused with the reason, before allocating.
    if ctx.adapter_info.driver.contains("llvmpipe") {
        let (s, l) = scene("oscillating-drop", &["domain.nx=140"]);
        let e = GpuSolver::<f32>::new(ctx.clone(), &s, &l, "direct.thread.recomputed.f32".parse().unwrap()).err();
        let e = e.expect("direct past the loop cap is refused").to_string();
        assert!(e.contains("LP_MAX_TGSI_LOOP_ITERATIONS") && e.contains("16126"), "{e}");
    }
}

/// The subgroup mapping with several particles per subgroup: composed with 2 and 4 lanes per
/// particle (`GpuSolver::with_subgroup_lanes`), below the adapter's smallest subgroup so that
/// S / G particles share one (lavapipe's subgroups are smaller than the default 16 lanes, where
/// each particle has a whole subgroup), and with the default lanes. Each must cover every
/// particle with its dispatch, match the CPU after one evaluation on both scenes (verify's
/// tolerances, lists exactly) and stay on the CPU's trajectory over 12 steps (the fused
/// epilogues run in the group's lane 0). A butterfly that skips an offset, a group that reads
/// another particle's lanes or a particle index that ignores S / G fails the evaluation.
#[test]
fn subgroup_groups_share_a_subgroup_and_match_cpu() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    let (smin, smax) = (ctx.adapter_info.subgroup_min_size, ctx.adapter_info.subgroup_max_size);
    println!("adapter subgroup size: {smin}..{smax} lanes");
    let ids = ["cells.subgroup.recomputed.f32", "tracking.subgroup.cached.f64"];
    if ids.iter().any(|id| id.parse::<VariantSpec>().unwrap().support(&ctx).is_err()) {
        println!("SKIP: the adapter runs no subgroup variant");
        return;
    }
    assert!(smin > 2, "subgroups of {smin} lanes: 2 lanes per particle would not share one");
    for lanes in [2, 4, SUBGROUP_LANES] {
        let per_subgroup = smin / lanes.min(smin);
        for (name, sets) in SCENES {
            let (s, l) = scene(name, sets);
            for id in ids {
                let spec: VariantSpec = id.parse().unwrap();
                let tag = format!("{name} {id} {lanes} lanes ({per_subgroup} per subgroup)");
                match spec.precision {
                    Precision::F32 => check_lanes::<f32>(&ctx, &s, &l, spec, lanes, &tag),
                    Precision::F64 => check_lanes::<f64>(&ctx, &s, &l, spec, lanes, &tag),
                }
            }
        }
    }
    let (s, l) = scene(SCENES[0].0, SCENES[0].1);
    let e = GpuSolver::<f32>::with_subgroup_lanes(ctx.clone(), &s, &l, ids[0].parse().unwrap(), 3);
    assert!(e.err().expect("3 lanes are refused").to_string().contains("must be 2, 4, 8 or 16"));
}

/// One evaluation of `spec` at `lanes` lanes per particle vs the CPU, then (on the first scene)
/// 12 steps vs the CPU's trajectory.
fn check_lanes<T: Real>(ctx: &Arc<GpuContext>, s: &Scene, l: &Layout, spec: VariantSpec, lanes: u32, tag: &str) {
    let mut g =
        GpuSolver::<T>::with_subgroup_lanes(ctx.clone(), s, l, spec, lanes).unwrap_or_else(|e| panic!("{tag}: {e}"));
    let [gx, gy, gz] = g.groups(Domain::Subgroups);
    let g_max = lanes.min(ctx.adapter_info.subgroup_max_size);
    assert!((gx * gy * gz * (64 / g_max)) as usize >= l.pos.len(), "{tag}: the grid misses particles");
    let mut cpu = CpuSolver::<T>::new(s, l, Exec::Parallel, SearchKind::Cells);
    cpu.evaluate().unwrap();
    g.evaluate_once().unwrap_or_else(|e| panic!("{tag}: {e}"));
    assert_fields_match(tag, &cpu.model, cpu.n_fluid, &cpu.f, &g.read_fields().unwrap(), None);
    assert_neighbours_match(tag, &cpu, &g);
    if s.name != SCENES[0].0 {
        return;
    }
    const STEPS: u64 = 12;
    let tol = if T::NAME == "f32" { 1e-4 } else { 1e-9 };
    let mut g = GpuSolver::<T>::with_subgroup_lanes(ctx.clone(), s, l, spec, lanes).unwrap();
    let mut cpu = CpuSolver::<T>::new(s, l, Exec::Parallel, SearchKind::Cells);
    for _ in 0..STEPS {
        cpu.step().unwrap();
        g.step().unwrap_or_else(|e| panic!("{tag}: {e}"));
    }
    let d = max_diff(&g.frame().pos, &cpu.frame().pos, l.n_fluid, l.dx);
    println!("{tag}: after {STEPS} steps max |Δx| vs CPU {d:.1e} Δx (tol {tol:e})");
    assert!(d <= tol, "{tag}: trajectories apart by {d:e} Δx after {STEPS} steps");
}
