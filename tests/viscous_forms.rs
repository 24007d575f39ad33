//! The two viscous pair forms of docs/PHYSICS.md §4.1 on a square lattice with free edges,
//! uniform number density (1/σ² = Δx⁴), η = 1, ρ = 1, every kernel at the h of the validation
//! cases ([`KERNELS`]):
//! * in the bulk both sum to η∇²v for a divergence-free field, and the projected form to
//!   η(∇²v + 2∇(∇·v)) for one that is not;
//! * their pair power over an n × n patch under a uniform gradient G is, per unit area, T70's
//!   η|G|² and the projected form's 2η e:e, less an edge loss O(h/L) removed here by
//!   extrapolating from n = 40 and 80. So for an irrotational G (|G|² = e:e) T70 takes out half
//!   the continuum's 2η e:e and the projected form all of it; for simple shear both take it all;
//! * on the capillary-wave case's lattice, under a standing wave's potential flow below a free
//!   surface, the projected form takes out twice T70's, and both approach their continuum
//!   values at first order in Δx.
//!
//! The projected form weighs the lattice's fourth angular moments, which a square lattice does
//! not make isotropic: the same field turned by θ gives a result with a cos 4θ part (measured
//! up to 40 % of the value at these h; see the printout). So
//! every check averages the field over eight orientations θ = kπ/16, which removes that part
//! exactly and leaves the isotropic value the equations are about.

use sphlab::diagnostics::viscous_share::{potential_wave_share, unit_pair_term};
use sphlab::physics::kernel::{KernelKind, KernelParams};
use sphlab::real::V2;
use sphlab::scene::ViscousForm;

type Field<'a> = &'a dyn Fn(V2<f64>) -> V2<f64>;

/// Each kernel at the h/Δx the oscillating drop's kernel rows run it (src/validate/oscillation).
const KERNELS: [(KernelKind, f64); 5] = [
    (KernelKind::CubicSpline, 1.2),
    (KernelKind::Quintic, 1.2),
    (KernelKind::Gaussian, 1.2),
    (KernelKind::WendlandC2, 1.5),
    (KernelKind::Johnson, 2.0),
];

/// The eight orientations a quarter turn apart (a cos 4θ term averages to zero over them).
fn angles() -> impl Iterator<Item = f64> {
    (0..8).map(|k| k as f64 * std::f64::consts::PI / 16.0)
}

/// `R(θ) u` (turn by θ).
fn turn(u: V2<f64>, th: f64) -> V2<f64> {
    let (s, c) = th.sin_cos();
    V2::new(c * u.x - s * u.y, s * u.x + c * u.y)
}

/// Σ_j of one form's pair term for particle (a, b) of an n × n lattice (Δx = 1), velocity field v.
fn pair_sum(kp: &KernelParams<f64>, form: ViscousForm, n: i64, a: i64, b: i64, v: Field) -> V2<f64> {
    let at = |a: i64, b: i64| V2::new(a as f64 + 0.5, b as f64 + 0.5);
    let (xi, vi) = (at(a, b), v(at(a, b)));
    let reach = kp.support.ceil() as i64;
    let mut sum = V2::zero();
    for c in (a - reach).max(0)..(a + reach + 1).min(n) {
        for d in (b - reach).max(0)..(b + reach + 1).min(n) {
            let xj = at(c, d);
            sum += unit_pair_term(kp, form, xi - xj, vi - v(xj));
        }
    }
    sum
}

/// Pair power per unit area, −Σ_i v_i·Σ_j term / n², of v = R G Rᵀ x on an n × n patch.
fn dissipation(kp: &KernelParams<f64>, form: ViscousForm, n: i64, g: [[f64; 2]; 2], th: f64) -> f64 {
    let v = move |x: V2<f64>| {
        let y = turn(x, -th);
        turn(V2::new(g[0][0] * y.x + g[0][1] * y.y, g[1][0] * y.x + g[1][1] * y.y), th)
    };
    let mut p = 0.0;
    for a in 0..n {
        for b in 0..n {
            let x = V2::new(a as f64 + 0.5, b as f64 + 0.5);
            p -= v(x).dot(pair_sum(kp, form, n, a, b, &v));
        }
    }
    p / (n * n) as f64
}

/// The dissipation averaged over the orientations and extrapolated to L/h → ∞ from n = 40 and
/// 80 (edge loss ∝ 1/n); also the spread (max − min) over the orientations at n = 80.
fn bulk_dissipation(kp: &KernelParams<f64>, form: ViscousForm, g: [[f64; 2]; 2]) -> (f64, f64) {
    let (mut sum, mut lo, mut hi) = (0.0, f64::INFINITY, f64::NEG_INFINITY);
    for th in angles() {
        let (d40, d80) = (dissipation(kp, form, 40, g, th), dissipation(kp, form, 80, g, th));
        sum += 2.0 * d80 - d40;
        (lo, hi) = (lo.min(d80), hi.max(d80));
    }
    (sum / 8.0, hi - lo)
}

#[test]
fn viscous_forms_dissipate_by_the_strain_rate() {
    let strain = [[1.0, 0.0], [0.0, -1.0]]; // irrotational: |G|² = 2, 2 e:e = 4
    let shear = [[0.0, 1.0], [0.0, 0.0]]; // simple shear: |G|² = 1, 2 e:e = 1
    for (kind, h) in KERNELS {
        let kp = KernelParams::<f64>::new(kind, h);
        let name = kind.name();
        let ((lap, lap_spread), (proj, proj_spread)) = (
            bulk_dissipation(&kp, ViscousForm::Laplacian, strain),
            bulk_dissipation(&kp, ViscousForm::Projected, strain),
        );
        eprintln!("{name}: strain T70 {lap:.4} (spread {lap_spread:.3}), projected {proj:.4} (spread {proj_spread:.3}); continuum 4");
        assert!((proj / lap - 2.0).abs() < 0.01, "{name}: projected / T70 strain dissipation {proj} / {lap} ≠ 2");
        assert!((proj / 4.0 - 1.0).abs() < 0.03, "{name}: projected strain dissipation {proj} ≠ 2η e:e = 4");
        let ((lap, _), (proj, _)) = (
            bulk_dissipation(&kp, ViscousForm::Laplacian, shear),
            bulk_dissipation(&kp, ViscousForm::Projected, shear),
        );
        eprintln!("{name}: shear T70 {lap:.4}, projected {proj:.4}; continuum 1");
        assert!((proj / lap - 1.0).abs() < 0.01, "{name}: projected / T70 shear dissipation {proj} / {lap} ≠ 1");
        assert!((proj - 1.0).abs() < 0.03, "{name}: shear dissipation {proj} ≠ η|G|² = 2η e:e = 1");
    }
}

#[test]
fn viscous_forms_sum_to_the_laplacian_in_the_bulk() {
    let (n, a, b) = (21, 10, 10);
    let centre = V2::new(10.5, 10.5);
    // Divergence-free: f = (y², 0), ∇²f = (2, 0) for both forms.
    let div_free = |y: V2<f64>| V2::new(y.y * y.y, 0.0);
    // Not divergence-free: f = (x², 0), ∇²f = (2, 0), ∇²f + 2∇(∇·f) = (6, 0).
    let compressive = |y: V2<f64>| V2::new(y.x * y.x, 0.0);
    for (kind, h) in KERNELS {
        let kp = KernelParams::<f64>::new(kind, h);
        let cases: [(ViscousForm, Field, f64); 4] = [
            (ViscousForm::Laplacian, &div_free, 2.0),
            (ViscousForm::Projected, &div_free, 2.0),
            (ViscousForm::Laplacian, &compressive, 2.0),
            (ViscousForm::Projected, &compressive, 6.0),
        ];
        for (k, (form, f, want)) in cases.into_iter().enumerate() {
            // The field turned by θ about the particle, v(x) = R f(Rᵀ(x − x_c)); its sum turned back.
            let mut mean = V2::zero();
            for th in angles() {
                let v = move |x: V2<f64>| turn(f(turn(x - centre, -th)), th);
                mean += turn(pair_sum(&kp, form, n, a, b, &v), -th) * 0.125;
            }
            eprintln!("{} case {k}: ({:.5}, {:.1e}), want ({want}, 0)", kind.name(), mean.x, mean.y);
            assert!(
                (mean.x / want - 1.0).abs() < 0.03 && mean.y.abs() < 1e-9,
                "{} case {k}: {mean:?} ≠ ({want}, 0)",
                kind.name()
            );
        }
    }
}

/// The capillary-wave case's flow (docs/PHYSICS.md §4.1, §9(f)): at λ/22, 44, 88, 176 the
/// quintic's pair sums take out, of the continuum's 2η∫e:e, T70 0.375, 0.431, 0.462, 0.478 and
/// the projected form 0.750, 0.862, 0.923, 0.956: exactly twice T70, and short of it by a
/// surface loss that halves with Δx (the pairs the free surface cuts off). Required: the factor
/// 2 within 1 % at every resolution, the projected loss halving within 15 % from λ/44 to λ/88,
/// and both limits (0.5, 1) approached from below.
#[test]
fn standing_wave_dissipation_on_the_lattice() {
    let kp = KernelParams::<f64>::new(KernelKind::Quintic, 1.2);
    let mut loss = Vec::new();
    for nx in [22, 44, 88, 176] {
        let (lap, proj) = (
            potential_wave_share(&kp, ViscousForm::Laplacian, nx),
            potential_wave_share(&kp, ViscousForm::Projected, nx),
        );
        eprintln!("λ/{nx}: T70 {lap:.4}, projected {proj:.4} of 2η∫e:e");
        assert!((proj / lap - 2.0).abs() < 0.02, "λ/{nx}: projected / T70 = {} ≠ 2", proj / lap);
        assert!(proj < 1.0 && lap < 0.5, "λ/{nx}: above the continuum's value: {lap}, {proj}");
        loss.push(1.0 - proj);
    }
    for w in loss.windows(2) {
        assert!(w[1] < w[0], "the surface loss does not fall with Δx: {loss:?}");
    }
    let halving = loss[1] / loss[2];
    assert!((halving / 2.0 - 1.0).abs() < 0.15, "surface loss λ/44 ÷ λ/88 = {halving}, not first order");
}
