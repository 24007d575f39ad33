//! Tests of the relax-60 case's geometry: the equal-area start caps, the analytic cap at the
//! first row and at the wall, which variants are held to 60°, and how the wall-shear plots tell
//! the variants apart.

use super::*;

#[test]
fn a_start_below_60_is_the_half_discs_area_meeting_the_wall_at_its_angle() {
    use crate::scene::{build::build_layout, overrides::apply_overrides};
    assert!(start_sets(90.0).is_empty());
    let base = crate::scene::builtin::relax_60();
    let liquid = |sets: &[String]| {
        let layout = build_layout(&apply_overrides(&base, sets).unwrap()).unwrap();
        let dx = layout.dx;
        let pts: Vec<[f64; 2]> = (0..layout.n_fluid).filter(|&i| layout.phase[i] == 0).map(|i| layout.pos[i]).collect();
        // The outermost first-row particle + Δx/2, as the series' x_tp.
        let x_row = pts.iter().filter(|p| p[1] < dx).map(|p| p[0]).fold(0.0, f64::max) + 0.5 * dx;
        (pts.len() as f64, x_row, dx)
    };
    let (n90, _, _) = liquid(&[]);
    for theta in [START_BELOW_DEG, 60.0, 120.0] {
        let (n, x_row, dx) = liquid(&start_sets(theta));
        // Same area to the lattice's resolution (825 particles at nx = 65).
        assert!((n / n90 - 1.0).abs() < 0.01, "{theta}°: {n} liquid particles vs {n90}");
        // The cap's width at the first row's height: R sin θ at the wall, less (Δx/2)·cot θ.
        let cap = start_cap(theta);
        let want = cap.x_tp - 0.5 * dx / theta.to_radians().tan();
        assert!((x_row - want).abs() < dx, "{theta}°: x_tp {x_row} vs {want}");
    }
    // 45°: D/D0 = R sin 45° / R0 = 1.659, against the 60° cap's 1.385.
    assert!((start_cap(45.0).x_tp / R0 - 1.659).abs() < 1e-3);
}

#[test]
fn the_cap_at_the_first_row_is_narrower_and_the_wall_estimate_recovers_the_wall_value() {
    let dx = 0.5 / 45.0;
    let (wall, row) = (analytic_spread(), analytic_spread_at(0.5 * dx));
    assert!((wall - 1.385).abs() < 5e-4, "{wall}");
    // The cap narrows by about (Δx/2)·cot 60° / R between the wall and the first row.
    let drop = 0.5 * dx / (R0 * 60f64.to_radians().tan());
    assert!((wall - row - drop).abs() < 0.05 * drop, "{wall} {row} {drop}");
    // A first-row reading of the exact cap at its exact angle, carried to the wall, gives the
    // wall value up to the circle's curvature over Δx/2 (2.4e-4 here, against the 0.013
    // it corrects); a reading without an angle is skipped.
    let rows = vec![
        SRow { t: 1.0, spread_factor: Some(row), theta_circle_fit: Some(60.0), ..Default::default() },
        SRow { t: 2.0, spread_factor: Some(row), theta_circle_fit: None, ..Default::default() },
    ];
    let w = wall_spread(&rows, dx);
    assert_eq!(w.len(), 1);
    assert!((w[0].1 - wall).abs() < 4e-4, "{} vs {wall}", w[0].1);
    // At 90° nothing is added.
    let rows = vec![SRow { t: 0.0, spread_factor: Some(1.0), theta_circle_fit: Some(90.0), ..Default::default() }];
    assert!((wall_spread(&rows, dx)[0].1 - 1.0).abs() < 1e-12);
}

#[test]
fn mode_b_and_the_unbalanced_young_force_are_held_to_60_degrees() {
    let held: Vec<&str> = variants().iter().filter(|v| v.held_to_young()).map(|v| v.id).collect();
    assert_eq!(
        held,
        [
            "b-noslip",
            "b-noslip-tvf",
            "b-freeslip",
            "b-noslip-from45",
            "a-young-noslip",
            "a-young-freeslip",
            "a-young-noslip-from45"
        ]
    );
    // A variant is Mode A with the wall bands by its scene: the overrides set the contact mode
    // and leave the wall tensions; the held Mode A variants are those of the unbalanced force.
    let scene =
        |v: &Variant| crate::scene::overrides::apply_overrides(&crate::scene::builtin::relax_60(), &v.sets).unwrap();
    for v in variants().iter().filter(|v| !v.held_to_young()) {
        assert_eq!(scene(v).contact.mode, crate::scene::ContactMode::A, "{}", v.id);
        assert_eq!(scene(v).contact.wall_tension, crate::scene::WallTension::Bands, "{}", v.id);
    }
    for v in variants().iter().filter(|v| v.held_to_young() && v.id.starts_with("a-")) {
        assert_eq!(scene(v).contact.wall_tension, crate::scene::WallTension::Unbalanced, "{}", v.id);
    }
}

#[test]
fn each_variant_has_its_own_look_in_the_wall_shear_plots_and_a_start_below_shares_its_siblings_colour() {
    let vs = variants();
    let looks: Vec<_> = (0..vs.len()).map(|k| case::shear_look(&vs, k)).collect();
    for (k, a) in looks.iter().enumerate() {
        for b in &looks[k + 1..] {
            assert_ne!(a, b, "{} shares its look", vs[k].id);
        }
    }
    for (k, v) in vs.iter().enumerate() {
        if let Some(sibling) = v.from_90 {
            let s = vs.iter().position(|w| w.id == sibling).expect("the sibling is a variant");
            assert_eq!(looks[k].0, looks[s].0, "{} and {sibling}", v.id);
        }
    }
    // One colour per from-90° run: the palette's ten hues are not reused.
    assert!(looks.iter().all(|l| l.0 < 10), "{looks:?}");
}
