//! Criterion bench of a full time step (STUDY.md §4, Fig. 6.3/6.9 style): every supported GPU
//! variant and the CPU reference (one thread and all threads, f64 and f32) on the same scene
//! (`oscillating-drop` after relaxation is skipped: the drop at rest with its initial velocity
//! field) at a few sizes, in one group `step` with `BenchmarkId::new(backend id, n)` (the
//! [`BackendId`] of `sphlab study` and `records.csv`: `cpu1.cells.f64`, `cells.thread.recomputed.f32`,
//! …) and throughput in particles. GPU time is wall clock over `iters` steps followed by a
//! device sync.
//!
//! A second group `step_device` times the same GPU cases by GPU timestamps (`gpu::timing`): the
//! summed device time of every stage pass of the `iters` steps (`Backend::device_time`), so
//! host-side recording, submission and readback overheads are left out. Where the adapter has no
//! `TIMESTAMP_QUERY` the group is skipped with the reason printed.
//!
//! A third group `step_reorder` times the GPU variants with cell-ordered particles
//! (`GpuSolver::set_reorder_every`) on (every 16 steps) and off, starting from the lattice order
//! of the scene and from a shuffled fluid order (the state of a well-mixed flow), as
//! `"{variant}.{lattice|shuffled}.reorder{k}"`.
//!
//! `SPHLAB_BENCH_SIZES=30,60` picks the resolutions (particles across the quarter box);
//! `SPHLAB_BENCH_VARIANTS=cells.thread.recomputed.f32,...` restricts the GPU variants (`none`
//! skips the GPU). `cargo bench --bench step -- --test` runs each case once (smoke test).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sphlab::backend::{Backend, BackendId};
use sphlab::exec::Exec;
use sphlab::gpu::variant::{Precision, VariantSpec};
use sphlab::neighbours::SearchKind;
use sphlab::scene::build::{build_layout, Layout};
use sphlab::scene::{builtin::builtin, overrides::apply_overrides, Scene};
use std::time::{Duration, Instant};

fn scene(nx: u32) -> Scene {
    let sets = [format!("domain.nx={nx}"), "relax.t=0".to_string(), format!("time.dt={}", 1e-4 * 30.0 / nx as f64)];
    apply_overrides(&builtin("oscillating-drop").expect("built-in"), &sets).expect("valid")
}

fn sizes() -> Vec<u32> {
    std::env::var("SPHLAB_BENCH_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![30, 60, 120])
}

/// Every backend to time: the CPU (one thread and all threads, f64 and f32, cells) and the GPU
/// variants.
fn backends() -> Vec<BackendId> {
    let mut v = Vec::new();
    for exec in [Exec::Serial, Exec::Parallel] {
        for precision in [Precision::F64, Precision::F32] {
            v.push(BackendId::Cpu { exec, search: SearchKind::Cells, precision });
        }
    }
    let only = std::env::var("SPHLAB_BENCH_VARIANTS").ok();
    if only.as_deref() == Some("none") {
        return v;
    }
    for spec in VariantSpec::all() {
        if only.as_ref().is_some_and(|o| !o.split(',').any(|x| x == spec.to_string())) {
            continue;
        }
        v.push(BackendId::Gpu(spec));
    }
    v
}

/// Builds a backend and takes one warm-up step (pipelines, neighbour structures); `None` with
/// the reason printed when it cannot run.
fn warm(group: &str, label: &BackendId, s: &Scene, layout: &Layout, device_time: bool) -> Option<Box<dyn Backend>> {
    let n = layout.pos.len();
    let mut b = match label.build(s, layout, None) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("{group}/{label}/{n}: skipped: {e}");
            return None;
        }
    };
    if device_time && !b.enable_device_time(true) {
        eprintln!("{group}/{label}/{n}: skipped: the adapter has no TIMESTAMP_QUERY (device time unavailable)");
        return None;
    }
    if let Err(e) = b.step() {
        eprintln!("{group}/{label}/{n}: skipped, first step failed: {e}");
        return None;
    }
    b.sync();
    Some(b)
}

fn bench_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("step");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    for nx in sizes() {
        let s = scene(nx);
        let layout = build_layout(&s).expect("layout");
        let n = layout.pos.len() as u64;
        group.throughput(Throughput::Elements(n));
        for label in backends() {
            let Some(mut b) = warm("step", &label, &s, &layout, false) else { continue };
            group.bench_with_input(BenchmarkId::new(label.to_string(), n), &n, |bench, _| {
                bench.iter_custom(|iters| {
                    let t = Instant::now();
                    for _ in 0..iters {
                        b.step().expect("step");
                    }
                    b.sync();
                    t.elapsed()
                })
            });
        }
    }
    group.finish();
}

fn bench_step_device(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_device");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    for nx in sizes() {
        let s = scene(nx);
        let layout = build_layout(&s).expect("layout");
        let n = layout.pos.len() as u64;
        group.throughput(Throughput::Elements(n));
        for label in backends().into_iter().filter(|id| matches!(id, BackendId::Gpu(_))) {
            let Some(mut b) = warm("step_device", &label, &s, &layout, true) else { continue };
            group.bench_with_input(BenchmarkId::new(label.to_string(), n), &n, |bench, _| {
                bench.iter_custom(|iters| {
                    let _ = b.device_time();
                    for _ in 0..iters {
                        b.step().expect("step");
                    }
                    b.sync();
                    let d = b.device_time().expect("device timing is on");
                    Duration::from_secs_f64(d.total_ms * 1e-3)
                })
            });
        }
    }
    group.finish();
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

fn bench_step_reorder(c: &mut Criterion) {
    use sphlab::gpu::{solver::GpuSolver, GpuContext};
    let mut group = c.benchmark_group("step_reorder");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    let ctx = match GpuContext::new() {
        Ok(c) => std::sync::Arc::new(c),
        Err(e) => {
            eprintln!("step_reorder: skipped: {e}");
            return;
        }
    };
    for nx in sizes() {
        let s = scene(nx);
        let lattice = build_layout(&s).expect("layout");
        let n = lattice.pos.len() as u64;
        group.throughput(Throughput::Elements(n));
        for (order, layout) in [("lattice", lattice.clone()), ("shuffled", shuffled(&lattice))] {
            for spec in backends().into_iter().filter_map(|id| if let BackendId::Gpu(s) = id { Some(s) } else { None })
            {
                for every in [0, 16] {
                    let label = format!("{spec}.{order}.reorder{every}");
                    let mut b: Box<dyn Backend> = match spec.precision {
                        Precision::F32 => match GpuSolver::<f32>::new(ctx.clone(), &s, &layout, spec) {
                            Ok(mut g) => {
                                g.set_reorder_every(every).expect("set");
                                Box::new(g)
                            }
                            Err(e) => {
                                eprintln!("step_reorder/{label}/{n}: skipped: {e}");
                                continue;
                            }
                        },
                        Precision::F64 => match GpuSolver::<f64>::new(ctx.clone(), &s, &layout, spec) {
                            Ok(mut g) => {
                                g.set_reorder_every(every).expect("set");
                                Box::new(g)
                            }
                            Err(e) => {
                                eprintln!("step_reorder/{label}/{n}: skipped: {e}");
                                continue;
                            }
                        },
                    };
                    b.step().expect("first step");
                    b.sync();
                    group.bench_with_input(BenchmarkId::new(label, n), &n, |bench, _| {
                        bench.iter_custom(|iters| {
                            let t = Instant::now();
                            for _ in 0..iters {
                                b.step().expect("step");
                            }
                            b.sync();
                            t.elapsed()
                        })
                    });
                }
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench_step, bench_step_device, bench_step_reorder);
criterion_main!(benches);
