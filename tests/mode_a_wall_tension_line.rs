//! Mode A with the wall's tensions at the contact line (`contact.wall_tension = "line"`,
//! docs/PHYSICS.md §8.2.3), at relax-60's start (nx = 21, σ_LS = 0.5, σ_GS = 1, the liquid–gas
//! interface free at the wall): no fluid–wall pair carries a surface force, the fluid's forces
//! differ from a wall with no tension at all (σ_LS = σ_GS) by σ_GS − σ_LS outwards within the
//! kernel's reach of the contact point and nowhere else, fluid far from the walls feels what it
//! feels beside the wall bands, and the combinations that mean nothing are refused by name.
//! Spread over the liquid–gas interface where the wall's kernel reach cuts it (§8.2.4), the same
//! force acts only on fluid particles of that band near the wall, and still sums to σ_GS − σ_LS.

use sphlab::cpu::momentum::PairTerm;
mod common;

use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::forces::balance::{split_forces, Partner, TERMS};
use sphlab::neighbours::SearchKind;
use sphlab::scene::build::build_layout;
use sphlab::scene::{builtin, ContactMode, LineForceSpread, LiquidGasAtWall, Scene, WallTension};

fn scene(tension: WallTension, sigma_ls: f64) -> Scene {
    spread_scene(tension, sigma_ls, LineForceSpread::Kernel)
}

fn spread_scene(tension: WallTension, sigma_ls: f64, spread: LineForceSpread) -> Scene {
    let mut sc = builtin::builtin("relax-60").unwrap();
    sc.domain.nx = 21;
    sc.contact.mode = ContactMode::A;
    sc.contact.sigma_ls = sigma_ls;
    sc.contact.liquid_gas_at_wall = LiquidGasAtWall::Free;
    sc.contact.wall_tension = tension;
    sc.contact.line_force_spread = spread;
    sc.validate().unwrap();
    sc
}

fn evaluated(sc: &Scene) -> CpuSolver<f64> {
    let layout = build_layout(sc).unwrap();
    let mut s = CpuSolver::<f64>::new(sc, &layout, Exec::Serial, SearchKind::Cells);
    s.evaluate().unwrap();
    s
}

#[test]
fn no_fluid_wall_pair_carries_a_surface_force() {
    let s = evaluated(&scene(WallTension::Line, 0.5));
    let t = TERMS.iter().position(|&x| x == PairTerm::Surface).unwrap();
    let worst = split_forces(&s)
        .iter()
        .map(|sp| sp[t][Partner::Wall as usize])
        .fold(0.0f64, |w, f| w.max(f[0].abs()).max(f[1].abs()));
    assert_eq!(worst, 0.0, "a fluid–wall pair carries a surface force of {worst:e}");
    // Beside the bands, the same pairs do carry one (what the option removes).
    let b = evaluated(&scene(WallTension::Bands, 0.5));
    let with_bands = split_forces(&b).iter().map(|sp| sp[t][Partner::Wall as usize][0].abs()).sum::<f64>();
    assert!(with_bands > 1e-3, "the wall bands' fluid–wall pairs carry {with_bands:e}");
}

#[test]
fn the_whole_wall_pull_acts_at_the_contact_point_and_nowhere_else() {
    let (on, neutral) = (evaluated(&scene(WallTension::Line, 0.5)), evaluated(&scene(WallTension::Line, 1.0)));
    assert_eq!(on.f.contacts.iter().map(|c| c.s).collect::<Vec<_>>(), vec![1.0], "one contact point, liquid on −x");
    assert!(neutral.f.contacts.is_empty(), "σ_LS = σ_GS: no line force, no contact point searched for");
    let (sum, beyond) = common::line_force_difference(&on, &neutral);
    assert!((sum[0] - 0.5).abs() < 1e-12, "Σ m Δa_x = {}, want σ_GS − σ_LS = 0.5", sum[0]);
    assert_eq!(sum[1], 0.0, "the line force has a y part");
    assert_eq!(beyond, 0.0, "the wall tensions reached particles beyond the contact point's support");
}

#[test]
fn fluid_beyond_two_supports_of_every_wall_feels_the_same_as_beside_the_bands() {
    let (line, bands) = (evaluated(&scene(WallTension::Line, 0.5)), evaluated(&scene(WallTension::Bands, 0.5)));
    let reach = 2.0 * line.model.support();
    let walls = &line.pos[line.n_fluid..];
    let (mut near, mut far, mut scale) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..line.n_fluid {
        let d = (line.f.acc[i] - bands.f.acc[i]).norm();
        scale = scale.max(bands.f.acc[i].norm());
        if walls.iter().all(|w| (line.pos[i] - *w).norm() >= reach) {
            far = far.max(d);
        } else {
            near = near.max(d);
        }
    }
    assert!(far <= 1e-12 * scale, "beyond two supports of every wall the forms differ by {far:e} (scale {scale:e})");
    assert!(near > 1e-3 * scale, "next to the wall the forms do not differ ({near:e}): the bands were not removed");
}

#[test]
fn meaningless_combinations_are_refused_by_name() {
    let mut sc = scene(WallTension::Line, 0.5);
    sc.contact.line_force = true;
    let e = sc.validate().unwrap_err().to_string();
    assert!(e.contains("contact.line_force"), "{e}");
    let mut sc = builtin::builtin("relax-60").unwrap();
    sc.contact.mode = ContactMode::B;
    sc.contact.wall_tension = WallTension::Line;
    let e = sc.validate().unwrap_err().to_string();
    assert!(e.contains("contact.wall_tension"), "{e}");
}

#[test]
fn spread_over_the_interface_the_pull_acts_on_the_band_at_the_wall_alone() {
    let on = evaluated(&spread_scene(WallTension::Line, 0.5, LineForceSpread::Interface));
    let neutral = evaluated(&spread_scene(WallTension::Line, 1.0, LineForceSpread::Interface));
    let (support, y_w) = (on.model.support(), on.model.y_wall);
    let cp = on.f.contacts[0].r;
    let (mut sum, mut pushed, mut stray) = (0.0, 0, 0);
    for i in 0..on.n_fluid {
        let d = on.f.acc[i].x - neutral.f.acc[i].x;
        assert_eq!(on.f.acc[i].y, neutral.f.acc[i].y, "particle {i}: a y part");
        sum += on.f.mass[i] * d;
        if d != 0.0 {
            pushed += 1;
            let near_wall = on.pos[i].y - y_w < support;
            let near_point = (on.pos[i] - cp).norm() < 2.0 * support;
            let on_band = on.f.grad[i].iter().any(|g| g.norm() > 0.0);
            if !(near_wall && near_point && on_band) {
                stray += 1;
            }
        }
    }
    assert!((sum - 0.5).abs() < 1e-12, "Σ m Δa_x = {sum}, want σ_GS − σ_LS = 0.5");
    assert!(pushed >= 4, "the pull acts on {pushed} particles");
    assert_eq!(stray, 0, "the pull reached particles off the band at the wall near the contact point");
}
