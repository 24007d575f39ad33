//! Criterion bench of the contact-angle diagnostics (`sphlab::diagnostics::measure_all`) on a
//! synthetic 60° cap: a cell-centred lattice of 10⁴ and 10⁵ particles with three wall rows,
//! liquid inside the equilibrium cap of the half-circle's area. Throughput in particles.
//! `cargo bench --bench diagnostics -- --test` runs each case once.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sphlab::diagnostics::{equilibrium_cap, measure_all};
use sphlab::scene::build::WALL;
use std::f64::consts::PI;

/// Lattice on [0, 0.5]² of spacing dx plus 3 wall rows below y = 0; liquid inside the cap.
fn cap_scene(dx: f64) -> (Vec<[f64; 2]>, Vec<u32>) {
    let c = equilibrium_cap(PI * 0.25 * 0.25 / 2.0, 60f64.to_radians());
    let n = (0.5 / dx).round() as usize;
    let (mut pos, mut phase) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            let p = [(i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx];
            pos.push(p);
            phase.push(if p[0] * p[0] + (p[1] - c.centre_y).powi(2) < c.radius * c.radius { 0 } else { 1 });
        }
    }
    for k in 0..3 {
        for i in 0..n {
            pos.push([(i as f64 + 0.5) * dx, -(k as f64 + 0.5) * dx]);
            phase.push(WALL);
        }
    }
    (pos, phase)
}

fn bench_measure_all(c: &mut Criterion) {
    let mut g = c.benchmark_group("contact_angle");
    for across in [100usize, 316] {
        let dx = 0.5 / across as f64;
        let (pos, phase) = cap_scene(dx);
        g.throughput(Throughput::Elements(pos.len() as u64));
        g.bench_with_input(BenchmarkId::new("measure_all", pos.len()), &(pos, phase), |b, (pos, phase)| {
            b.iter(|| measure_all(pos, phase, dx, 0.0, true))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_measure_all);
criterion_main!(benches);
