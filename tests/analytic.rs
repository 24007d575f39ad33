//! The analytic drop-spread models against thesis Table 1 and the §5.2 impact case
//! (docs/PHYSICS.md §11).

use sphlab::analytic::*;
use std::f64::consts::PI;

#[test]
fn table1_has_every_row() {
    let t = table1();
    assert_eq!(t.len(), 33);
    assert_eq!((t[0].re, t[0].we, t[0].theta_rad), (106.0, 802.0, 1.693));
    assert_eq!(t[25].model_a, 9.186);
    assert_eq!(t[32].reference, "[56]");
}

#[test]
fn table1_all_model_cells_within_half_percent() {
    let rows = table1_comparison();
    println!("{}", format_table1(&rows));
    for (i, r) in rows.iter().enumerate() {
        for (name, c) in r.cells() {
            assert!(
                c.rel_error.abs() < 0.005,
                "row {} (Re {}) {name}: thesis {} sphlab {}",
                i + 1,
                r.row.re,
                c.thesis,
                c.sphlab
            );
        }
        // Table 1 only exercises the thick-film branch.
        let c = spread_2d_c(r.row.re, r.row.we, r.row.theta_rad).unwrap();
        assert_eq!(c.branch, Branch::ThickFilm);
        assert!((1.0..10.0).contains(&c.h_over_delta), "h/δ {}", c.h_over_delta);
    }
    let (i, name, c) = worst_cell(&rows).unwrap();
    println!(
        "worst cell: row {} {name}: thesis {} sphlab {:.5} rel {:+.4} %",
        i + 1,
        c.thesis,
        c.sphlab,
        100.0 * c.rel_error
    );
}

#[test]
fn impact_case_of_section_5_2() {
    // θ (°), axisym, (a), (b), (c) h>δ, (c) h<δ — docs/PHYSICS.md §11, Re = 440, We = 6.86.
    let table = [
        (50.0, 2.815, 8.843, 11.028, 4.373, 4.295),
        (70.0, 2.397, 6.074, 7.527, 4.026, 3.992),
        (90.0, 2.092, 4.480, 5.384, 3.626, 3.633),
        (100.0, 1.976, 3.953, 4.681, 3.425, 3.449),
        (110.0, 1.880, 3.548, 4.148, 3.235, 3.271),
        (130.0, 1.739, 2.999, 3.440, 2.913, 2.961),
        (145.0, 1.670, 2.750, 3.124, 2.739, 2.788),
        (160.0, 1.627, 2.602, 2.939, 2.626, 2.675),
        (175.0, 1.608, 2.538, 2.859, 2.575, 2.623),
    ];
    for (deg, ax, a, b, thick, thin) in table {
        let s = spread_all(440.0, 6.86, f64::to_radians(deg)).unwrap();
        print!("{}", format_spread(&s));
        let got = [s.axisym, s.model_a, s.model_b, s.model_c_thick, s.model_c_thin];
        for (g, want) in got.into_iter().zip([ax, a, b, thick, thin]) {
            assert!((g - want).abs() <= 0.002, "θ {deg}°: got {g}, want {want}");
        }
        // At Re = 440 both branches sit near h = δ; the solver picks the thick-film one.
        assert_eq!(s.model_c_branch, Branch::ThickFilm);
        assert_eq!(s.model_c, s.model_c_thick);
    }
}

#[test]
fn bad_inputs_are_errors() {
    use AnalyticError::*;
    let t = 1.0;
    for re in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(spread_all(re, 10.0, t), Err(InvalidRe(_))));
        assert!(matches!(spread_axisym(re, 10.0, t), Err(InvalidRe(_))));
    }
    for we in [-1e-9, f64::NAN, f64::INFINITY] {
        assert!(matches!(spread_2d_a(100.0, we, t), Err(InvalidWe(_))));
        assert!(matches!(spread_2d_b(100.0, we, t), Err(InvalidWe(_))));
    }
    for th in [0.0, PI, -0.5, 4.0, f64::NAN, f64::NEG_INFINITY] {
        assert!(matches!(spread_2d_c(100.0, 10.0, th), Err(InvalidTheta(_))));
        assert!(matches!(spread_2d_c_branch(100.0, 10.0, th, Branch::ThinFilm), Err(InvalidTheta(_))));
    }
    let msg = spread_all(-3.0, 1.0, 1.0).unwrap_err().to_string();
    assert!(msg.contains("re"), "{msg}");
    // We = 0 is valid (no viscous work in the 2D models): ξ = π/(1 − cos θ) everywhere.
    let s = spread_all(100.0, 0.0, PI / 2.0).unwrap();
    for v in [s.model_a, s.model_b, s.model_c, s.model_c_thick, s.model_c_thin] {
        assert!((v - PI).abs() < 1e-12, "{v}");
    }
}

#[test]
fn thin_film_branch_is_used_when_h_below_delta() {
    // Large We, small Re: the film is thinner than the boundary layer.
    let (re, we, th) = (10.0, 1000.0, PI / 2.0);
    let c = spread_2d_c(re, we, th).unwrap();
    assert_eq!(c.branch, Branch::ThinFilm);
    assert!(c.h_over_delta < 1.0 && c.xi.is_finite() && c.xi > 0.0);
    assert_eq!(c.xi, spread_2d_c_branch(re, we, th, Branch::ThinFilm).unwrap());
    let thick = spread_2d_c_branch(re, we, th, Branch::ThickFilm).unwrap();
    assert!(h_over_delta(re, thick) < 1.0, "thick-film solution rejected");
}

#[test]
fn branches_agree_at_h_equal_delta() {
    let re: f64 = 100.0;
    let xi_star = PI * (2.0 * re).sqrt() / (4.0 * 2.4); // h/δ = 1
    assert!((h_over_delta(re, xi_star) - 1.0).abs() < 1e-14);
    for we in [0.5, 7.0, 300.0] {
        let thick = viscous_work_2d_c(re, we, xi_star, Branch::ThickFilm);
        let thin = viscous_work_2d_c(re, we, xi_star, Branch::ThinFilm);
        assert!((thick / thin - 1.0).abs() < 1e-12, "{thick} vs {thin}");
    }
    // Choose We so that the balance is solved exactly at h = δ: both branches give ξ*.
    let th = f64::to_radians(30.0);
    let k = 1.0 - th.cos();
    let g = viscous_work_2d_c(re, 1.0, xi_star, Branch::ThinFilm); // W per unit We
    let we = (k * xi_star - PI) / (PI / 8.0 - g);
    assert!(we > 0.0);
    for b in [Branch::ThickFilm, Branch::ThinFilm] {
        let xi = spread_2d_c_branch(re, we, th, b).unwrap();
        assert!((xi / xi_star - 1.0).abs() < 1e-10, "{b}: {xi} vs {xi_star}");
    }
}
