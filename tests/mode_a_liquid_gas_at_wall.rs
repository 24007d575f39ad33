//! Mode A's liquid–gas interface at the wall (docs/PHYSICS.md §8.2.2): the fluid–wall pairs of
//! `"shared"` carry the fluid's liquid–gas tensor and so take back part of that interface's
//! pull at the line, σ_LG (−cos θ, sin θ); `"free"` leaves exactly that part out and nothing
//! else. Measured at relax-60's start (nx = 45, σ_LS = 0.5, σ_GS = 1), a cap meeting the wall at
//! 90° and at 135°: the forces of the two settings differ only on fluid particles within the
//! kernel's reach of the wall, and along the pull they differ by the same part of σ_LG at both
//! angles (0.17: less than the half a tensor uniform up to the wall would give, since the
//! liquid–gas colour gradient weakens where the kernel reaches into the uncoloured wall).

use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::neighbours::SearchKind;
use sphlab::scene::build::build_layout;
use sphlab::scene::overrides::apply_overrides;
use sphlab::scene::{builtin, ContactMode, LiquidGasAtWall, Scene};

fn scene(at_wall: LiquidGasAtWall, theta0: f64) -> Scene {
    let mut sc = builtin::builtin("relax-60").unwrap();
    sc.domain.nx = 45;
    sc.contact.mode = ContactMode::A;
    sc.contact.sigma_ls = 0.5;
    sc.contact.liquid_gas_at_wall = at_wall;
    let sc = apply_overrides(&sc, &sphlab::validate::relax_start_sets(theta0)).unwrap();
    sc.validate().unwrap();
    sc
}

/// (Σ m_i (a_shared − a_free), largest |Δa| farther than the support from the wall).
fn difference(theta0: f64) -> ([f64; 2], f64) {
    let run = |at_wall| {
        let sc = scene(at_wall, theta0);
        let layout = build_layout(&sc).unwrap();
        let mut s = CpuSolver::<f64>::new(&sc, &layout, Exec::Serial, SearchKind::Cells);
        s.evaluate().unwrap();
        s
    };
    let (shared, free) = (run(LiquidGasAtWall::Shared), run(LiquidGasAtWall::Free));
    let (support, y_w) = (shared.model.support(), shared.model.y_wall);
    let (mut sum, mut beyond) = ([0.0; 2], 0.0f64);
    for i in 0..shared.n_fluid {
        let d = [shared.f.acc[i].x - free.f.acc[i].x, shared.f.acc[i].y - free.f.acc[i].y];
        if shared.pos[i].y - y_w >= support {
            beyond = beyond.max(d[0].abs().max(d[1].abs()));
        }
        sum[0] += shared.f.mass[i] * d[0];
        sum[1] += shared.f.mass[i] * d[1];
    }
    (sum, beyond)
}

/// The part of the liquid–gas pull σ_LG t̂, t̂ = (−cos θ0, sin θ0), that the shared wall pairs
/// take back: −(shared − free)·t̂ (σ_LG = 1).
fn taken_back(theta0: f64) -> f64 {
    let (sum, beyond) = difference(theta0);
    let t = theta0.to_radians();
    let tang = [-t.cos(), t.sin()];
    let f = -(sum[0] * tang[0] + sum[1] * tang[1]);
    eprintln!("θ0 = {theta0}°: shared − free = ({:.4}, {:.4}); taken back along t̂: {f:.4}", sum[0], sum[1]);
    assert_eq!(beyond, 0.0, "θ0 = {theta0}°: the settings differ beyond the kernel's reach of the wall");
    f
}

#[test]
fn shared_walls_take_back_a_fixed_part_of_the_liquid_gas_pull() {
    let (f90, f135) = (taken_back(90.0), taken_back(135.0));
    for (theta0, f) in [(90.0, f90), (135.0, f135)] {
        assert!(f > 0.1 && f < 0.3, "θ0 = {theta0}°: the wall pairs take back {f:.4} of the pull, not 0.1–0.3");
    }
    assert!((f90 - f135).abs() < 0.03, "the part taken back depends on the angle: {f90:.4} at 90°, {f135:.4} at 135°");
}
