//! The complex arithmetic Prosperetti's capillary-wave solution needs (docs/PHYSICS.md §14): a
//! small complex type, the Faddeeva function `w(z) = exp(−z²) erfc(−iz)` by Weideman's rational
//! expansion (SIAM J. Numer. Anal. 31, 1994, 1497–1518), the complex `erfc` and the scaled
//! product `exp(z²) erfc(z)` built on it, and the roots of a complex polynomial by the
//! Durand–Kerner iteration with Newton polishing.

use std::f64::consts::PI;
use std::ops::{Add, Div, Mul, Neg, Sub};
use std::sync::OnceLock;

/// A complex number.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct C {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

/// `re + i·im`.
pub const fn c(re: f64, im: f64) -> C {
    C { re, im }
}

/// The imaginary unit.
pub const I: C = c(0.0, 1.0);

impl C {
    /// A real number.
    pub const fn real(re: f64) -> C {
        c(re, 0.0)
    }
    /// |z|.
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    /// exp(z).
    pub fn exp(self) -> C {
        let m = self.re.exp();
        c(m * self.im.cos(), m * self.im.sin())
    }
    /// z·z.
    pub fn sq(self) -> C {
        self * self
    }
    /// The principal square root.
    pub fn sqrt(self) -> C {
        let r = self.abs();
        if r == 0.0 {
            return C::default();
        }
        let re = ((r + self.re) / 2.0).sqrt();
        let im = ((r - self.re) / 2.0).sqrt();
        c(re, if self.im < 0.0 { -im } else { im })
    }
    /// True when both parts are finite.
    pub fn is_finite(self) -> bool {
        self.re.is_finite() && self.im.is_finite()
    }
}

impl Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        c(self.re + o.re, self.im + o.im)
    }
}
impl Sub for C {
    type Output = C;
    fn sub(self, o: C) -> C {
        c(self.re - o.re, self.im - o.im)
    }
}
impl Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        c(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
}
impl Mul<f64> for C {
    type Output = C;
    fn mul(self, s: f64) -> C {
        c(self.re * s, self.im * s)
    }
}
impl Div for C {
    type Output = C;
    fn div(self, o: C) -> C {
        // Smith's algorithm: no overflow of |o|² for large o.
        if o.re.abs() >= o.im.abs() {
            let (r, d) = (o.im / o.re, o.re + o.im * (o.im / o.re));
            c((self.re + self.im * r) / d, (self.im - self.re * r) / d)
        } else {
            let (r, d) = (o.re / o.im, o.im + o.re * (o.re / o.im));
            c((self.re * r + self.im) / d, (self.im * r - self.re) / d)
        }
    }
}
impl Neg for C {
    type Output = C;
    fn neg(self) -> C {
        c(-self.re, -self.im)
    }
}

/// Terms of Weideman's expansion: 40 gives about 1e-14 relative error in the upper half
/// plane (his Table 1 reaches 1e-13 at 32).
const WEIDEMAN_N: usize = 40;

/// Weideman's `L = (N/√2)^{1/2}` and his coefficients `a_1 … a_N`: the Fourier cosine
/// coefficients `a_m = (1/2M) Σ_k f(t_k) cos(mθ_k)` of `f(t) = exp(−t²)(L² + t²)` sampled at
/// `t_k = L tan(θ_k/2)`, `θ_k = kπ/M`, `k = −M+1 … M−1`, `M = 2N` (f = 0 at θ = ±π), by a
/// direct sum (2N coefficients from 4N samples, computed once).
fn weideman() -> &'static (f64, Vec<f64>) {
    static COEF: OnceLock<(f64, Vec<f64>)> = OnceLock::new();
    COEF.get_or_init(|| {
        let n = WEIDEMAN_N;
        let m = 2 * n;
        let l = (n as f64 / 2f64.sqrt()).sqrt();
        let samples: Vec<(f64, f64)> = (-(m as i64) + 1..m as i64)
            .map(|k| {
                let theta = k as f64 * PI / m as f64;
                let t = l * (theta / 2.0).tan();
                (theta, (-t * t).exp() * (l * l + t * t))
            })
            .collect();
        let a = (1..=n)
            .map(|j| samples.iter().map(|(th, f)| f * (j as f64 * th).cos()).sum::<f64>() / (2 * m) as f64)
            .collect();
        (l, a)
    })
}

/// The Faddeeva function `w(z) = exp(−z²) erfc(−iz)`, for every z: Weideman's expansion
/// `w = 2p(Z)/(L − iz)² + π^{−1/2}/(L − iz)`, `Z = (L + iz)/(L − iz)`, `p(Z) = Σ a_m Z^{m−1}`
/// in the upper half plane, and `w(z) = 2exp(−z²) − w(−z)` below it.
pub fn faddeeva(z: C) -> C {
    if z.im < 0.0 {
        return (-z.sq()).exp() * 2.0 - faddeeva(-z);
    }
    let (l, a) = weideman();
    let lm = C::real(*l) - I * z;
    let zz = (C::real(*l) + I * z) / lm;
    let p = a.iter().rev().fold(C::default(), |acc, &am| acc * zz + C::real(am));
    p * 2.0 / lm.sq() + C::real(1.0 / PI.sqrt()) / lm
}

/// `exp(z²)·erfc(z)` without forming either factor where it would overflow: `w(iz)` for
/// Re z ≥ 0, and `2exp(z²) − w(−iz)` for Re z < 0 (from erfc(z) = 2 − erfc(−z)).
pub fn exp_sq_erfc(z: C) -> C {
    if z.re >= 0.0 {
        faddeeva(I * z)
    } else {
        z.sq().exp() * 2.0 - faddeeva(-(I * z))
    }
}

/// The complementary error function of a complex argument.
pub fn erfc(z: C) -> C {
    if z.re >= 0.0 {
        (-z.sq()).exp() * faddeeva(I * z)
    } else {
        C::real(2.0) - erfc(-z)
    }
}

/// The complementary error function of a real argument.
pub fn erfc_real(x: f64) -> f64 {
    erfc(C::real(x)).re
}

/// p(z) and p'(z) of the polynomial with coefficients `coef` (highest power first).
fn eval(coef: &[C], z: C) -> (C, C) {
    let mut p = C::default();
    let mut dp = C::default();
    for &a in coef {
        dp = dp * z + p;
        p = p * z + a;
    }
    (p, dp)
}

/// Every root of the polynomial `Σ coef[k] z^(n−k)` (highest power first, `coef[0] ≠ 0`), by
/// the Durand–Kerner (Weierstrass) iteration from the usual spiral start, then two Newton
/// steps on the original polynomial. Simple roots converge quadratically; a multiple root
/// only linearly (it is returned less accurate). Empty for degree 0 or a zero leading term.
pub fn poly_roots(coef: &[C]) -> Vec<C> {
    let n = coef.len().saturating_sub(1);
    if n == 0 || coef[0].abs() == 0.0 {
        return Vec::new();
    }
    let monic: Vec<C> = coef.iter().map(|&a| a / coef[0]).collect();
    // Cauchy's bound on |z| sets the scale of the start.
    let radius = 1.0 + monic[1..].iter().map(|a| a.abs()).fold(0.0, f64::max);
    let seed = c(0.4, 0.9);
    let mut z: Vec<C> = (0..n)
        .map(|k| {
            let mut s = C::real(1.0);
            for _ in 0..k {
                s = s * seed;
            }
            s * (radius / 2.0)
        })
        .collect();
    for _ in 0..1000 {
        let mut change = 0.0f64;
        for i in 0..n {
            let (p, _) = eval(&monic, z[i]);
            let mut den = C::real(1.0);
            for j in (0..n).filter(|&j| j != i) {
                den = den * (z[i] - z[j]);
            }
            if den.abs() == 0.0 {
                continue;
            }
            let step = p / den;
            z[i] = z[i] - step;
            change = change.max(step.abs() / z[i].abs().max(1e-300));
        }
        if change < 1e-15 {
            break;
        }
    }
    for r in &mut z {
        for _ in 0..2 {
            let (p, dp) = eval(&monic, *r);
            if dp.abs() > 0.0 {
                *r = *r - p / dp;
            }
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: C, b: C, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs().max(1e-300)
    }

    #[test]
    fn faddeeva_and_erfc_match_reference_values() {
        // w(i) = e·erfc(1); w(1) = e^{-1} + (2i/√π)·Dawson(1); erf(1 + i) (Abramowitz & Stegun 7.1).
        let e_erfc1 = std::f64::consts::E * 0.157_299_207_050_285_13;
        assert!(close(faddeeva(I), C::real(e_erfc1), 1e-12), "{:?}", faddeeva(I));
        let w1 = c((-1f64).exp(), 2.0 / PI.sqrt() * 0.538_079_506_912_768_4);
        assert!(close(faddeeva(C::real(1.0)), w1, 1e-12), "{:?}", faddeeva(C::real(1.0)));
        let erfc_1i = C::real(1.0) - c(1.316_151_281_697_947_6, 0.190_453_469_237_834_7);
        assert!(close(erfc(c(1.0, 1.0)), erfc_1i, 1e-12), "{:?}", erfc(c(1.0, 1.0)));
        // The left half plane, through erfc(−z) = 2 − erfc(z).
        let e = erfc(c(-1.0, -1.0));
        assert!(close(e, c(2.0 - erfc_1i.re, -erfc_1i.im), 1e-12), "{e:?}");
        for (x, v) in [
            (0.0, 1.0),
            (0.5, 0.479_500_122_186_953_5),
            (2.0, 0.004_677_734_981_047_266),
            (-1.0, 1.842_700_792_949_715),
        ] {
            assert!((erfc_real(x) - v).abs() <= 1e-13 * v, "erfc({x}) = {} vs {v}", erfc_real(x));
        }
        // A tail value where erfc itself underflows towards 0: erfc(5) = 1.5374597944280349e-12.
        assert!((erfc_real(5.0) / 1.537_459_794_428_035e-12 - 1.0).abs() < 1e-10, "{}", erfc_real(5.0));
    }

    #[test]
    fn the_scaled_product_is_continuous_across_the_imaginary_axis() {
        for im in [-3.0, -0.5, 0.0, 0.7, 4.0] {
            let a = exp_sq_erfc(c(1e-12, im));
            let b = exp_sq_erfc(c(-1e-12, im));
            assert!(close(a, b, 1e-9), "im {im}: {a:?} vs {b:?}");
            // and equals the product of its factors where neither overflows.
            let z = c(0.3, im);
            assert!(close(exp_sq_erfc(z), z.sq().exp() * erfc(z), 1e-11), "im {im}");
        }
    }

    #[test]
    fn roots_of_known_polynomials() {
        let mut r = poly_roots(&[C::real(1.0), C::default(), C::default(), C::default(), C::real(4.0)]);
        r.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        let want = [c(-1.0, -1.0), c(-1.0, 1.0), c(1.0, -1.0), c(1.0, 1.0)];
        for (a, b) in r.iter().zip(want) {
            assert!(close(*a, b, 1e-13), "{r:?}");
        }
        // (z − 1)(z − 2)(z − 3)(z − 4) = z⁴ − 10z³ + 35z² − 50z + 24.
        let mut r = poly_roots(&[1.0, -10.0, 35.0, -50.0, 24.0].map(C::real));
        r.sort_by(|a, b| a.re.total_cmp(&b.re));
        for (k, z) in r.iter().enumerate() {
            assert!(close(*z, C::real(k as f64 + 1.0), 1e-12) && z.im.abs() < 1e-12, "{r:?}");
        }
        assert!(poly_roots(&[C::default(), C::real(1.0)]).is_empty());
    }
}
