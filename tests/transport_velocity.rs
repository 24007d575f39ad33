//! The transport-velocity formulation (`time.background = "transport"`, Adami, Hu & Adams 2013)
//! on the CPU reference, on a perturbed 90° sessile drop (walls, Mode B, both fluids):
//! * the background pressure leaves the EOS and the momentum equation, and the shift a_b is
//!   exactly the pressure term (T68) of a uniform p_b that the momentum form carries: for every
//!   fluid particle `a(momentum) − a(transport) = a_b` to rounding;
//! * the drift moves with v + (dt/2)(a + a_b) (one Verlet step from the same state);
//! * the shift vanishes with p_b = 0 and has zero total momentum in a fully periodic box;
//! * the artificial stress A = ρ v ⊗ (ṽ − v) (their eq. 12) is the pair sum of docs/PHYSICS.md
//!   §7.5 over the lagged ṽ − v, recomputed here by brute force over every pair, carries no
//!   momentum, and the advection keeps (dt/2)·a_b for it.

use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::neighbours::SearchKind;
use sphlab::physics::kernel::kernel_dwdr;
use sphlab::real::V2;
use sphlab::scene::build::build_layout;
use sphlab::scene::builtin::builtin;
use sphlab::scene::overrides::apply_overrides;

mod common;

const P_B: f64 = 20.0;

/// `scene` at the given overrides, fluid positions jittered by ±0.1Δx and velocities in ±0.1
/// (the same for every call with the same seed).
fn perturbed(scene: &str, sets: &[String], seed: u64) -> CpuSolver<f64> {
    let scene = apply_overrides(&builtin(scene).unwrap(), sets).unwrap();
    let layout = build_layout(&scene).unwrap();
    let mut s = CpuSolver::<f64>::new(&scene, &layout, Exec::Serial, SearchKind::Cells);
    let dx = scene.domain.dx();
    let mut rng = common::Rng::new(seed);
    for i in 0..s.n_fluid {
        s.pos[i] += V2::new(rng.range(-0.1 * dx, 0.1 * dx), rng.range(-0.1 * dx, 0.1 * dx));
        s.vel[i] = V2::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1));
    }
    s.search.invalidate();
    s
}

fn sessile(background: &str, p_b: f64, extra: &[&str]) -> CpuSolver<f64> {
    let mut sets: Vec<String> = vec![
        "domain.nx=20".into(),
        format!("phases.0.p_b={p_b}"),
        format!("phases.1.p_b={p_b}"),
        format!("time.background=\"{background}\""),
    ];
    sets.extend(extra.iter().map(|s| s.to_string()));
    perturbed("sessile-90", &sets, 7)
}

fn max_norm(v: &[V2<f64>]) -> f64 {
    v.iter().map(|a| a.norm()).fold(0.0, f64::max)
}

#[test]
fn shift_is_the_pressure_term_of_the_uniform_background() {
    for wall in ["t-wall", "r-wall"] {
        let w = format!("walls.pressure=\"{wall}\"");
        let mut m = sessile("momentum", P_B, &[&w]);
        let mut t = sessile("transport", P_B, &[&w]);
        m.evaluate().unwrap();
        t.evaluate().unwrap();
        assert!(m.f.shift.is_empty(), "the momentum form has no shift");
        assert_eq!(t.f.shift.len(), t.n_fluid, "one shift per fluid particle");
        for i in 0..t.n_fluid {
            assert!((m.f.p[i] - t.f.p[i] - P_B).abs() < 1e-9, "{wall}: p_b must leave the EOS (particle {i})");
        }
        let scale = max_norm(&t.f.shift);
        // p_b/ρ0 over Δx times a disorder of ~0.1: well above rounding, far below p_b/Δx.
        assert!(scale > 1.0 && scale < 1e4, "{wall}: |a_b| max {scale}");
        let mut worst = 0.0_f64;
        for i in 0..t.n_fluid {
            let d = m.f.acc[i] - t.f.acc[i] - t.f.shift[i];
            worst = worst.max(d.norm());
        }
        assert!(worst < 1e-9 * scale, "{wall}: a(momentum) − a(transport) − a_b up to {worst} (|a_b| {scale})");
    }
    // No background, no shift.
    let mut z = sessile("transport", 0.0, &[]);
    z.evaluate().unwrap();
    assert_eq!(max_norm(&z.f.shift), 0.0, "p_b = 0 gives no shift");
}

#[test]
fn drift_moves_with_half_a_step_of_the_shift() {
    let extra = ["time.integrator=\"verlet\"", "time.dt=1e-4"];
    let mut probe = sessile("transport", P_B, &extra);
    probe.evaluate().unwrap();
    let (r0, v0) = (probe.pos.clone(), probe.vel.clone());
    let (a0, b0) = (probe.f.acc.clone(), probe.f.shift.clone());
    let mut s = sessile("transport", P_B, &extra);
    s.advance().unwrap();
    let dt = s.dt;
    assert!((dt - 1e-4).abs() < 1e-15, "fixed dt {dt}");
    let (lo, hi) = (s.model.lo, s.model.hi);
    let margin = 3.0 * s.model.dx;
    let (mut worst, mut moved) = (0.0_f64, 0.0_f64);
    for i in 0..s.n_fluid {
        let p = r0[i];
        if p.x < lo.x + margin || p.x > hi.x - margin || p.y < lo.y + margin || p.y > hi.y - margin {
            continue; // boundary reflections apply there
        }
        let expect = p + (v0[i] + (a0[i] + b0[i]) * (0.5 * dt)) * dt;
        assert_eq!(s.f.shift_dv[i], b0[i] * (0.5 * dt), "the advection keeps (dt/2)·a_b for the stress (particle {i})");
        worst = worst.max((s.pos[i] - expect).norm());
        moved = moved.max((b0[i] * (0.5 * dt * dt)).norm());
    }
    assert!(moved > 1e-12, "the shift must move some particle measurably ({moved})");
    assert!(worst < 1e-14, "r1 − (r0 + dt(v0 + dt/2 (a0 + a_b))) up to {worst} (shift displacement up to {moved})");
}

#[test]
fn shift_carries_no_momentum_in_a_periodic_box() {
    let sets: Vec<String> =
        common::PERIODIC_DROP.iter().chain(&["time.background=\"transport\""]).map(|s| s.to_string()).collect();
    let mut s = perturbed("oscillating-drop", &sets, 11);
    assert_eq!(s.n_fluid, s.pos.len(), "no walls in a periodic box");
    s.evaluate().unwrap();
    let (mut sum, mut abs) = (V2::new(0.0, 0.0), 0.0);
    for i in 0..s.n_fluid {
        sum += s.f.shift[i] * s.f.mass[i];
        abs += s.f.shift[i].norm() * s.f.mass[i];
    }
    assert!(abs > 0.0, "a perturbed set has a shift");
    assert!(sum.norm() < 1e-12 * abs, "Σ m a_b = {sum:?} against Σ m |a_b| = {abs}");
}

#[test]
fn artificial_stress_is_the_pair_sum_of_the_lagged_shift() {
    let sets: Vec<String> = common::PERIODIC_DROP
        .iter()
        .chain(&["time.background=\"transport\"", "phases.0.p_b=20.0", "phases.1.p_b=20.0"])
        .map(|s| s.to_string())
        .collect();
    let mut s = perturbed("oscillating-drop", &sets, 5);
    assert!(s.model.artificial_stress, "transport carries the artificial stress");
    let n = s.n_fluid;
    let mut rng = common::Rng::new(3);
    s.f.shift_dv = (0..n).map(|_| V2::new(rng.range(-0.02, 0.02), rng.range(-0.02, 0.02))).collect();
    s.model.artificial_stress = false;
    s.evaluate().unwrap();
    let without = s.f.acc.clone();
    s.model.artificial_stress = true;
    s.evaluate().unwrap();
    let got: Vec<V2<f64>> = (0..n).map(|i| s.f.acc[i] - without[i]).collect();
    // Brute force over every pair, minimum image in the periodic box.
    let (lo, hi) = (s.model.lo, s.model.hi);
    let (lx, ly) = (hi.x - lo.x, hi.y - lo.y);
    let (f, kp) = (&s.f, &s.model.kernel);
    let (mut worst, mut scale, mut momentum, mut abs) = (0.0_f64, 0.0_f64, V2::new(0.0, 0.0), 0.0);
    for (i, g) in got.iter().enumerate() {
        let mut sum = V2::new(0.0, 0.0);
        for j in 0..n {
            let mut d = s.pos[i] - s.pos[j];
            d.x -= lx * (d.x / lx).round();
            d.y -= ly * (d.y / ly).round();
            let r = d.norm();
            if j == i || r >= kp.support {
                continue;
            }
            let gw = d * (kernel_dwdr(kp, r) / r);
            let a_i = s.vel[i] * (f.rho[i] * f.shift_dv[i].dot(gw));
            let a_j = s.vel[j] * (f.rho[j] * f.shift_dv[j].dot(gw));
            let w = 0.5 * (1.0 / (f.sigma[i] * f.sigma[i]) + 1.0 / (f.sigma[j] * f.sigma[j]));
            sum += (a_i + a_j) * w;
        }
        let expect = sum * (1.0 / f.mass[i]);
        worst = worst.max((*g - expect).norm());
        scale = scale.max(expect.norm());
        momentum += *g * f.mass[i];
        abs += g.norm() * f.mass[i];
    }
    assert!(scale > 1e-6, "random shifts and velocities give a stress ({scale})");
    assert!(worst < 1e-10 * scale, "solver − brute force up to {worst} (|a^A| up to {scale})");
    assert!(momentum.norm() < 1e-12 * abs, "Σ m a^A = {momentum:?} against Σ m |a^A| = {abs}");
    // The shift-only form and the first evaluation carry none.
    let mut t = perturbed("oscillating-drop", &sets, 5);
    t.evaluate().unwrap();
    assert!(t.f.shift_dv.is_empty(), "no advection yet, no lagged ṽ − v");
}
