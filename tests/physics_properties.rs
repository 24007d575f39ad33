//! Properties of the pure physics functions (`core/src/physics/`) against docs/PHYSICS.md §0, §1, §3, §5.3:
//! kernel normalisation by radial quadrature (independent of the lattice), second moments
//! against closed forms, lattice sums and self values of §1, dW/dr against central finite
//! differences, F' ≤ 0, the sign rules of §0 through `physics::pair`, the surface stress tensor
//! against an independent matrix formula, and the EOS rest state and sound speed.

use sphlab::physics::eos::{eos_pressure, eos_stiffness};
use sphlab::physics::kernel::{kernel_dwdr, kernel_w, lattice_sum, KernelKind, KernelParams};
use sphlab::physics::pair::*;
use sphlab::physics::stress::{stress_isotropic, stress_tensor};
use sphlab::real::{Sym2, V2};
use std::f64::consts::PI;

/// 5-point Gauss–Legendre nodes and weights on [-1, 1] (exact for polynomials of degree ≤ 9).
const GL5: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// Knots of f(q) (the piecewise boundaries), support end included.
fn knots(kind: KernelKind) -> Vec<f64> {
    match kind {
        KernelKind::CubicSpline => vec![0.0, 1.0, 2.0],
        KernelKind::Quintic => vec![0.0, 1.0, 2.0, 3.0],
        KernelKind::Johnson | KernelKind::WendlandC2 => vec![0.0, 2.0],
        KernelKind::Gaussian => vec![0.0, 3.0],
    }
}

/// `2π ∫_0^{κh} r^(1+p) W(r) dr` by composite Gauss–Legendre aligned with the knots
/// (`sub` sub-intervals per knot interval).
fn radial_moment(kind: KernelKind, h: f64, p: i32, sub: usize) -> f64 {
    let kp = KernelParams::<f64>::new(kind, h);
    let k = knots(kind);
    let mut s = 0.0;
    for w in k.windows(2) {
        let (a, b) = (w[0] * h, w[1] * h);
        let dl = (b - a) / sub as f64;
        for m in 0..sub {
            let (lo, hi) = (a + m as f64 * dl, a + (m + 1) as f64 * dl);
            let (c, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            for &(x, wt) in &GL5 {
                let r = c + half * x;
                s += wt * half * r.powi(1 + p) * kernel_w(&kp, r);
            }
        }
    }
    2.0 * PI * s
}

/// Closed-form `∫ W dA` (the Gaussian is truncated at 3h and loses e⁻⁹, docs/PHYSICS.md §1).
fn exact_mass(kind: KernelKind) -> f64 {
    match kind {
        KernelKind::Gaussian => 1.0 - (-9.0f64).exp(),
        _ => 1.0,
    }
}

/// Closed-form second moment `∫ r² W dA / h²` (derived by hand from the table of §1):
/// cubic 31/49; quintic 7·(3⁹ − 6·2⁹ + 15)/(239·504) (from ∫_0^a q³(a−q)⁵dq = a⁹/504);
/// Johnson 4/5; Wendland C2 5/9 (Beta integrals); truncated Gaussian 1 − 10e⁻⁹.
fn exact_m2(kind: KernelKind) -> f64 {
    match kind {
        KernelKind::CubicSpline => 31.0 / 49.0,
        KernelKind::Quintic => 7.0 * (19683.0 - 6.0 * 512.0 + 15.0) / (239.0 * 504.0),
        KernelKind::Johnson => 0.8,
        KernelKind::WendlandC2 => 5.0 / 9.0,
        KernelKind::Gaussian => 1.0 - 10.0 * (-9.0f64).exp(),
    }
}

#[test]
fn kernel_integrates_to_one_by_radial_quadrature() {
    for kind in KernelKind::ALL {
        for h in [1.0, 1.3, 0.0123] {
            let m = radial_moment(kind, h, 0, 200);
            let exact = exact_mass(kind);
            println!("{:>13} h={h}: ∫W dA = {m:.12} (expected {exact:.12})", kind.name());
            assert!((m - exact).abs() < 1e-6, "{} h={h}: ∫W dA = {m:.10}, expected {exact:.10}", kind.name());
        }
    }
}

#[test]
fn gaussian_truncation_loss_is_e_minus_9() {
    // The brief asks ∫W = 1 within 1e-6 for every kernel; the truncated Gaussian (α = 1/(πh²),
    // untruncated) cannot satisfy that: it misses e⁻⁹ = 1.234e-4 (docs/PHYSICS.md §1, optional fix
    // not applied in core/src/physics/kernel.rs). Pin the deficit so a change is noticed.
    let m = radial_moment(KernelKind::Gaussian, 1.0, 0, 400);
    let loss = 1.0 - m;
    println!("gaussian: 1 − ∫W dA = {loss:.6e}");
    assert!(
        (loss - (-9.0f64).exp()).abs() < 1e-9,
        "gaussian mass deficit {loss:e}, expected e⁻⁹ = {:e}",
        (-9.0f64).exp()
    );
}

#[test]
fn kernel_second_moment_matches_closed_form() {
    for kind in KernelKind::ALL {
        let exact = exact_m2(kind);
        for h in [1.0, 1.3] {
            // two resolutions: the quadrature is converged, and it agrees with the closed form
            let coarse = radial_moment(kind, h, 2, 50) / (h * h);
            let fine = radial_moment(kind, h, 2, 400) / (h * h);
            println!("{:>13} h={h}: ∫r²W dA/h² = {fine:.12} (closed form {exact:.12})", kind.name());
            assert!(
                (coarse - fine).abs() < 1e-10,
                "{} h={h}: quadrature not converged: {coarse} vs {fine}",
                kind.name()
            );
            assert!(
                (fine - exact).abs() < 1e-9,
                "{} h={h}: ∫r²W dA/h² = {fine:.12}, closed form {exact:.12}",
                kind.name()
            );
        }
    }
}

#[test]
fn lattice_sums_match_spec() {
    let cases = [
        (KernelKind::Quintic, 1.0, 1.00006),
        (KernelKind::CubicSpline, 1.2, 0.99976),
        (KernelKind::CubicSpline, 1.3, 0.99995),
        (KernelKind::Johnson, 1.2, 1.05586),
        (KernelKind::WendlandC2, 1.3, 1.0105),
        (KernelKind::Gaussian, 1.0, 0.99993),
    ];
    for (kind, ratio, want) in cases {
        let s1 = lattice_sum(kind, ratio, 1.0);
        // scale invariance: Δx² Σ W is independent of Δx
        let dx = 0.0137;
        let s2 = lattice_sum(kind, ratio * dx, dx) * dx * dx;
        println!("{:>13} h={ratio}Δx: Δx²ΣW = {s1:.6} (spec {want}), at Δx={dx}: {s2:.6}", kind.name());
        assert!((s1 - want).abs() < 1e-3, "{} h={ratio}Δx: lattice sum {s1:.6}, spec {want}", kind.name());
        assert!(
            (s1 - want).abs() < 1e-4,
            "{} h={ratio}Δx: lattice sum {s1:.6}, spec {want} (5-digit value)",
            kind.name()
        );
        assert!((s1 - s2).abs() < 1e-9, "{} h={ratio}Δx: Δx²ΣW depends on Δx: {s1} vs {s2}", kind.name());
    }
}

#[test]
fn self_values() {
    for (kind, want) in [(KernelKind::Quintic, 0.30766), (KernelKind::CubicSpline, 0.45473)] {
        for h in [1.0, 0.37] {
            let kp = KernelParams::<f64>::new(kind, h);
            let w0 = kernel_w(&kp, 0.0) * h * h;
            println!("{:>13}: W(0)h² = {w0:.6} (spec {want})", kind.name());
            assert!((w0 - want).abs() < 1e-5, "{}: W(0)h² = {w0:.6}, spec {want}", kind.name());
        }
    }
}

#[test]
fn dwdr_matches_central_difference() {
    for kind in KernelKind::ALL {
        let h = 1.3;
        let kp = KernelParams::<f64>::new(kind, h);
        let kappa = kind.support_factor();
        let kn = knots(kind);
        // Richardson-extrapolated central difference: removes the ε² truncation term, which
        // alone is ~1e-6 relative near the support end, where F' → 0 like (κ − q)².
        let eps = 1e-4 * h;
        let cd = |r: f64, e: f64| (kernel_w(&kp, r + e) - kernel_w(&kp, r - e)) / (2.0 * e);
        let fmax = (0..=1000).map(|k| kernel_dwdr(&kp, k as f64 * kappa * h / 1000.0).abs()).fold(0.0, f64::max);
        let mut worst: f64 = 0.0;
        let n = 2000;
        for k in 1..n {
            let q = k as f64 * kappa / n as f64 + 1e-4;
            if kn.iter().any(|&t| (q - t).abs() < 1e-3 + 1e-4) || q >= kappa {
                continue;
            }
            let r = q * h;
            let fd = (4.0 * cd(r, 0.5 * eps) - cd(r, eps)) / 3.0;
            let d = kernel_dwdr(&kp, r);
            let err = (fd - d).abs() / (d.abs() + 1e-6 * fmax);
            worst = worst.max(err);
            assert!(err < 1e-6, "{} q={q}: dW/dr = {d:e}, central difference {fd:e} (rel err {err:e})", kind.name());
        }
        println!("{:>13}: worst rel err of dW/dr vs central difference {worst:.2e}", kind.name());
    }
}

#[test]
fn dwdr_is_nonpositive_everywhere() {
    for kind in KernelKind::ALL {
        for h in [1.0, 1.2] {
            let kp = KernelParams::<f64>::new(kind, h);
            let kp32 = KernelParams::<f32>::new(kind, h);
            let end = (kind.support_factor() + 0.5) * h;
            for k in 0..=20000 {
                let r = k as f64 * end / 20000.0;
                let d = kernel_dwdr(&kp, r);
                let d32 = kernel_dwdr(&kp32, r as f32);
                assert!(d <= 0.0, "{} h={h}: F'({r}) = {d:e} > 0", kind.name());
                assert!(d32 <= 0.0, "{} h={h} f32: F'({r}) = {d32:e} > 0", kind.name());
                assert!(kernel_w(&kp, r) >= 0.0, "{} W({r}) < 0", kind.name());
            }
            let s = kind.support_factor() * h;
            assert_eq!(kernel_w(&kp, s), 0.0, "{}: W(κh) must be 0", kind.name());
            assert_eq!(kernel_dwdr(&kp, s * 1.0001), 0.0, "{}: F' beyond support must be 0", kind.name());
        }
    }
}

/// Deterministic pseudo-random numbers in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn positive_pressure_pushes_i_away_from_j() {
    let mut rng = Lcg(7);
    for kind in KernelKind::ALL {
        let kp = KernelParams::<f64>::new(kind, 1.0);
        for _ in 0..200 {
            let xi = V2::new(rng.next() * 4.0, rng.next() * 4.0);
            let r = 0.05 + rng.next() * (kind.support_factor() - 0.1);
            let ang = rng.next() * 2.0 * PI;
            let xj = xi - V2::new(r * ang.cos(), r * ang.sin());
            let x_ij = xi - xj;
            let r = x_ij.norm();
            let gw = grad_w_ij(kernel_dwdr(&kp, r), x_ij, r);
            assert!(gw.dot(x_ij) < 0.0, "{}: ∇_iW_ij must point from i to j", kind.name());
            let (pi, pj) = (0.1 + rng.next(), 0.1 + rng.next());
            let (si, sj) = (0.8 + 0.4 * rng.next(), 0.8 + 0.4 * rng.next());
            let a = pressure_acc_ij(pi, 1.0 / (si * si), pj, 1.0 / (sj * sj), gw);
            let cos = a.dot(x_ij) / (a.norm() * r);
            assert!(
                (cos - 1.0).abs() < 1e-12,
                "{}: pressure acc not along e_ij (away from j): cos = {cos}",
                kind.name()
            );
            // and negative pressure pulls
            let a2 = pressure_acc_ij(-pi, 1.0 / (si * si), -pj, 1.0 / (sj * sj), gw);
            assert!(a2.dot(x_ij) < 0.0, "{}: tension must pull i towards j", kind.name());
            // antisymmetry: the reaction on j is equal and opposite
            let gw_ji = grad_w_ij(kernel_dwdr(&kp, r), -x_ij, r);
            let b = pressure_acc_ij(pj, 1.0 / (sj * sj), pi, 1.0 / (si * si), gw_ji);
            assert!((a + b).norm() <= 1e-15 * a.norm(), "pressure pair not antisymmetric: {a:?} vs {b:?}");
        }
    }
}

#[test]
fn viscosity_decelerates_i_relative_to_j() {
    let mut rng = Lcg(11);
    for kind in KernelKind::ALL {
        let h = 1.2;
        let kp = KernelParams::<f64>::new(kind, h);
        for _ in 0..200 {
            let r = 0.02 + rng.next() * (kind.support_factor() * h - 0.05);
            let dwdr = kernel_dwdr(&kp, r);
            let fac = viscous_fac_ij(dwdr, r, h);
            assert!(fac < 0.0, "{} r={r}: F'/r regularised = {fac} must be < 0", kind.name());
            let reg = r * dwdr / (r * r + 0.01 * h * h);
            assert!((fac - reg).abs() <= 1e-15 * reg.abs(), "viscous_fac_ij {fac} ≠ rF'/(r²+0.01h²) {reg}");
            let v_ij = V2::new(rng.next() - 0.5, rng.next() - 0.5);
            let (ei, ej) = (0.01 + rng.next(), 0.01 + rng.next());
            let eta = harmonic_viscosity(ei, ej);
            assert!((eta - 2.0 * ei * ej / (ei + ej)).abs() < 1e-15, "harmonic mean {eta}");
            assert!(eta <= ei.max(ej) && eta >= ei.min(ej), "harmonic mean {eta} outside [{ei}, {ej}]");
            let a = viscous_acc_ij(eta, 1.1, 0.9, fac, v_ij);
            let cos = a.dot(v_ij) / (a.norm() * v_ij.norm());
            assert!((cos + 1.0).abs() < 1e-12, "{}: viscous acc must oppose v_ij: cos = {cos}", kind.name());
            let b = viscous_acc_ij(eta, 0.9, 1.1, fac, -v_ij);
            assert!((a + b).norm() <= 1e-15 * a.norm(), "viscous pair not antisymmetric");
        }
    }
    assert_eq!(harmonic_viscosity(0.0, 0.0), 0.0, "η̄(0,0) must be 0, not NaN");
}

/// Independent full-matrix form `σ|g|(I/2 − n̂n̂)`.
fn pi_matrix(g: V2<f64>, s: f64) -> [[f64; 2]; 2] {
    let m = g.norm();
    let (nx, ny) = (g.x / m, g.y / m);
    [[s * m * (0.5 - nx * nx), -s * m * nx * ny], [-s * m * ny * nx, s * m * (0.5 - ny * ny)]]
}

#[test]
fn stress_tensor_is_symmetric_traceless_and_matches_formula() {
    let mut rng = Lcg(3);
    for _ in 0..500 {
        let g = V2::new(rng.next() * 2.0 - 1.0, rng.next() * 2.0 - 1.0);
        let s = 0.1 + rng.next();
        let t = stress_tensor(g, s);
        let want = pi_matrix(g, s);
        // full matrix through mul_vec on the basis vectors
        let c0 = t.mul_vec(V2::new(1.0, 0.0));
        let c1 = t.mul_vec(V2::new(0.0, 1.0));
        let got = [[c0.x, c1.x], [c0.y, c1.y]];
        let scale = s * g.norm();
        for a in 0..2 {
            for b in 0..2 {
                assert!(
                    (got[a][b] - want[a][b]).abs() < 1e-14 * scale,
                    "Π[{a}][{b}] = {} vs σ|g|(I/2−n̂n̂) = {}",
                    got[a][b],
                    want[a][b]
                );
            }
        }
        assert!(
            (want[0][0] + want[1][1]).abs() < 1e-14 * scale,
            "independent formula trace {}",
            want[0][0] + want[1][1]
        );
        assert!((got[0][1] - got[1][0]).abs() == 0.0, "Π not symmetric: {:?}", got);
        assert!((got[0][0] + got[1][1]).abs() < 1e-14 * scale, "Π not traceless: trace {}", got[0][0] + got[1][1]);
        // eigenvectors: Π g = −σ|g|/2 g (compression along the normal), Π g⊥ = +σ|g|/2 g⊥
        let pg = t.mul_vec(g);
        let want_pg = g * (-0.5 * scale);
        assert!((pg - want_pg).norm() < 1e-14 * scale * g.norm(), "Π·g = {pg:?}, expected {want_pg:?}");
        let gp = V2::new(-g.y, g.x);
        let pgp = t.mul_vec(gp);
        assert!((pgp - gp * (0.5 * scale)).norm() < 1e-14 * scale * g.norm(), "Π·g⊥ = {pgp:?}");
        // even in g, linear in |g| and σ
        let tm = stress_tensor(-g, s);
        assert!((tm.xx - t.xx).abs() < 1e-15 * scale && (tm.xy - t.xy).abs() < 1e-15 * scale, "Π(−g) ≠ Π(g)");
        let t3 = stress_tensor(g * 3.0, s);
        assert!(
            (t3.xx - 3.0 * t.xx).abs() < 1e-14 * scale && (t3.xy - 3.0 * t.xy).abs() < 1e-14 * scale,
            "Π(3g) ≠ 3Π(g)"
        );
    }
    let z = stress_tensor(V2::<f64>::zero(), 1.0);
    assert_eq!(z, Sym2::zero(), "Π(g = 0) must be exactly 0, got {z:?}");
    let z32 = stress_tensor(V2::<f32>::zero(), 1.0);
    assert!(z32.xx == 0.0 && z32.xy == 0.0 && z32.xx.is_finite(), "f32 Π(0) = {z32:?}");
    // spec component form, horizontal interface: g = (0, 1) ⇒ Π_xx = σ/2, Π_xy = 0
    let t = stress_tensor(V2::new(0.0, 1.0), 1.0);
    assert_eq!((t.xx, t.xy), (0.5, 0.0), "flat interface Π = {t:?}");
}

#[test]
fn tangential_form_pulls_along_the_interface_and_not_across() {
    // Π + sI = σ|g|(I − n̂n̂): no traction on the interface's own plane (Π·g + s g = 0), a
    // tension σ|g| along it, and its surface pair term is that of a pressure −s.
    let mut rng = Lcg(7);
    for _ in 0..200 {
        let g = V2::new(rng.next() * 2.0 - 1.0, rng.next() * 2.0 - 1.0);
        let s = 0.1 + rng.next();
        let (t, iso) = (stress_tensor(g, s), stress_isotropic(g, s));
        let scale = s * g.norm();
        let across = t.mul_vec(g) + g * iso;
        assert!(across.norm() < 1e-14 * scale * g.norm(), "(Π + sI)·g = {across:?}, expected 0");
        let gp = V2::new(-g.y, g.x);
        let along = t.mul_vec(gp) + gp * iso;
        assert!((along - gp * scale).norm() < 1e-14 * scale * g.norm(), "(Π + sI)·g⊥ = {along:?}");
        let (si, sj, gw) = (iso, 0.3 * iso, V2::new(rng.next() - 0.5, rng.next() - 0.5));
        let a = surface_isotropic_acc_ij(si, 1.1, sj, 0.9, gw);
        let b = pressure_acc_ij(-si, 1.1, -sj, 0.9, gw);
        assert!((a - b).norm() < 1e-14 * (a.norm() + 1e-300), "isotropic term {a:?} vs the pressure term of −s {b:?}");
    }
    assert_eq!(stress_isotropic(V2::<f64>::zero(), 1.0), 0.0, "s(g = 0) must be 0");
}

#[test]
fn surface_pair_force_antisymmetric() {
    let kp = KernelParams::<f64>::new(KernelKind::Quintic, 1.0);
    let x_ij = V2::new(0.7, -1.1);
    let r = x_ij.norm();
    let gw = grad_w_ij(kernel_dwdr(&kp, r), x_ij, r);
    let gw_ji = grad_w_ij(kernel_dwdr(&kp, r), -x_ij, r);
    let (pi, pj) = (stress_tensor(V2::new(0.3, 0.2), 1.0), stress_tensor(V2::new(-0.1, 0.4), 1.0));
    let a = surface_acc_ij(pi, 1.2, pj, 0.8, gw);
    let b = surface_acc_ij(pj, 0.8, pi, 1.2, gw_ji);
    assert!(a.norm() > 0.0 && (a + b).norm() <= 1e-16 * a.norm(), "surface pair not antisymmetric: {a:?} {b:?}");
}

#[test]
fn eos_rest_state_and_sound_speed() {
    for (rho0, c0, gamma, p_b) in [
        (1.0, 35.0, 7.0, 0.0),
        (1.0, 20.0, 7.0, 57.0),
        (1000.0, 20.0, 7.0, 0.0),
        (1.2, 258.2, 1.4, 0.0),
        (3.0, 5.0, 1.0, -2.0),
    ] {
        let b = eos_stiffness(rho0, c0, gamma);
        assert!((b - rho0 * c0 * c0 / gamma).abs() <= 1e-12 * b, "B = {b}");
        let p0 = eos_pressure(rho0, rho0, b, gamma, p_b);
        assert_eq!(p0, p_b, "p(ρ0) = {p0}, expected p_b = {p_b}");
        let e = 1e-6 * rho0;
        let dpdrho =
            (eos_pressure(rho0 + e, rho0, b, gamma, p_b) - eos_pressure(rho0 - e, rho0, b, gamma, p_b)) / (2.0 * e);
        let rel = (dpdrho - c0 * c0) / (c0 * c0);
        println!("ρ0={rho0} c0={c0} γ={gamma}: dp/dρ = {dpdrho:.8} (c0² = {})", c0 * c0);
        assert!(rel.abs() < 1e-7, "dp/dρ at ρ0 = {dpdrho}, c0² = {} (rel {rel:e})", c0 * c0);
        // monotone: compression raises pressure
        assert!(
            eos_pressure(1.01 * rho0, rho0, b, gamma, p_b) > p_b
                && eos_pressure(0.99 * rho0, rho0, b, gamma, p_b) < p_b
        );
        let p32 = eos_pressure(rho0 as f32, rho0 as f32, b as f32, gamma as f32, p_b as f32);
        assert_eq!(p32, p_b as f32, "f32 p(ρ0) = {p32}");
    }
}
