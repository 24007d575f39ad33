//! Conservation on an isolated, fully periodic two-phase system (a drop of R = 10Δx in a 40Δx
//! periodic box, surface tension and viscosity on, positions perturbed and random velocities):
//! every pair force is antisymmetric, so one `evaluate()` gives Σ m_i a_i = 0 to rounding, and
//! 50 `advance()` steps keep the total momentum to rounding and the mass of each phase exactly.
//! (Momentum is not tested with mirror planes or walls, which exchange momentum with the box.)

use sphlab::backend::Backend;
use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::neighbours::SearchKind;
use sphlab::real::{Real, V2};
use sphlab::scene::build::build_layout;
use sphlab::scene::builtin::builtin;
use sphlab::scene::overrides::apply_overrides;

/// Deterministic pseudo-random numbers in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

mod common;

/// The periodic drop with a large fixed step (CFL limit 0.25 h/c = 7e-3) so 50 steps move the
/// particles.
const DT: &str = "time.dt=0.002";

/// The perturbed periodic drop: positions jittered by ±0.05Δx, velocities uniform in ±0.2
/// (c0 = 35, so the Mach number stays below 1 %), both phases.
fn perturbed<T: Real>(extra: &[&str], seed: u64) -> CpuSolver<T> {
    let base = builtin("oscillating-drop").unwrap();
    let sets: Vec<String> = common::PERIODIC_DROP.iter().chain(&[DT]).chain(extra).map(|s| s.to_string()).collect();
    let scene = apply_overrides(&base, &sets).unwrap();
    let layout = build_layout(&scene).unwrap();
    assert_eq!(layout.n_wall(), 0, "a fully periodic box must have no wall particles");
    let mut s = CpuSolver::<T>::new(&scene, &layout, Exec::Parallel, SearchKind::Cells);
    assert!(s.model.stages.surface_tension && s.model.stages.viscosity, "surface tension and viscosity must be on");
    let mut rng = Lcg(seed);
    for i in 0..s.n_fluid {
        s.pos[i] += V2::from_f64(0.1 * (rng.next() - 0.5), 0.1 * (rng.next() - 0.5));
        s.vel[i] = V2::from_f64(0.4 * (rng.next() - 0.5), 0.4 * (rng.next() - 0.5));
    }
    s.search.invalidate();
    s
}

/// (Σ m v, Σ m |v|).
fn momentum(f: &sphlab::backend::Frame) -> ([f64; 2], f64) {
    let (mut p, mut a) = ([0.0; 2], 0.0);
    for i in 0..f.n_fluid {
        p[0] += f.mass[i] * f.vel[i][0];
        p[1] += f.mass[i] * f.vel[i][1];
        a += f.mass[i] * f.vel[i][0].hypot(f.vel[i][1]);
    }
    (p, a)
}

/// (Σ m a, Σ m |a|).
fn force_sum(f: &sphlab::backend::Frame) -> ([f64; 2], f64) {
    let (mut p, mut a) = ([0.0; 2], 0.0);
    for i in 0..f.n_fluid {
        p[0] += f.mass[i] * f.acc[i][0];
        p[1] += f.mass[i] * f.acc[i][1];
        a += f.mass[i] * f.acc[i][0].hypot(f.acc[i][1]);
    }
    (p, a)
}

/// Phase masses as bit patterns, and particle counts.
fn phase_mass(f: &sphlab::backend::Frame) -> ([u64; 2], [usize; 2]) {
    let (mut m, mut n) = ([0.0f64; 2], [0usize; 2]);
    for i in 0..f.n_fluid {
        m[f.phase[i] as usize] += f.mass[i];
        n[f.phase[i] as usize] += 1;
    }
    ([m[0].to_bits(), m[1].to_bits()], n)
}

#[test]
fn pair_forces_are_antisymmetric_f64() {
    for seed in [1u64, 2, 3] {
        let mut s = perturbed::<f64>(&[], seed);
        s.evaluate().unwrap();
        let f = s.frame();
        let (sum, abs) = force_sum(&f);
        let rel = sum[0].hypot(sum[1]) / abs;
        println!("seed {seed}: |Σ m a| = {:.3e}, Σ|m a| = {abs:.4e}, ratio {rel:.3e}", sum[0].hypot(sum[1]));
        assert!(abs > 1.0, "the perturbed system should have sizeable forces, Σ|m a| = {abs}");
        assert!(rel < 1e-12, "seed {seed}: Σ m a = {sum:?} (relative {rel:e}): pair forces not antisymmetric");
    }
}

#[test]
fn each_force_term_is_antisymmetric() {
    // switch terms off one at a time so a broken term cannot hide behind the others
    // (name, overrides, jitter positions and velocities). The unjittered lattice has p ≈ 0, so
    // the last case measures the surface term alone.
    let cases: [(&str, &[&str], bool); 4] = [
        ("pressure only", &["surface_tension.sigma=0.0", "phases.0.mu=0.0", "phases.1.mu=0.0"], true),
        (
            "pressure + viscosity (unequal μ)",
            &["surface_tension.sigma=0.0", "phases.0.mu=0.3", "phases.1.mu=0.02"],
            true,
        ),
        ("pressure + surface tension", &["phases.0.mu=0.0", "phases.1.mu=0.0", "surface_tension.sigma=3.0"], true),
        ("surface tension alone (lattice at rest)", &["phases.0.mu=0.0", "phases.1.mu=0.0"], false),
    ];
    for (name, extra, jitter) in cases {
        let base = builtin("oscillating-drop").unwrap();
        let sets: Vec<String> =
            common::PERIODIC_DROP.iter().chain(&[DT]).chain(extra.iter()).map(|s| s.to_string()).collect();
        let scene = apply_overrides(&base, &sets).unwrap();
        let layout = build_layout(&scene).unwrap();
        let mut s = CpuSolver::<f64>::new(&scene, &layout, Exec::Serial, SearchKind::Cells);
        let mut rng = Lcg(17);
        for i in 0..if jitter { s.n_fluid } else { 0 } {
            s.pos[i] += V2::from_f64(0.1 * (rng.next() - 0.5), 0.1 * (rng.next() - 0.5));
            s.vel[i] = V2::from_f64(0.4 * (rng.next() - 0.5), 0.4 * (rng.next() - 0.5));
        }
        s.evaluate().unwrap();
        let (sum, abs) = force_sum(&s.frame());
        let rel = sum[0].hypot(sum[1]) / abs;
        assert!(abs > 0.1, "{name}: forces expected, Σ|m a| = {abs}");
        println!("{name}: Σ|m a| = {abs:.4e}, |Σ m a|/Σ|m a| = {rel:.3e}");
        assert!(rel < 1e-12, "{name}: Σ m a = {sum:?}, relative {rel:e}");
    }
}

#[test]
fn pair_forces_are_antisymmetric_f32() {
    let mut s = perturbed::<f32>(&[], 1);
    s.evaluate().unwrap();
    let (sum, abs) = force_sum(&s.frame());
    let rel = sum[0].hypot(sum[1]) / abs;
    println!("f32: |Σ m a|/Σ|m a| = {rel:.3e}");
    // f32 rounding of ~30-term sums over ~1600 particles
    assert!(rel < 1e-5, "f32: Σ m a = {sum:?}, relative {rel:e}");
}

#[test]
fn momentum_and_mass_conserved_over_50_steps() {
    for (search, exec) in [(SearchKind::Cells, Exec::Parallel), (SearchKind::Tracking, Exec::Serial)] {
        let mut s = perturbed::<f64>(&[], 5);
        s.search = sphlab::neighbours::Search::new(search);
        let f0 = s.frame();
        s.exec = exec;
        let (p0, pa0) = momentum(&f0);
        let (m0, n0) = phase_mass(&f0);
        let mut max_a: f64 = 0.0;
        let mut worst: f64 = 0.0;
        for step in 0..50 {
            s.advance().unwrap();
            let f = s.frame();
            let (p, pa) = momentum(&f);
            let (_, fa) = force_sum(&f);
            max_a = max_a.max(fa);
            let dp = (p[0] - p0[0]).hypot(p[1] - p0[1]);
            // rounding budget: each step adds dt·Σ m a (rounded) to Σ m v
            let scale = pa.max(pa0);
            worst = worst.max(dp / scale);
            assert!(
                dp / scale < 1e-13,
                "{search:?} step {}: ΔP = {dp:.3e} (Σ m|v| = {scale:.3e}, rel {:.3e})",
                step + 1,
                dp / scale
            );
            let (m, n) = phase_mass(&f);
            assert_eq!(n, n0, "{search:?} step {}: particles per phase changed", step + 1);
            assert_eq!(
                m,
                m0,
                "{search:?} step {}: phase masses not bitwise equal: {:?} vs {:?}",
                step + 1,
                m.map(f64::from_bits),
                m0.map(f64::from_bits)
            );
        }
        let f = s.frame();
        let moved =
            (0..f.n_fluid).map(|i| (f.vel[i][0] - f0.vel[i][0]).hypot(f.vel[i][1] - f0.vel[i][1])).fold(0.0, f64::max);
        let inside = (0..f.n_fluid).all(|i| (0.0..40.0).contains(&f.pos[i][0]) && (0.0..40.0).contains(&f.pos[i][1]));
        println!(
            "{search:?}: P0 = ({:.3e}, {:.3e}), worst |ΔP|/Σm|v| = {worst:.3e} over 50 steps, max Σ|m a| {max_a:.3e}, max |Δv| {moved:.3e}, t = {:.3}",
            p0[0], p0[1], s.t
        );
        assert!(moved > 1e-3, "the system should evolve (max |Δv| = {moved:e})");
        assert!(inside, "periodic wrapping must keep every particle inside [0, 40)²");
    }
}
