//! Criterion bench of a full time step, one group per experiment of `sphlab study`
//! (docs/STUDY.md §4), with the study's scenes (`sphlab::study::study_scene`) and ids:
//! `BenchmarkId::new(backend id, N)` where the backend id is the [`BackendId`] of the study and
//! `records.csv` (`cpu1.cells.f64`, `cells.thread.recomputed.f32`, …), throughput in particles.
//!
//! * `e1`: search {direct, cells, tracking} × {CPU one thread, the default GPU variant of each
//!   search} at nx = 45 (2,025 fluid particles);
//! * `e4`: every GPU variant and the CPU one thread / all threads at nx = 100;
//! * `scaling`: the CPU (one thread, all threads; f64, f32) and every GPU variant at a few sizes;
//! * `e4_device`: the GPU cases of `e4` timed by one GPU timestamp pair around each submission
//!   (`DeviceTiming::Batch`, the engine as it runs), where the adapter has `TIMESTAMP_QUERY`;
//! * `reorder`: the GPU variants of `e4` with cell-ordered particles on (every 16 steps) and off,
//!   from the lattice order and from a shuffled fluid order, as `"{variant}.{lattice|shuffled}.reorder{k}"`.
//!
//! Each measurement is `iters` steps and one device sync (throughput); a run whose error flags
//! are set afterwards (overflow, blow-up) panics instead of being measured. Backends are built
//! lazily inside the bench closure, so `cargo bench --bench step -- --list` only registers ids
//! (seconds). `SPHLAB_BENCH_SIZES=30,60` picks the scaling resolutions;
//! `SPHLAB_BENCH_VARIANTS=cells.thread.recomputed.f32,...` restricts the GPU variants (`none`
//! skips the GPU). `cargo bench --bench step -- --test` runs each case once (smoke test).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sphlab::backend::{Backend, DeviceTiming};
use sphlab::backend_id::BackendId;
use sphlab::exec::Exec;
use sphlab::gpu::variant::VariantSpec;
use sphlab::gpu::GpuContext;
use sphlab::neighbours::SearchKind;
use sphlab::real::Precision;
use sphlab::scene::build::{build_layout, Layout};
use sphlab::scene::Scene;
use sphlab::study::study_scene;
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

fn sizes() -> Vec<u32> {
    std::env::var("SPHLAB_BENCH_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![30, 60, 120])
}

/// The adapter (opened once; `None` without one or with `SPHLAB_BENCH_VARIANTS=none`).
fn gpu() -> Option<&'static Arc<GpuContext>> {
    static CTX: OnceLock<Option<Arc<GpuContext>>> = OnceLock::new();
    CTX.get_or_init(|| {
        if std::env::var("SPHLAB_BENCH_VARIANTS").as_deref() == Ok("none") {
            return None;
        }
        GpuContext::new().map(Arc::new).map_err(|e| eprintln!("bench: no GPU adapter ({e}); CPU only")).ok()
    })
    .as_ref()
}

/// The GPU variants to time: supported on the adapter and named by `SPHLAB_BENCH_VARIANTS`.
fn variants() -> Vec<VariantSpec> {
    static V: OnceLock<Vec<VariantSpec>> = OnceLock::new();
    V.get_or_init(supported_variants).clone()
}

fn supported_variants() -> Vec<VariantSpec> {
    let Some(ctx) = gpu() else { return Vec::new() };
    let only = std::env::var("SPHLAB_BENCH_VARIANTS").ok();
    VariantSpec::all()
        .into_iter()
        .filter(|s| only.as_ref().is_none_or(|o| o.split(',').any(|x| x == s.to_string())))
        .filter(|s| match s.support(ctx) {
            Ok(()) => true,
            Err(e) => {
                eprintln!("bench: {s} unsupported on this adapter ({e})");
                false
            }
        })
        .collect()
}

fn cpu(exec: Exec, search: SearchKind, precision: Precision) -> BackendId {
    BackendId::Cpu { exec, search, precision }
}

/// Particles of the study scene at `nx`, from the resource plan (no layout is built).
fn particles(nx: u32) -> u64 {
    static N: std::sync::Mutex<Vec<(u32, u64)>> = std::sync::Mutex::new(Vec::new());
    let mut memo = N.lock().expect("memo");
    if let Some(&(_, n)) = memo.iter().find(|m| m.0 == nx) {
        return n;
    }
    let n = sphlab::plan::Plan::new(&study_scene(nx), 8, false).n_total as u64;
    memo.push((nx, n));
    n
}

/// Builds `id` on the study scene at `nx` and takes one step (pipelines, neighbour structures).
fn build(id: BackendId, nx: u32, device_time: bool) -> Box<dyn Backend> {
    let s = study_scene(nx);
    let layout = build_layout(&s).expect("layout");
    let mut b = id.build(&s, &layout, gpu()).unwrap_or_else(|e| panic!("{id} at nx={nx}: {e}"));
    if device_time {
        assert!(b.enable_device_time(DeviceTiming::Batch), "{id}: device timing did not switch on");
    }
    b.step().unwrap_or_else(|e| panic!("{id} at nx={nx}: first step failed: {e}"));
    b.sync();
    b
}

/// Registers `id` at `nx` in `group`; the backend is built on the first call of the routine.
fn register(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: BackendId,
    nx: u32,
    device_time: bool,
) {
    register_with(group, id.to_string(), particles(nx), device_time, move || build(id, nx, device_time));
}

/// Registers `label` (N particles) in `group`, built lazily by `make` on the first call.
fn register_with(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    label: String,
    n: u64,
    device_time: bool,
    make: impl Fn() -> Box<dyn Backend> + 'static,
) {
    group.throughput(Throughput::Elements(n));
    let mut backend: Option<Box<dyn Backend>> = None;
    let id = label.clone();
    group.bench_function(BenchmarkId::new(label, n), move |bench| {
        let b = backend.get_or_insert_with(&make);
        bench.iter_custom(|iters| {
            let _ = b.device_time();
            let t = Instant::now();
            for _ in 0..iters {
                b.step().unwrap_or_else(|e| panic!("{id}: {e}"));
            }
            b.sync();
            let wall = t.elapsed();
            if let Some(e) = b.take_error() {
                panic!("{id} at N={n}: the run failed, not a measurement: {e}");
            }
            if device_time {
                Duration::from_secs_f64(b.device_time().expect("device timing is on").batch_ms * 1e-3)
            } else {
                wall
            }
        })
    });
}

fn configure<'a>(c: &'a mut Criterion, name: &str) -> criterion::BenchmarkGroup<'a, criterion::measurement::WallTime> {
    let mut g = c.benchmark_group(name);
    g.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    g
}

fn bench_e1(c: &mut Criterion) {
    let mut g = configure(c, "e1");
    for search in [SearchKind::Direct, SearchKind::Cells, SearchKind::Tracking] {
        register(&mut g, cpu(Exec::Serial, search, Precision::F64), 45, false);
    }
    for spec in variants().into_iter().filter(|s| *s == VariantSpec { search: s.search, ..VariantSpec::default() }) {
        register(&mut g, BackendId::Gpu(spec), 45, false);
    }
    g.finish();
}

fn bench_e4(c: &mut Criterion) {
    let mut g = configure(c, "e4");
    register(&mut g, cpu(Exec::Serial, SearchKind::Cells, Precision::F64), 100, false);
    register(&mut g, cpu(Exec::Parallel, SearchKind::Cells, Precision::F64), 100, false);
    for spec in variants().into_iter().filter(|s| s.search != SearchKind::Direct) {
        register(&mut g, BackendId::Gpu(spec), 100, false);
    }
    g.finish();
}

fn bench_scaling(c: &mut Criterion) {
    let mut g = configure(c, "scaling");
    for nx in sizes() {
        for exec in [Exec::Serial, Exec::Parallel] {
            for precision in [Precision::F64, Precision::F32] {
                register(&mut g, cpu(exec, SearchKind::Cells, precision), nx, false);
            }
        }
        for spec in variants() {
            if spec.search == SearchKind::Direct && particles(nx) > sphlab::study::DIRECT_MAX_N as u64 {
                continue;
            }
            register(&mut g, BackendId::Gpu(spec), nx, false);
        }
    }
    g.finish();
}

fn bench_e4_device(c: &mut Criterion) {
    let Some(ctx) = gpu() else { return };
    if !ctx.has(wgpu::Features::TIMESTAMP_QUERY) {
        eprintln!("e4_device: skipped: the adapter has no TIMESTAMP_QUERY (device time unavailable)");
        return;
    }
    let mut g = configure(c, "e4_device");
    for spec in variants().into_iter().filter(|s| s.search != SearchKind::Direct) {
        register(&mut g, BackendId::Gpu(spec), 100, true);
    }
    g.finish();
}

/// `layout` with its fluid particles in a fixed pseudo-random order (xorshift Fisher–Yates).
fn shuffled(layout: &Layout) -> Layout {
    let mut l = layout.clone();
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    for i in (1..l.n_fluid).rev() {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let j = (x % (i as u64 + 1)) as usize;
        l.pos.swap(i, j);
        l.vel.swap(i, j);
        l.phase.swap(i, j);
    }
    l
}

/// A GPU solver of `spec` on `layout` renumbering its particles every `every` steps (0: never).
fn reordered(spec: VariantSpec, s: &Scene, layout: &Layout, every: u64) -> Box<dyn Backend> {
    use sphlab::gpu::solver::GpuSolver;
    let ctx = gpu().expect("adapter").clone();
    let mut b: Box<dyn Backend> = match spec.precision {
        Precision::F32 => {
            let mut g = GpuSolver::<f32>::new(ctx, s, layout, spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
            g.set_reorder_every(every).expect("set_reorder_every");
            Box::new(g)
        }
        Precision::F64 => {
            let mut g = GpuSolver::<f64>::new(ctx, s, layout, spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
            g.set_reorder_every(every).expect("set_reorder_every");
            Box::new(g)
        }
    };
    b.step().unwrap_or_else(|e| panic!("{spec}: first step failed: {e}"));
    b.sync();
    b
}

/// Cell-ordered particles (`GpuSolver::set_reorder_every`) on (tracking: every 16 steps; the
/// cells search: at every evaluation, physical cell order with no `sorted` indirection) and off
/// (the particles as loaded, reached through `sorted`), from the lattice order of the E4 scene
/// and from a shuffled fluid order (the state of a well-mixed flow), as
/// `"{variant}.{lattice|shuffled}.reorder{k}"`.
fn bench_reorder(c: &mut Criterion) {
    if gpu().is_none() {
        return;
    }
    let mut g = configure(c, "reorder");
    let nx = 100;
    for spec in variants().into_iter().filter(|s| s.search != SearchKind::Direct) {
        for order in ["lattice", "shuffled"] {
            for every in [0, 16] {
                let label = format!("{spec}.{order}.reorder{every}");
                register_with(&mut g, label, particles(nx), false, move || {
                    let s = study_scene(nx);
                    let lattice = build_layout(&s).expect("layout");
                    let layout = if order == "shuffled" { shuffled(&lattice) } else { lattice };
                    reordered(spec, &s, &layout, every)
                });
            }
        }
    }
    g.finish();
}

criterion_group!(benches, bench_e1, bench_e4, bench_scaling, bench_e4_device, bench_reorder);
criterion_main!(benches);
