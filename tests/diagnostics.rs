//! Tests of `sphlab::diagnostics` on synthetic particle sets (docs/PHYSICS.md §9, §10).
//! Run with `--nocapture` to see the measured numbers.

use sphlab::diagnostics::analytic_flows::poiseuille_max;
use sphlab::diagnostics::contact_angle::{two_point_angle, two_point_points};
use sphlab::diagnostics::*;
use sphlab::scene::build::WALL;
use std::f64::consts::PI;

const DX: f64 = 0.5 / 65.0;
const R0: f64 = 0.25;

/// Cell-centred lattice on [0, side]² (spacing dx) plus 3 wall rows below y = 0; liquid inside
/// the circle of centre (0, yc) and radius rc, gas elsewhere.
fn cap_scene(dx: f64, side: f64, rc: f64, yc: f64) -> (Vec<[f64; 2]>, Vec<u32>) {
    let n = (side / dx).round() as usize;
    let (mut pos, mut phase) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            let p = [(i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx];
            pos.push(p);
            phase.push(if p[0] * p[0] + (p[1] - yc).powi(2) < rc * rc { 0 } else { 1 });
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

/// Cap of angle θ whose full-drop area equals the half circle of radius R0.
fn cap(theta_deg: f64, scale: f64) -> (Cap, Vec<[f64; 2]>, Vec<u32>) {
    let c = equilibrium_cap(scale * scale * PI * R0 * R0 / 2.0, theta_deg.to_radians());
    let (pos, phase) = cap_scene(DX, 0.5, c.radius, c.centre_y);
    (c, pos, phase)
}

#[test]
fn circle_fit_recovers_angle_and_radius() {
    for theta in [60.0, 90.0, 120.0] {
        let (c, pos, phase) = cap(theta, 1.0);
        let f = circle_fit(&pos, &phase, DX, 0.0).expect("fit");
        let rel = f.radius / c.radius - 1.0;
        eprintln!(
            "circle fit θ={theta}: θ_fit={:.3}° R_fit={:.5} (exact {:.5}, rel {:+.4}%) xc={:+.2e} yc={:.5} (exact {:.5}) half_width={:.5} (x_tp {:.5}) n={}",
            f.theta_deg, f.radius, c.radius, 100.0 * rel, f.xc, f.yc, c.centre_y, f.half_width, c.x_tp, f.n_points
        );
        assert!((f.theta_deg - theta).abs() < 3.0);
        assert!(rel.abs() < 0.01);
    }
}

#[test]
fn area_inversion_on_lattice_caps() {
    for theta in [60.0, 90.0, 120.0] {
        let (c, pos, phase) = cap(theta, 1.0);
        let all = measure_all(&pos, &phase, DX, 0.0, true);
        let xtp = contact_half_width(&pos, &phase, DX, 0.0).unwrap();
        eprintln!(
            "measure_all θ={theta}: area={:.3}° circle={:.3}° two_point={:.3}° | x_tp particle={:.5} exact={:.5}",
            all.area.unwrap(),
            all.circle_fit.unwrap(),
            all.two_point.unwrap(),
            xtp,
            c.x_tp
        );
        assert!((all.area.unwrap() - theta).abs() < 3.0);
        assert!((all.circle_fit.unwrap() - theta).abs() < 3.0);
        assert!((xtp - c.x_tp).abs() < DX);
    }
}

#[test]
fn two_point_averaged_over_lattice_offsets() {
    // One snapshot is quantised by the lattice (row offsets are multiples of Δx); average the
    // interface points over 16 caps whose contact line sweeps one Δx, as a time window would.
    for theta in [60.0, 90.0, 120.0] {
        let (c0, ..) = cap(theta, 1.0);
        let (mut p1m, mut p2m, mut theta_mean) = ([0.0; 2], [0.0; 2], 0.0);
        let m = 16;
        for k in 0..m {
            let scale = 1.0 + (k as f64 / m as f64) * DX / c0.x_tp;
            let (_, pos, phase) = cap(theta, scale);
            let (p1, p2) = two_point_points(&pos, &phase, DX, 0.0).unwrap();
            for d in 0..2 {
                p1m[d] += p1[d] / m as f64;
                p2m[d] += p2[d] / m as f64;
            }
            theta_mean += two_point_angle(p1, p2) / m as f64;
        }
        let (_, pos, phase) = cap(theta, 1.0);
        let single = two_point(&pos, &phase, DX, 0.0).unwrap();
        let averaged = two_point_angle(p1m, p2m);
        eprintln!(
            "two-point θ={theta}: single snapshot {single:.2}°, mean of angles {theta_mean:.2}°, angle of mean points {averaged:.2}°"
        );
        assert!((averaged - theta).abs() < 5.0);
    }
}

#[test]
fn area_inversion_exact_on_exact_cap() {
    let a = PI * R0 * R0 / 2.0;
    let mut worst: f64 = 0.0;
    for theta in [10.0, 30.0, 60.0, 90.0, 120.0, 150.0, 175.0] {
        let c = equilibrium_cap(a, f64::to_radians(theta));
        worst = worst.max((area_inversion(a, c.x_tp).unwrap() - theta).abs());
    }
    eprintln!("area inversion on exact caps: max error {worst:.2e}°");
    assert!(worst < 1e-8);
    assert!(area_inversion(0.0, 1.0).is_none() && area_inversion(1.0, 0.0).is_none());
}

/// `measure_all` on 10⁵ particles gives the cap's angle (its speed is timed in
/// `benches/diagnostics.rs`, not asserted here).
#[test]
fn measure_all_on_1e5_particles() {
    let dx = 0.5 / 316.0;
    let c = equilibrium_cap(PI * R0 * R0 / 2.0, 60f64.to_radians());
    let (pos, phase) = cap_scene(dx, 0.5, c.radius, c.centre_y);
    assert!(pos.len() > 100_000, "{} particles", pos.len());
    let all = measure_all(&pos, &phase, dx, 0.0, true);
    eprintln!("measure_all on {} particles: {all:?}", pos.len());
    assert!((all.circle_fit.unwrap() - 60.0).abs() < 1.0);
}

#[test]
fn empty_inputs_give_none() {
    assert!(two_point(&[], &[], DX, 0.0).is_none());
    assert!(circle_fit(&[], &[], DX, 0.0).is_none());
    assert!(contact_half_width(&[], &[], DX, 0.0).is_none());
    assert_eq!(measure_all(&[], &[], DX, 0.0, true), ContactAngles::default());
    assert!(oscillation(&[], &[]).is_none());
    assert!(max_normal_deviation(&[], &[], &[], DX, 0.0, [0.0; 2]).is_none());
    assert!(centroid(&[], &[], &[], 0)[0].is_nan());
    assert_eq!(kinetic_energy(&[], &[], &[], 0), 0.0);
    assert!(wall_shear_profile(&[], &[], &[], DX, 0.0, 0.5, 4, false).iter().all(|b| b.2 == 0));
    // All-liquid: no gas, so no interface.
    let (pos, _) = cap_scene(DX, 0.1, 0.0, 0.0);
    let phase = vec![0; pos.len()];
    assert!(circle_fit(&pos, &phase, DX, 0.0).is_none());
}

#[test]
fn poiseuille_series_limits() {
    let (l, nu, g) = (1e-3, 1e-6, 1e-4);
    let umax = poiseuille_max(l, nu, g);
    let (mut worst_steady, mut worst_zero): (f64, f64) = (0.0, 0.0);
    for k in 0..=20 {
        let y = l * k as f64 / 20.0;
        let steady = g / (2.0 * nu) * y * (l - y);
        worst_steady = worst_steady.max((poiseuille_velocity(y, 1e3, l, nu, g) - steady).abs() / umax);
        worst_zero = worst_zero.max(poiseuille_velocity(y, 0.0, l, nu, g).abs() / umax);
    }
    let mid = poiseuille_velocity(0.5 * l, 0.1, l, nu, g) / umax;
    eprintln!(
        "Poiseuille: u_max={umax:.4e}, steady rel err {worst_steady:.2e}, t=0 |u|/u_max {worst_zero:.2e}, centre at t=0.1 s: {mid:.4}"
    );
    assert!(worst_steady < 1e-10);
    assert!(worst_zero < 1e-3);
    assert!(mid > 0.0 && mid < 1.0);
}

#[test]
fn mode2_period_and_equilibrium_cap() {
    let t = drop_mode2_period(1.0, 1.0, 1.0, 0.1875);
    let c = equilibrium_cap(PI * R0 * R0 / 2.0, 60f64.to_radians());
    eprintln!(
        "mode-2 period {t:.5}; cap 60°: R_c={:.5} D/D0={:.5} apex={:.5} centre_y={:.5}",
        c.radius,
        c.x_tp / R0,
        c.apex,
        c.centre_y
    );
    assert!((t - 0.2945).abs() < 1e-4);
    assert!((c.radius - 0.3998).abs() < 1e-4);
    assert!((c.x_tp / R0 - 1.385).abs() < 1e-3);
    assert!((c.apex - 0.1999).abs() < 1e-4 && (c.centre_y + 0.1999).abs() < 1e-4);
    // 90°: the half circle itself.
    let h = equilibrium_cap(PI * R0 * R0 / 2.0, PI / 2.0);
    assert!((h.radius - R0).abs() < 1e-12 && h.centre_y.abs() < 1e-12);
}

/// Deterministic Gaussian noise (xorshift + Box–Muller).
fn noise(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n).map(|_| sigma * (-2.0 * u().ln()).sqrt() * (2.0 * PI * u()).cos()).collect()
}

#[test]
fn oscillation_of_noisy_damped_cosine() {
    let (mean, a0, period, beta) = (0.0796, 0.012, 0.37, 1.5);
    let w = 2.0 * PI / period;
    let t: Vec<f64> = (0..=2000).map(|i| i as f64 * 1e-3).collect();
    let clean: Vec<f64> = t.iter().map(|&t| mean + a0 * (-beta * t).exp() * (w * t).cos()).collect();
    // Truth: ½(max − min) of the clean signal over [0, T].
    let first: Vec<f64> = clean.iter().zip(&t).filter(|(_, &t)| t <= period).map(|(c, _)| *c).collect();
    let amp_true =
        0.5 * (first.iter().cloned().fold(f64::MIN, f64::max) - first.iter().cloned().fold(f64::MAX, f64::min));
    // Worst case over 8 noise realisations.
    let mut o = oscillation(&t, &clean).expect("clean");
    eprintln!(
        "oscillation, clean signal: period {:.6}, amplitude_first_cycle {:.6}",
        o.period, o.amplitude_first_cycle
    );
    for seed in 0..8 {
        let eps = noise(t.len(), 0.02 * a0, seed);
        let x: Vec<f64> = clean.iter().zip(&eps).map(|(c, e)| c + e).collect();
        let r = oscillation(&t, &x).expect("oscillation");
        if (r.period / period - 1.0).abs() > (o.period / period - 1.0).abs() {
            o.period = r.period;
        }
        if (r.amplitude_first_cycle - amp_true).abs() > (o.amplitude_first_cycle - amp_true).abs() {
            o.amplitude_first_cycle = r.amplitude_first_cycle;
        }
    }
    eprintln!(
        "oscillation: period {:.5} (true {period}, err {:+.3}%), amplitude_first_cycle {:.5} (true {amp_true:.5}, err {:+.2}%), amplitude {:.5}, mean {:.5}, cycles {}",
        o.period,
        100.0 * (o.period / period - 1.0),
        o.amplitude_first_cycle,
        100.0 * (o.amplitude_first_cycle / amp_true - 1.0),
        o.amplitude,
        o.mean,
        o.n_cycles
    );
    assert!((o.period / period - 1.0).abs() < 0.01);
    assert!((o.amplitude_first_cycle / amp_true - 1.0).abs() < 0.05);
    assert!(o.n_cycles >= 4);
    assert!(oscillation(&t, &vec![1.0; t.len()]).is_none());

    // Thesis-like short record (Fig. 4.1): t ∈ [0, 0.6], starting at the mean and moving up.
    let ts: Vec<f64> = (0..=600).map(|i| i as f64 * 1e-3).collect();
    let mut worst: f64 = 0.0;
    for seed in 0..8 {
        let eps = noise(ts.len(), 0.02 * a0, seed);
        let xs: Vec<f64> =
            ts.iter().zip(&eps).map(|(&t, e)| mean + a0 * (-beta * t).exp() * (w * t).sin() + e).collect();
        let s = oscillation(&ts, &xs).expect("short record");
        assert_eq!(s.n_cycles, 1);
        worst = worst.max((s.period / period - 1.0).abs());
    }
    eprintln!("oscillation, t in [0, 0.6], 8 noise seeds: worst period error {:.3}%", 100.0 * worst);
    assert!(worst < 0.01);
}

#[test]
fn wall_shear_profile_of_linear_shear() {
    let gamma = 2.5;
    let (pos, mut phase) = cap_scene(DX, 0.5, 0.25, 0.0);
    for (p, ph) in pos.iter().zip(phase.iter_mut()) {
        if *ph != WALL && p[0] > 0.3 {
            *ph = 1; // mix phases: any fluid phase counts
        }
    }
    let vel: Vec<[f64; 2]> = pos.iter().map(|p| [if p[1] > 0.0 { gamma * p[1] } else { 0.0 }, 0.0]).collect();
    let prof = wall_shear_profile(&pos, &vel, &phase, DX, 0.0, 0.5, 20, false);
    let worst = prof.iter().map(|b| (b.1 - gamma).abs()).fold(0.0, f64::max);
    // Flow towards −x from x = 0.25 on (the bins from 0.5 of the wall): |γ̇| is the same, the signed mean changes sign there.
    let back: Vec<[f64; 2]> =
        pos.iter().zip(&vel).map(|(p, v)| [if p[0] >= 0.25 { -v[0] } else { v[0] }, v[1]]).collect();
    let abs = wall_shear_profile(&pos, &back, &phase, DX, 0.0, 0.5, 20, false);
    let signed = wall_shear_profile(&pos, &back, &phase, DX, 0.0, 0.5, 20, true);
    for ((a, s), b) in abs.iter().zip(&signed).zip(&prof) {
        assert!((a.1 - b.1).abs() < 1e-12 && a.2 == s.2, "{a:?} {b:?}");
        let want = if s.0 * 0.5 > 0.25 { -gamma } else { gamma };
        assert!((s.1 - want).abs() < 1e-12, "bin at {}: signed {} (want {want})", s.0, s.1);
    }
    eprintln!(
        "wall shear: {} bins, counts {:?}, max |γ̇ − {gamma}| = {worst:.2e}",
        prof.len(),
        prof.iter().map(|b| b.2).collect::<Vec<_>>()
    );
    assert_eq!(prof.len(), 20);
    assert!(prof.iter().all(|b| b.2 > 0) && worst < 1e-12);
    assert_eq!(prof.iter().map(|b| b.2).sum::<usize>(), 65);
    assert!((prof[0].0 - 0.025).abs() < 1e-12 && (prof[19].0 - 0.975).abs() < 1e-12);
}

#[test]
fn flow_basics_and_normal_deviation() {
    let pos = vec![[1.0, 0.0], [0.0, 2.0], [3.0, 3.0], [0.0, -1.0]];
    let vel = vec![[1.0, 0.0], [0.0, 2.0], [1.0, 1.0], [5.0, 5.0]];
    let phase = vec![0, 0, 1, WALL];
    let mass = vec![1.0, 3.0, 2.0, 7.0];
    assert_eq!(kinetic_energy(&mass, &vel, &phase, 0), 0.5 + 6.0);
    assert_eq!(kinetic_energy(&mass, &vel, &phase, 1), 2.0);
    assert_eq!(centroid(&mass, &pos, &phase, 0), [0.25, 1.5]);
    assert_eq!(mass_per_phase(&mass, &phase, 2), vec![4.0, 2.0]);
    let rho = vec![1.01, 0.98, 1.3, 5.0];
    assert!((max_density_error(&rho, &[1.0, 1.2], &phase) - 0.1 / 1.2).abs() < 1e-12);
    // The maxima's particles: the wall (ρ = 5, v = (5, 5)) is never one of them.
    let (i, e) = argmax_density_error(&rho, &[1.0, 1.2], &phase).expect("fluid particles");
    assert!(i == 2 && (e - 0.1 / 1.2).abs() < 1e-12, "{i} {e}");
    assert_eq!(argmax_speed(&vel, &phase), Some((1, 2.0)));
    // A NaN is skipped, the first of equal errors wins, a phase without ρ0 and no fluid give None.
    let (rho2, phase2) = (vec![f64::NAN, 1.02, 0.98, 1.01], vec![0, 0, 0, 0]);
    assert_eq!(argmax_density_error(&rho2, &[1.0], &phase2).map(|k| k.0), Some(1));
    assert_eq!(argmax_density_error(&rho2, &[], &phase2), None);
    assert_eq!(argmax_speed(&vel[3..], &phase[3..]), None);

    // Radial outward normals: liquid grad_c = +r̂, gas grad_c = −r̂ → 0°; tilt one by 7°.
    let dx = 0.01;
    let (mut p, mut ph, mut g) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..36 {
        let a = k as f64 * PI / 36.0;
        for (r, phs, s) in [(0.2, 0u32, 1.0), (0.21, 1, -1.0)] {
            p.push([r * a.cos(), r * a.sin()]);
            ph.push(phs);
            g.push([s * a.cos(), s * a.sin()]);
        }
    }
    let d0 = max_normal_deviation(&p, &ph, &g, dx, 0.0, [0.0, 0.0]).unwrap();
    let i = 20; // liquid, angle 10·π/36, y > 3dx
    let a = (10.0 * PI / 36.0) + 7f64.to_radians();
    g[i] = [a.cos(), a.sin()];
    let d7 = max_normal_deviation(&p, &ph, &g, dx, 0.0, [0.0, 0.0]).unwrap();
    eprintln!("normal deviation: radial {d0:.2e}°, one tilted by 7°: {d7:.6}°");
    assert!(d0 < 1e-6 && (d7 - 7.0).abs() < 1e-9);
    // A weak gradient (below NORMAL_GRAD_FRACTION of the largest) tilted by 40° does not count;
    // just above the threshold it does.
    let j = 22; // liquid, angle 11·π/36
    let b = (11.0 * PI / 36.0) + 40f64.to_radians();
    let weak = 0.99 * flow::NORMAL_GRAD_FRACTION;
    g[j] = [weak * b.cos(), weak * b.sin()];
    let dw = max_normal_deviation(&p, &ph, &g, dx, 0.0, [0.0, 0.0]).unwrap();
    let strong = 1.01 * flow::NORMAL_GRAD_FRACTION;
    g[j] = [strong * b.cos(), strong * b.sin()];
    let ds = max_normal_deviation(&p, &ph, &g, dx, 0.0, [0.0, 0.0]).unwrap();
    assert!((dw - 7.0).abs() < 1e-9 && (ds - 40.0).abs() < 1e-9, "threshold: {dw}°, {ds}°");
}
