//! Shared test helpers: GPU presence rule, a seeded RNG, the wgebra-style harness that runs
//! one WGSL library function on many inputs through an appended `@compute` test entry point, and
//! the GPU-vs-CPU field and neighbour comparison (through `sphlab::verify`).
#![allow(dead_code, reason = "each test binary uses a different subset of the helpers")]

use sphlab::cpu::CpuSolver;
use sphlab::fields::{Field, Fields};
use sphlab::gpu::compose::{compose_mapped, validate, F64};
use sphlab::gpu::solver::GpuSolver;
use sphlab::gpu::{gpu_required, GpuContext, GpuVec};
use sphlab::model::Model;
use sphlab::neighbours::cells::CellGrid;
use sphlab::real::Real;
use sphlab::verify::compare_fields;
use std::sync::{Mutex, MutexGuard};

/// GPU tests run one at a time (one device at a time on a software adapter keeps memory and
/// timing sane): hold this guard for the whole test.
pub fn serial() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|p| p.into_inner())
}

/// The GPU presence rule: `Some(ctx)` when an adapter opens;
/// otherwise a loud SKIP and `None`, or a panic when [`gpu_required`] (`SPHLAB_REQUIRE_GPU=1`
/// or `CI=true`).
pub fn gpu_or_skip() -> Option<GpuContext> {
    let test = std::thread::current().name().unwrap_or("?").to_string();
    match GpuContext::new() {
        Ok(ctx) => {
            eprintln!("[{test}] GPU: {}", ctx.describe());
            Some(ctx)
        }
        Err(e) if gpu_required() => {
            panic!("[{test}] a GPU is required (SPHLAB_REQUIRE_GPU=1 or CI=true) but: {e}")
        }
        Err(e) => {
            // Written to the stderr handle directly: the test harness captures `eprintln!`,
            // and a skip must be visible in a plain `cargo test` run.
            let msg = format!(
                "\n!!!!!!!! SKIP [{test}]: no GPU adapter ({e}). \
                 Set SPHLAB_REQUIRE_GPU=1 to make this a failure. !!!!!!!!\n"
            );
            let _ = std::io::Write::write_all(&mut std::io::stderr(), msg.as_bytes());
            None
        }
    }
}

/// The oscillating-drop scene as a fully periodic 40Δx box (Δx = 1) with a drop of R = 10Δx at
/// its centre and no relaxation: no walls, so every pair force is antisymmetric.
pub const PERIODIC_DROP: [&str; 10] = [
    "domain.x=[0.0,40.0]",
    "domain.y=[0.0,40.0]",
    "domain.nx=40",
    "domain.left=\"periodic\"",
    "domain.right=\"periodic\"",
    "domain.top=\"periodic\"",
    "domain.bottom=\"periodic\"",
    "shapes.0.centre=[20.0,20.0]",
    "shapes.0.radius=10.0",
    "relax.t=0.0",
];

/// SplitMix64: a tiny, seeded, reproducible generator (no `rand` dependency needed).
pub struct Rng(u64);

impl Rng {
    /// A generator with a fixed seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi), rounded to the working precision.
    pub fn range<T: Real>(&mut self, lo: f64, hi: f64) -> T {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        T::c(lo + (hi - lo) * u)
    }
    /// Uniform sign times a log-uniform magnitude in [lo, hi).
    pub fn signed_log<T: Real>(&mut self, lo: f64, hi: f64) -> T {
        let m = (lo.ln() + (hi.ln() - lo.ln()) * self.range::<f64>(0.0, 1.0)).exp();
        T::c(if self.next_u64() & 1 == 0 { m } else { -m })
    }
    /// A fair coin as 0/1.
    pub fn bit(&mut self) -> u32 {
        (self.next_u64() & 1) as u32
    }
}

/// One evaluation of the function under test: real arguments, integer arguments (kernel ids,
/// booleans as 0/1).
#[derive(Clone, Debug)]
pub struct Case<T> {
    pub args: Vec<T>,
    pub ints: Vec<u32>,
}

impl<T> Case<T> {
    pub fn new(args: Vec<T>, ints: Vec<u32>) -> Self {
        Self { args, ints }
    }
}

/// A WGSL function under test: the module to import and the test body. In the body `i` is the
/// case index; `a(i, k)`/`a2(i, k)` read real argument k (and k+1 as a vector), `n(i, k)` reads
/// integer argument k, `put(i, k, v)`/`put2(i, k, v)` write output k (and k+1).
pub struct Twin<'a> {
    pub name: &'a str,
    pub module: &'a str,
    pub body: &'a str,
    pub nout: usize,
}

/// The appended test entry point (wgmath `format!("{}\n{}", src, test_kernel)` pattern).
fn test_kernel(t: &Twin, nin: usize, nint: usize) -> String {
    format!(
        "#import {module}
@group(0) @binding(0) var<storage, read> inp: array<real>;
@group(0) @binding(1) var<storage, read> ints: array<u32>;
@group(0) @binding(2) var<storage, read_write> out: array<real>;
const NIN: u32 = {nin}u;
const NINT: u32 = {nint}u;
const NOUT: u32 = {nout}u;
fn a(i: u32, k: u32) -> real {{ return inp[i * NIN + k]; }}
fn a2(i: u32, k: u32) -> real2 {{ return real2(a(i, k), a(i, k + 1u)); }}
fn n(i: u32, k: u32) -> u32 {{ return ints[i * NINT + k]; }}
fn put(i: u32, k: u32, v: real) {{ out[i * NOUT + k] = v; }}
fn put2(i: u32, k: u32, v: real2) {{ put(i, k, v.x); put(i, k + 1u, v.y); }}
@compute @workgroup_size(64)
fn test_main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = gid.x;
    if i >= arrayLength(&out) / NOUT {{ return; }}
    _ = n(0u, 0u); // keeps binding 1 in the auto layout when the body uses no integer argument
    {body}
}}
",
        module = t.module,
        nout = t.nout,
        body = t.body
    )
}

/// NaN bits of the working precision (the poison written before the dispatch).
fn poison<T: Real>() -> T {
    T::nan()
}

/// Runs `t` on every case on the GPU and returns the `nout` outputs per case.
pub fn run_twin<T: Real>(ctx: &GpuContext, t: &Twin, cases: &[Case<T>]) -> Vec<T> {
    let nin = cases[0].args.len().max(1);
    let nint = cases[0].ints.len().max(1);
    let mut args = Vec::with_capacity(cases.len() * nin);
    let mut ints = Vec::with_capacity(cases.len() * nint);
    for c in cases {
        assert_eq!((c.args.len().max(1), c.ints.len().max(1)), (nin, nint), "all cases have the same arity");
        args.extend(c.args.iter().copied().chain(std::iter::repeat(T::zero())).take(nin));
        ints.extend(c.ints.iter().copied().chain(std::iter::repeat(0)).take(nint));
    }
    let defines: &[&str] = if T::NAME == "f64" { &[F64] } else { &[] };
    let composed = compose_mapped("<test kernel>", &test_kernel(t, nin, nint), defines).expect("test kernel composes");
    if let Err(e) = validate(&composed) {
        panic!("{} [{}]: naga rejects the test kernel: {e}", t.name, T::NAME);
    }
    let label = format!("sphlab.test.{}.{}", t.name, T::NAME);
    let pipeline = ctx.compute_pipeline(&label, &composed.source, "test_main").expect("pipeline builds");
    let inp = GpuVec::from_slice(ctx, "inp", &args).expect("upload");
    let ints = GpuVec::from_slice(ctx, "ints", &ints).expect("upload");
    let out = GpuVec::<T>::new(ctx, "out", cases.len() * t.nout).expect("alloc");
    out.fill(ctx, poison()).expect("poison");
    let bg = ctx.bind_group(&pipeline, &[&inp.buffer, &ints.buffer, &out.buffer]).expect("bind group");
    ctx.dispatch(&pipeline, &bg, cases.len().div_ceil(64) as u32).expect("dispatch");
    out.read_back(ctx).expect("read back")
}

/// Compares GPU outputs with `(value, magnitude)` pairs from the Rust twin. The error of one
/// output is `|gpu − cpu| / max(magnitude, abs_floor)`, where `magnitude` is the size of the
/// terms that produced it (|cpu| when nothing cancels) and `abs_floor` absorbs flushed
/// denormals. NaN where a number is expected (the poison left in place) counts as infinite.
/// Panics with the first offenders when the max error exceeds `tol`; returns the max error.
pub fn compare<T: Real>(name: &str, gpu: &[T], cpu: &[(T, T)], cases: &[Case<T>], tol: f64, abs_floor: f64) -> f64 {
    assert_eq!(gpu.len(), cpu.len(), "{name}: output count");
    let nout = cpu.len() / cases.len();
    let mut errs: Vec<(f64, usize)> = Vec::new();
    let mut max = 0.0f64;
    for (k, (g, (c, m))) in gpu.iter().zip(cpu).enumerate() {
        let (g, c, m) = (g.f64(), c.f64(), m.f64());
        let e = if g == c {
            0.0
        } else if g.is_nan() || c.is_nan() {
            f64::INFINITY
        } else {
            (g - c).abs() / m.abs().max(abs_floor)
        };
        max = max.max(e);
        if e > tol {
            errs.push((e, k));
        }
    }
    println!("twin {name:<34} [{}] max err {max:.3e} (tol {tol:.0e}) over {} outputs", T::NAME, gpu.len());
    if !errs.is_empty() {
        errs.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut msg = format!("{name} [{}]: {} outputs exceed tol {tol:e}; worst first:\n", T::NAME, errs.len());
        for (e, k) in errs.iter().take(10) {
            let c = &cases[k / nout];
            msg += &format!(
                "  case {} out {}: gpu {:e} cpu {:e} mag {:e} err {e:.3e}; args {:?} ints {:?}\n",
                k / nout,
                k % nout,
                gpu[*k].f64(),
                cpu[*k].0.f64(),
                cpu[*k].1.f64(),
                c.args,
                c.ints
            );
        }
        panic!("{msg}");
    }
    max
}

/// GPU-vs-CPU comparison of one evaluation by `sphlab::verify`'s measure and tolerance table:
/// prints every check on one line and panics with the failing ones; returns the worst
/// (max-rel, rel-L2) over the fields.
pub fn assert_fields_match<T: Real>(
    tag: &str,
    model: &Model<T>,
    n_fluid: usize,
    cpu: &Fields<T>,
    gpu: &Fields<T>,
    only: Option<&[Field]>,
) -> (f64, f64) {
    let checks = compare_fields("field", "", gpu, cpu, model, n_fluid, only);
    let line: String = checks.iter().map(|c| format!(" {} {:.1e}/{:.1e}", c.name, c.max_rel, c.rel_l2)).collect();
    println!("{tag:<46}{line}");
    let failed: Vec<String> = checks
        .iter()
        .filter(|c| !c.pass)
        .map(|c| format!("{} max-rel {:e} rel-L2 {:e} (tol {:e})", c.name, c.max_rel, c.rel_l2, c.tolerance))
        .collect();
    assert!(failed.is_empty(), "{tag}: {}", failed.join("; "));
    let finite = |x: f64| if x.is_nan() { 0.0 } else { x };
    checks.iter().fold((0.0, 0.0), |(m, l), c| (m.max(c.max_rel), l.max(finite(c.rel_l2))))
}

/// One force evaluation of GPU variant `id` (its precision read from the id) on `scene` matches
/// the CPU's of the same precision (`c64` or `c32`, already evaluated), by [`assert_fields_match`].
pub fn assert_gpu_evaluation_matches(
    tag: &str,
    ctx: &std::sync::Arc<GpuContext>,
    scene: &sphlab::scene::Scene,
    layout: &sphlab::scene::build::Layout,
    id: &str,
    c64: &CpuSolver<f64>,
    c32: &CpuSolver<f32>,
) {
    let spec: sphlab::gpu::variant::VariantSpec = id.parse().unwrap();
    let nf = c64.n_fluid;
    if id.ends_with("f64") {
        let mut g = GpuSolver::<f64>::new(ctx.clone(), scene, layout, spec).unwrap();
        g.evaluate_once().unwrap();
        assert_fields_match(tag, &c64.model, nf, &c64.f, &g.read_fields().unwrap(), None);
    } else {
        let mut g = GpuSolver::<f32>::new(ctx.clone(), scene, layout, spec).unwrap();
        g.evaluate_once().unwrap();
        assert_fields_match(tag, &c32.model, nf, &c32.f, &g.read_fields().unwrap(), None);
    }
}

/// One variant of each mapping family, both precisions: what a physics option's GPU check runs.
pub const MAPPING_VARIANTS: [&str; 5] = [
    "cells.thread.recomputed.f32",
    "cells.thread.recomputed.f64",
    "tracking.subgroup.cached.f32",
    "cells.block-tree.fixed.recomputed.f64",
    "direct.block-atomic.native.cached.f32",
];

/// The CPU reference on `scene`'s `layout` (cells search, parallel), after one force evaluation.
pub fn evaluated_cpu<T: Real>(scene: &sphlab::scene::Scene, layout: &sphlab::scene::build::Layout) -> CpuSolver<T> {
    let mut c = CpuSolver::<T>::new(scene, layout, sphlab::exec::Exec::Parallel, sphlab::neighbours::SearchKind::Cells);
    c.evaluate().unwrap();
    c
}

/// [`assert_gpu_evaluation_matches`] for each variant of `ids` the adapter supports (an
/// unsupported one is printed with the reason), tagged `<tag> <id>`.
pub fn assert_variants_match(
    tag: &str,
    ctx: &std::sync::Arc<GpuContext>,
    (scene, layout): (&sphlab::scene::Scene, &sphlab::scene::build::Layout),
    ids: &[&str],
    c64: &CpuSolver<f64>,
    c32: &CpuSolver<f32>,
) {
    for id in ids {
        let spec: sphlab::gpu::variant::VariantSpec = id.parse().unwrap();
        if let Err(why) = spec.support(ctx) {
            println!("unsupported on this adapter: {why}");
            continue;
        }
        assert_gpu_evaluation_matches(&format!("{tag} {id}"), ctx, scene, layout, id, c64, c32);
    }
}

/// The GPU neighbour structures equal the CPU's exactly: the cell ranges of the `cells` grid
/// (same counting sort over the same grid) and, for list variants, every particle's list as a set.
pub fn assert_neighbours_match<T: Real>(tag: &str, cpu: &CpuSolver<T>, gpu: &GpuSolver<T>) {
    let v = gpu.read_neighbours().expect("read neighbours");
    if !v.cell_start.is_empty() {
        let grid = CellGrid::build(&cpu.pos, cpu.model.support());
        let (start, sorted) = grid.ranges();
        assert!(v.cell_start == start, "{tag}: cell ranges differ");
        assert!(v.sorted == sorted, "{tag}: particles by cell differ");
    }
    if let Some(lists) = &v.lists {
        for (i, l) in lists.iter().enumerate() {
            assert_eq!(l.as_slice(), cpu.nbrs.of(i), "{tag}: neighbour list of particle {i}");
        }
    }
}

/// A built-in scene without its relaxation, with `--set` style overrides, and its layout with
/// the scene's initial velocities.
pub fn scene(name: &str, sets: &[&str]) -> (sphlab::scene::Scene, sphlab::scene::build::Layout) {
    let mut s = sphlab::scene::builtin::builtin(name).expect("builtin");
    s.relax = None;
    let sets: Vec<String> = sets.iter().map(|x| x.to_string()).collect();
    let s = sphlab::scene::overrides::apply_overrides(&s, &sets).expect("overrides");
    let mut l = sphlab::scene::build::build_layout(&s).expect("layout");
    let v = sphlab::scene::initial::initial_velocities(&s, &l, None);
    l.vel[..l.n_fluid].copy_from_slice(&v);
    (s, l)
}

/// Mode A's contact-line force as the difference of two evaluations of the same state, `on`
/// with it and `off` without: `Σ m_i (a_on − a_off)` over the fluid, and the largest component
/// of `a_on − a_off` on a fluid particle at least the support away from every contact point of
/// `on` (zero when the force stays within its reach).
pub fn line_force_difference(on: &CpuSolver<f64>, off: &CpuSolver<f64>) -> ([f64; 2], f64) {
    let support = on.model.support();
    let (mut sum, mut beyond) = ([0.0; 2], 0.0f64);
    for i in 0..on.n_fluid {
        let d = [on.f.acc[i].x - off.f.acc[i].x, on.f.acc[i].y - off.f.acc[i].y];
        if on.f.contacts.iter().all(|cp| (on.pos[i] - cp.r).norm() >= support) {
            beyond = beyond.max(d[0].abs().max(d[1].abs()));
        }
        sum[0] += on.f.mass[i] * d[0];
        sum[1] += on.f.mass[i] * d[1];
    }
    (sum, beyond)
}
