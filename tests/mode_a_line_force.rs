//! Mode A's contact-line force (docs/PHYSICS.md §8.2.1): at relax-60's start (σ_LS = 0.5,
//! σ_GS = 1) the accelerations with and without `contact.line_force` differ by the line force
//! alone, in x, within the kernel's reach of the contact point, and its forces sum to
//! `(1 − s_w)(σ_GS − σ_LS)` outwards; with σ_LS = σ_GS there is none.

mod common;

use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::model::WALL_BAND_SHARE;
use sphlab::neighbours::SearchKind;
use sphlab::scene::build::build_layout;
use sphlab::scene::{builtin, ContactMode, Scene};

fn scene(line_force: bool, sigma_ls: f64) -> Scene {
    let mut sc = builtin::builtin("relax-60").unwrap();
    sc.domain.nx = 21;
    sc.contact.mode = ContactMode::A;
    sc.contact.sigma_ls = sigma_ls;
    sc.contact.line_force = line_force;
    sc.validate().unwrap();
    sc
}

/// (contact points' orientations, Σ m_i Δa_i, largest |Δa| beyond the support of the points).
fn difference(sigma_ls: f64) -> (Vec<f64>, [f64; 2], f64) {
    let run = |on: bool| {
        let sc = scene(on, sigma_ls);
        let layout = build_layout(&sc).unwrap();
        let mut s = CpuSolver::<f64>::new(&sc, &layout, Exec::Serial, SearchKind::Cells);
        s.evaluate().unwrap();
        s
    };
    let (on, off) = (run(true), run(false));
    assert!(off.f.contacts.is_empty(), "the bands alone need no contact points");
    let (sum, beyond) = common::line_force_difference(&on, &off);
    (on.f.contacts.iter().map(|c| c.s).collect(), sum, beyond)
}

#[test]
fn the_line_force_carries_the_missing_share_of_the_wall_traction() {
    let (s, sum, beyond) = difference(0.5);
    assert_eq!(s, vec![1.0], "relax-60's drop has one contact point, liquid on its −x side");
    let want = (1.0 - WALL_BAND_SHARE) * (1.0 - 0.5);
    assert!((sum[0] - want).abs() < 1e-12, "Σ m Δa_x = {}, want {want}", sum[0]);
    assert_eq!(sum[1], 0.0, "the line force has a y part");
    assert_eq!(beyond, 0.0, "the line force reached particles beyond the kernel's support");
}

#[test]
fn equal_wall_tensions_have_no_line_force() {
    let (s, sum, _) = difference(1.0);
    assert!(s.is_empty(), "σ_LS = σ_GS: the contact line is not even searched for: {s:?}");
    assert_eq!(sum, [0.0, 0.0]);
}
