//! The capillary wave's band rows: built from each band end's runs under their base's id.

use super::*;

fn wave() -> CapillaryWave {
    CapillaryWave { quick: false, rms: Vec::new(), damping: Vec::new(), periods: Vec::new(), kernel: None }
}

#[test]
fn the_band_rebuilds_the_forms_damping_row_from_each_ends_runs_and_only_there() {
    let mut w = wave();
    // (id, damping rate, Prosperetti's by the same fit)
    w.damping = vec![
        ("ratio1".into(), 1.0, 1.0),
        ("ratio1-projected".into(), 1.02, 1.0),
        ("ratio1-pb-half".into(), 0.5, 1.0),
        ("ratio1-projected-alpha1".into(), 0.9, 1.0),
        ("ratio1-pb-double".into(), 1.0, 1.0),
    ];
    let rows = w.band_derived_rows();
    let q = "damping rate γ / Prosperetti's, density ratio 1: T70 / projected viscous form";
    let half = rows.iter().find(|r| r.quantity == format!("at p_b × 0.5 (α = 1): {q}")).expect("α × 0.5's row");
    assert_eq!(half.sphlab, "0.500 / 0.900");
    assert!(half.verdict.starts_with("info") && half.verdict.contains("criterion not met"), "{}", half.verdict);
    // α × 2 has no projected run: no row, so no band.
    assert!(!rows.iter().any(|r| r.quantity.starts_with("at p_b × 2 (α = 4): ")), "{rows:?}");
    // The rule's own rows are not band rows.
    assert!(w.derived_rows(&w.rms, &w.periods, &w.damping).iter().any(|r| r.quantity == q && r.is_pass()));
}

#[test]
fn band_runs_repeat_their_base_with_alpha_and_no_explicit_background_pressure() {
    let runs = wave().runs();
    let get = |id: &str| runs.iter().find(|r| r.spec.id == id).unwrap_or_else(|| panic!("{id}"));
    for (base, member) in [("ratio1-nx64-projected", "ratio1-nx64-projected-alpha4"), ("ratio1000", "ratio1000-alpha1")]
    {
        let (b, m) = (get(base), get(member));
        assert_eq!(m.label, b.label);
        assert_eq!(m.spec.sets[..b.spec.sets.len()], b.spec.sets[..]);
        assert_eq!(m.spec.sets.len(), b.spec.sets.len() + 1);
        assert!(m.spec.sets.last().unwrap().starts_with("capillary_rule.alpha="));
        assert!(!m.spec.sets.iter().any(|s| s.contains(".p_b=")), "{:?}", m.spec.sets);
    }
    // Members committed under other names are not made again.
    assert!(!runs.iter().any(|r| r.spec.id == "ratio1-alpha1" || r.spec.id == "ratio1-nx64-alpha4"));
    let a1 = get("ratio1000-alpha1").spec.scene().expect("scene");
    let base = get("ratio1000").spec.scene().expect("scene");
    assert!((a1.phases[0].p_b / base.phases[0].p_b - 0.5).abs() < 1e-12);
    assert_eq!(a1.phases[0].c0, base.phases[0].c0);
}
