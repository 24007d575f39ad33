//! A standing wave on a horizontal interface (docs/PHYSICS.md §9(f)): the initial lattice is
//! displaced by the potential-flow displacement of a linear wave between two impermeable
//! planes (the domain's bottom and top), so that the interface `y = y0` (a lattice line,
//! painted by the shapes as usual) starts as `y0 + a cos(k(x − x0))` with the fluid at rest,
//! the planes stay where they are and each fluid keeps its area.

use serde::{Deserialize, Serialize};

/// The initial interface wave of a scene (`[interface_wave]`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InterfaceWave {
    /// The undisturbed interface height (a lattice line `y[0] + jΔx`).
    pub y0: f64,
    /// Initial amplitude a0 (k|a0|·coth(kH) ≤ [`MAX_KA`], H the shallower layer's depth).
    pub amplitude: f64,
    /// Wavelength λ = 2π/k; the crest is at the domain's left edge `x0 = domain.x[0]`.
    pub wavelength: f64,
}

/// Largest k|a0|·coth(kH): the displacement map's Jacobian is
/// `1 − (ka0)²(ĉ² cos²kX + ŝ² sin²kX)`, `ĉ = cosh(k(H − |d|))/sinh(kH) ≤ coth(kH)`,
/// `ŝ = sinh(k(H − |d|))/sinh(kH) ≤ ĉ`, so it is one-to-one below 1; 0.5 keeps every
/// particle's area within 25 % of the lattice's.
pub const MAX_KA: f64 = 0.5;

impl InterfaceWave {
    /// Wavenumber k = 2π/λ.
    pub fn k(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.wavelength
    }

    /// The lattice point `p` displaced by
    /// `ξ = a (sign(d) cosh(k(H − |d|)) sin kX, sinh(k(H − |d|)) cos kX)/sinh(kH)`, `d = y − y0`,
    /// `X = x − x0`, `H` the depth of p's side (`y0 − y_bottom` below, `y_top − y0` above): the
    /// gradient of the harmonic potential `∓(a/k) cosh(k(H − |d|)) cos kX / sinh(kH)` on each
    /// side, so it is divergence-free in each fluid, continuous in y across the interface (which
    /// moves by exactly `a cos kX`) and zero across the planes. Deep layers give the deep-water
    /// `a e^{−k|d|}`.
    pub fn displace(&self, p: [f64; 2], x0: f64, y_bottom: f64, y_top: f64) -> [f64; 2] {
        let k = self.k();
        let d = p[1] - self.y0;
        let depth = if d < 0.0 { self.y0 - y_bottom } else { y_top - self.y0 };
        // cosh(k(H − |d|))/sinh(kH) and sinh(…)/sinh(kH) without overflow for deep layers.
        let (near, far, norm) =
            ((-k * d.abs()).exp(), (-k * (2.0 * depth - d.abs())).exp(), 1.0 - (-2.0 * k * depth).exp());
        let (ch, sh) = ((near + far) / norm, (near - far) / norm);
        let kx = k * (p[0] - x0);
        [p[0] + d.signum() * self.amplitude * ch * kx.sin(), p[1] + self.amplitude * sh * kx.cos()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_displacement_is_divergence_free_and_moves_the_interface_by_the_amplitude() {
        let w = InterfaceWave { y0: 0.25, amplitude: 0.02, wavelength: 0.7 };
        let (bottom, top) = (-0.1, 0.6);
        let h = 1e-6;
        let disp = |p: [f64; 2]| w.displace(p, 0.0, bottom, top);
        for p in [[0.1, 0.4], [0.33, 0.1], [0.6, 0.26], [0.05, -0.05]] {
            let (xp, xm) = (disp([p[0] + h, p[1]]), disp([p[0] - h, p[1]]));
            let (yp, ym) = (disp([p[0], p[1] + h]), disp([p[0], p[1] - h]));
            let div = (xp[0] - xm[0] - 2.0 * h) / (2.0 * h) + (yp[1] - ym[1] - 2.0 * h) / (2.0 * h);
            assert!(div.abs() < 1e-7, "∇·ξ at {p:?} = {div}");
        }
        for x in [0.0, 0.1, 0.35, 0.5] {
            let (above, below) = (disp([x, 0.25 + 1e-12]), disp([x, 0.25 - 1e-12]));
            let want = 0.25 + 0.02 * (w.k() * x).cos();
            assert!((above[1] - want).abs() < 1e-10 && (below[1] - want).abs() < 1e-10, "x {x}: {above:?} {below:?}");
            // The planes do not move.
            assert!((disp([x, bottom])[1] - bottom).abs() < 1e-15 && (disp([x, top])[1] - top).abs() < 1e-15);
        }
        // Deep layers: the deep-water field a e^{−k|d|}.
        let deep = w.displace([0.0, 0.25 + 0.3], 0.0, -1e3, 1e3);
        assert!((deep[1] - 0.55 - 0.02 * (-w.k() * 0.3).exp()).abs() < 1e-15, "{deep:?}");
    }
}
