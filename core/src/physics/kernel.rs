//! Smoothing kernels in 2D (docs/PHYSICS.md §1, thesis T40–T43). CPU twin of `shaders/kernel.wgsl`.
//!
//! `W(r,h) = α·f(q)` and `∂W/∂r = (α/h)·f'(q)` with `q = r/h` and `α = α_2D/h²`. Constants are
//! computed in `f64` and stored in the working precision ([`KernelParams`]). The kernel is
//! selected by an integer id so that the GPU reads it from the uniform buffer.

use crate::real::Real;
use serde::{Deserialize, Serialize};

/// The kernels sphlab offers (docs/PHYSICS.md §1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum KernelKind {
    /// Monaghan cubic spline (T42), support 2h.
    CubicSpline,
    /// Morris quintic spline (T43), support 3h (the default, h = Δx).
    Quintic,
    /// Johnson quadratic (T41), support 2h.
    Johnson,
    /// Truncated Gaussian (T40), support 3h.
    Gaussian,
    /// Wendland C2 (not in the thesis), support 2h; use h ≥ 1.3Δx.
    WendlandC2,
}

impl KernelKind {
    /// Every kernel, in id order.
    pub const ALL: [KernelKind; 5] = [
        KernelKind::CubicSpline,
        KernelKind::Quintic,
        KernelKind::Johnson,
        KernelKind::Gaussian,
        KernelKind::WendlandC2,
    ];
    /// Integer id shared with WGSL (`KERNEL_*` constants in `shaders/kernel.wgsl`).
    pub fn id(self) -> u32 {
        self as u32
    }
    /// The kebab-case name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            KernelKind::CubicSpline => "cubic-spline",
            KernelKind::Quintic => "quintic",
            KernelKind::Johnson => "johnson",
            KernelKind::Gaussian => "gaussian",
            KernelKind::WendlandC2 => "wendland-c2",
        }
    }
    /// Support radius in units of h (κ).
    pub fn support_factor(self) -> f64 {
        match self {
            KernelKind::CubicSpline | KernelKind::Johnson | KernelKind::WendlandC2 => 2.0,
            KernelKind::Quintic | KernelKind::Gaussian => 3.0,
        }
    }
    /// 2D normalisation α_2D (multiply by 1/h²).
    pub fn alpha_2d(self) -> f64 {
        use std::f64::consts::PI;
        match self {
            KernelKind::CubicSpline => 10.0 / (7.0 * PI),
            KernelKind::Quintic => 7.0 / (478.0 * PI),
            KernelKind::Johnson => 2.0 / PI,
            KernelKind::Gaussian => 1.0 / PI,
            KernelKind::WendlandC2 => 7.0 / (4.0 * PI),
        }
    }
}

/// Kernel constants for one smoothing length, in the working precision.
#[derive(Clone, Copy, Debug)]
pub struct KernelParams<T> {
    /// Which kernel.
    pub kind: KernelKind,
    /// Smoothing length h.
    pub h: T,
    /// 1/h.
    pub inv_h: T,
    /// α_2D / h².
    pub alpha: T,
    /// Support radius κh.
    pub support: T,
}

impl<T: Real> KernelParams<T> {
    /// Constants for `kind` at smoothing length `h` (computed in f64).
    pub fn new(kind: KernelKind, h: f64) -> Self {
        Self {
            kind,
            h: T::c(h),
            inv_h: T::c(1.0 / h),
            alpha: T::c(kind.alpha_2d() / (h * h)),
            support: T::c(kind.support_factor() * h),
        }
    }
}

/// Dimensionless kernel shape f(q) (zero outside the support).
#[inline(always)]
pub fn kernel_f<T: Real>(kind: KernelKind, q: T) -> T {
    let c = T::c;
    match kind {
        KernelKind::CubicSpline => {
            if q < c(1.0) {
                c(1.0) - c(1.5) * q * q + c(0.75) * q * q * q
            } else if q < c(2.0) {
                let a = c(2.0) - q;
                c(0.25) * a * a * a
            } else {
                c(0.0)
            }
        }
        KernelKind::Quintic => {
            let p5 = |a: T| {
                let a2 = a * a;
                a2 * a2 * a
            };
            if q < c(1.0) {
                p5(c(3.0) - q) - c(6.0) * p5(c(2.0) - q) + c(15.0) * p5(c(1.0) - q)
            } else if q < c(2.0) {
                p5(c(3.0) - q) - c(6.0) * p5(c(2.0) - q)
            } else if q < c(3.0) {
                p5(c(3.0) - q)
            } else {
                c(0.0)
            }
        }
        KernelKind::Johnson => {
            if q < c(2.0) {
                let a = c(2.0) - q;
                c(0.1875) * a * a
            } else {
                c(0.0)
            }
        }
        KernelKind::Gaussian => {
            if q < c(3.0) {
                (-q * q).exp()
            } else {
                c(0.0)
            }
        }
        KernelKind::WendlandC2 => {
            if q < c(2.0) {
                let a = c(1.0) - c(0.5) * q;
                let a2 = a * a;
                a2 * a2 * (c(2.0) * q + c(1.0))
            } else {
                c(0.0)
            }
        }
    }
}

/// Derivative of the shape, f'(q) (≤ 0; zero outside the support).
#[inline(always)]
pub fn kernel_df<T: Real>(kind: KernelKind, q: T) -> T {
    let c = T::c;
    match kind {
        KernelKind::CubicSpline => {
            if q < c(1.0) {
                c(-3.0) * q + c(2.25) * q * q
            } else if q < c(2.0) {
                let a = c(2.0) - q;
                c(-0.75) * a * a
            } else {
                c(0.0)
            }
        }
        KernelKind::Quintic => {
            let p4 = |a: T| {
                let a2 = a * a;
                a2 * a2
            };
            if q < c(1.0) {
                c(-5.0) * p4(c(3.0) - q) + c(30.0) * p4(c(2.0) - q) - c(75.0) * p4(c(1.0) - q)
            } else if q < c(2.0) {
                c(-5.0) * p4(c(3.0) - q) + c(30.0) * p4(c(2.0) - q)
            } else if q < c(3.0) {
                c(-5.0) * p4(c(3.0) - q)
            } else {
                c(0.0)
            }
        }
        KernelKind::Johnson => {
            if q < c(2.0) {
                c(-0.375) * (c(2.0) - q)
            } else {
                c(0.0)
            }
        }
        KernelKind::Gaussian => {
            if q < c(3.0) {
                c(-2.0) * q * (-q * q).exp()
            } else {
                c(0.0)
            }
        }
        KernelKind::WendlandC2 => {
            if q < c(2.0) {
                let a = c(1.0) - c(0.5) * q;
                c(-5.0) * q * a * a * a
            } else {
                c(0.0)
            }
        }
    }
}

/// W(r, h).
#[inline(always)]
pub fn kernel_w<T: Real>(kp: &KernelParams<T>, r: T) -> T {
    kp.alpha * kernel_f(kp.kind, r * kp.inv_h)
}

/// ∂W/∂r (r, h) = F'(r), ≤ 0.
#[inline(always)]
pub fn kernel_dwdr<T: Real>(kp: &KernelParams<T>, r: T) -> T {
    kp.alpha * kp.inv_h * kernel_df(kp.kind, r * kp.inv_h)
}

/// Lattice sum `Σ_j W(|r_j|)` over an infinite square lattice of spacing `dx` centred on a
/// lattice point (self included), computed in f64. Used to normalise particle masses (§2).
pub fn lattice_sum(kind: KernelKind, h: f64, dx: f64) -> f64 {
    let kp = KernelParams::<f64>::new(kind, h);
    let n = (kp.support / dx).ceil() as i64 + 1;
    let mut s = 0.0;
    for a in -n..=n {
        for b in -n..=n {
            let r = ((a * a + b * b) as f64).sqrt() * dx;
            s += kernel_w(&kp, r);
        }
    }
    s
}
