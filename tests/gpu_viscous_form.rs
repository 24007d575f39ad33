//! The projected viscous form (docs/PHYSICS.md §4.1) on the GPU: on `oscillating-drop` (relax
//! off, its T84 velocity field, so the viscous sums are not zero; fluid–fluid and fluid–wall
//! pairs) the CPU's accelerations with the two forms differ by far more than verify's
//! tolerance, and one force evaluation of a variant of each mapping and precision with the
//! projected form matches the CPU's with that form. A GPU path that ignored the form fails.

mod common;

use common::{assert_variants_match, evaluated_cpu, gpu_or_skip, scene, serial, MAPPING_VARIANTS};
use sphlab::fields::Field;
use sphlab::verify::field_error;
use std::sync::Arc;

#[test]
fn projected_viscous_form_matches_cpu_on_the_gpu() {
    let _g = serial();
    let (lap, _) = scene("oscillating-drop", &[]);
    let (s, l) = scene("oscillating-drop", &["viscous_form=projected"]);
    let (c64_lap, c64, c32) =
        (evaluated_cpu::<f64>(&lap, &l), evaluated_cpu::<f64>(&s, &l), evaluated_cpu::<f32>(&s, &l));
    let nf = c64.n_fluid;
    let (_, diff) = field_error(&c64.f.flat(Field::Acc, nf), &c64_lap.f.flat(Field::Acc, nf), 0.0);
    println!("CPU f64 accelerations, projected against T70: rel-L2 {diff:.2e}");
    assert!(diff > 1e-3, "the two forms give accelerations only {diff:e} apart: the check could not see the form");
    let Some(ctx) = gpu_or_skip() else { return };
    let ctx = Arc::new(ctx);
    assert_variants_match("projected", &ctx, (&s, &l), &MAPPING_VARIANTS, &c64, &c32);
}
