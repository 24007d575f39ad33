//! What a viscous pair form takes out of a standing capillary wave on the rest lattice
//! (docs/PHYSICS.md §4.1): the pair power of T70 or of the projected form under the potential
//! flow φ = cos kx e^{ky} below a free surface y = 0, over the continuum's 2η∫e:e = 2ηk³λ. It is
//! what the form would give the wave's damping rate, as a share of the free-surface value, if
//! the flow stayed potential: 1/2 for T70 and 1 for the projected form as Δx → 0, less a surface
//! loss of first order in Δx (the pairs the surface cuts off). Pure arithmetic on the pair
//! functions the solver uses.

use crate::physics::kernel::{kernel_dwdr, KernelParams};
use crate::physics::pair::{viscous_acc_ij, viscous_fac_ij, viscous_projected_acc_ij};
use crate::real::V2;
use crate::scene::ViscousForm;

/// The share of 2η∫e:e that `form` takes out of the wave λ = `nx`·Δx on a square lattice
/// (x periodic, depth λ/2, Δx = 1), kernel `kp` in lattice units.
pub fn potential_wave_share(kp: &KernelParams<f64>, form: ViscousForm, nx: u32) -> f64 {
    let (nx, ny) = (nx as i64, nx as i64 / 2);
    let k = 2.0 * std::f64::consts::PI / nx as f64;
    let v = |x: V2<f64>| V2::new(-k * (k * x.x).sin() * (k * x.y).exp(), k * (k * x.x).cos() * (k * x.y).exp());
    let at = |a: i64, b: i64| V2::new(a as f64 + 0.5, -(b as f64) - 0.5);
    let reach = kp.support.ceil() as i64;
    let mut power = 0.0;
    for a in 0..nx {
        for b in 0..ny {
            let (xi, vi) = (at(a, b), v(at(a, b)));
            let mut sum = V2::zero();
            // Columns beyond 0..nx are the periodic images: the field there is their velocity.
            for c in a - reach..=a + reach {
                for d in (b - reach).max(0)..(b + reach + 1).min(ny) {
                    let xj = at(c, d);
                    sum += unit_pair_term(kp, form, xi - xj, vi - v(xj));
                }
            }
            power -= vi.dot(sum);
        }
    }
    power / (2.0 * k.powi(3) * nx as f64)
}

/// One pair's viscous term of `form` with η = 1 and 1/σ² = 1 on both sides (Δx = 1): zero for
/// the self pair and beyond the support.
pub fn unit_pair_term(kp: &KernelParams<f64>, form: ViscousForm, x_ij: V2<f64>, v_ij: V2<f64>) -> V2<f64> {
    let r2 = x_ij.norm2();
    let r = r2.sqrt();
    if r2 == 0.0 || r >= kp.support {
        return V2::zero();
    }
    let fac = viscous_fac_ij(kernel_dwdr(kp, r), r, kp.h);
    match form {
        ViscousForm::Laplacian => viscous_acc_ij(1.0, 1.0, 1.0, fac, v_ij),
        ViscousForm::Projected => viscous_projected_acc_ij(1.0, 1.0, 1.0, fac, v_ij, x_ij, r2),
    }
}
