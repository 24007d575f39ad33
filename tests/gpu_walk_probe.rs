//! The neighbour-walk probe (`gpu::walk_probe`): its lattice and cells find exactly the
//! neighbours a brute-force search finds, every form on the adapter finds what the host's walk
//! finds (a wrong slot is an error, not a time), and each (form, access) gets a positive time.

mod common;

use common::{gpu_or_skip, serial};
use sphlab::gpu::walk_probe::{check_output, measure_walk, Lattice, CELL_DX, FORMS};

#[test]
fn the_cells_hold_every_neighbour_a_brute_force_search_finds() {
    let lat = Lattice::new(40);
    let n = lat.pos.len();
    assert_eq!(*lat.cell_start.last().unwrap() as usize, n);
    assert!(lat.cell_start.windows(2).all(|w| w[0] <= w[1]));
    let mut sorted_order = lat.order.clone();
    sorted_order.sort_unstable();
    assert!(sorted_order.iter().enumerate().all(|(k, &o)| k == o as usize), "order is a permutation");
    for s in (0..n).step_by(37) {
        assert_eq!(lat.pos_perm[lat.order[s] as usize], lat.pos[s]);
        let xi = lat.pos[s];
        let brute =
            lat.pos.iter().filter(|xj| (xi[0] - xj[0]).powi(2) + (xi[1] - xj[1]).powi(2) < CELL_DX * CELL_DX).count();
        let (nb, w, cand, wq) = lat.expected(s);
        assert_eq!(nb as usize, brute, "slot {s}");
        assert!(cand >= nb && w >= 1.0, "slot {s}: {cand} candidates, weight {w}");
        // Σ W over the support of a unit lattice is about 1 (the kernel's normalisation).
        assert!((wq - 1.0).abs() < 0.05 || nb < 30, "slot {s}: Σ W = {wq} over {nb} neighbours");
    }
    // An interior particle's 3×3 cells of 3.6 Δx hold between 9·3² and 9·4² lattice points.
    let mid = (0..n).find(|&s| lat.pos[s] == [20.5, 20.5]).unwrap();
    let (_, _, cand, wq) = lat.expected(mid);
    assert!((wq - 1.0).abs() < 1e-3, "an interior particle's quintic sum Σ W = {wq}");
    assert!((81..=144).contains(&cand), "{cand} candidates in 3×3 cells of 3.6 Δx");
}

#[test]
fn a_walk_that_misses_a_neighbour_is_an_error() {
    let lat = Lattice::new(12);
    let expected: Vec<_> = (0..lat.pos.len()).map(|s| lat.expected(s)).collect();
    let mut found: Vec<f32> = expected.iter().map(|e| e.0 as f32).collect();
    check_output("ranges", "read", &found, &expected, 0).unwrap();
    found[17] -= 1.0;
    let e = check_output("ranges", "read", &found, &expected, 0).unwrap_err().to_string();
    assert!(e.contains("slot 17"), "{e}");
    let sums: Vec<f32> = expected.iter().map(|e| e.1 as f32).collect();
    check_output("pair-sum", "read", &sums, &expected, 3).unwrap();
    assert!(check_output("pair-sum", "read", &vec![0.0; sums.len()], &expected, 3).is_err());
    let mut quintic: Vec<f32> = expected.iter().map(|e| e.3 as f32).collect();
    check_output("quintic", "read", &quintic, &expected, 4).unwrap();
    assert!(check_output("quintic", "read", &sums, &expected, 4).is_err(), "the Wendland sums are not the quintic's");
    quintic[5] *= 1.001;
    assert!(check_output("quintic", "read", &quintic, &expected, 4).unwrap_err().to_string().contains("slot 5"));
}

#[test]
fn every_form_and_access_finds_the_hosts_neighbours_and_is_timed() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    let Some(rows) = measure_walk(&ctx, 24).unwrap() else {
        assert!(!ctx.has(wgpu::Features::TIMESTAMP_QUERY), "timestamps give times");
        return;
    };
    assert_eq!(rows.len(), 2 * FORMS.len());
    for r in &rows {
        println!(
            "{} {:>10}: {:.1} ns per particle, {:.0} ps per candidate",
            r.form, r.access, r.ns_per_particle, r.ps_per_candidate
        );
    }
    for r in &rows {
        assert_eq!(r.n, 24 * 24);
        assert!(r.best_ns > 0.0 && r.ns_per_particle > 0.0 && r.ps_per_candidate > 0.0, "{r:?}");
        assert!(r.candidates > r.neighbours && r.neighbours > 20.0, "{r:?}");
    }
    let forms: Vec<(&str, &str)> = rows.iter().map(|r| (r.form.as_str(), r.access.as_str())).collect();
    assert!(forms.contains(&("params-by-value", "read_write")) && forms.contains(&("indirect", "read")));
    assert!(forms.contains(&("quintic", "read_write")));
}
