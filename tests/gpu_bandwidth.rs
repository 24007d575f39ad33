//! The adapter's measured streaming bandwidth (`gpu::bandwidth::measure_bandwidth`): the study's
//! probe moves [`PROBE_BYTES`] per buffer (capped by the adapter's buffer size) in chunks of at
//! most the binding limit, one dispatch each, and gives a finite positive figure; the quick probe
//! of `sphlab run` stays one chunk on any adapter whose binding limit holds it. Under a time
//! budget the probe shrinks by halving until its cost at the quick probe's rate fits its share.

mod common;

use common::{gpu_or_skip, serial};
use sphlab::gpu::bandwidth::{
    measure_bandwidth, measure_bandwidth_within, probe_bytes_within, PROBE_BUDGET_SHARE, PROBE_BYTES, PROBE_REPEATS,
    QUICK_PROBE_BYTES,
};

#[test]
fn study_probe_covers_its_bytes_in_binding_sized_chunks() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if !ctx.has(wgpu::Features::TIMESTAMP_QUERY) {
        assert!(measure_bandwidth(&ctx, QUICK_PROBE_BYTES).unwrap().is_none(), "never estimated without timestamps");
        return;
    }
    let l = &ctx.limits;
    let align = u64::from(l.min_storage_buffer_offset_alignment).max(16);
    let chunk = l.max_storage_buffer_binding_size.min(l.max_buffer_size) / align * align;
    for bytes in [PROBE_BYTES, QUICK_PROBE_BYTES] {
        let b = measure_bandwidth(&ctx, bytes).unwrap().expect("timestamps give a bandwidth");
        let want = bytes.min(l.max_buffer_size) / 16 * 16;
        assert_eq!(b.buffer_bytes, want);
        let dispatches = want.div_ceil(chunk);
        assert!(b.method.contains(&format!("(dispatches per pass: {dispatches})")), "{}", b.method);
        assert!(b.gb_per_s.is_finite() && b.gb_per_s > 0.0 && b.best_ns > 0.0, "{b:?}");
        // The figure is what the best pass moved: 2 × bytes in best_ns.
        assert!((b.gb_per_s - 2.0 * want as f64 / b.best_ns).abs() <= 1e-9 * b.gb_per_s);
        println!("{}: {:.2} GB/s ({})", ctx.describe(), b.gb_per_s, b.method);
    }
}

#[test]
fn probe_size_halves_until_its_cost_fits_the_seconds() {
    // One pass of the full 1 GiB probe at 1 GB/s moves 2 GiB: the probe (first fill + every
    // pass) costs (PROBE_REPEATS + 2) × 2.147 s.
    let full = f64::from(PROBE_REPEATS + 2) * 2.0 * PROBE_BYTES as f64 / 1e9;
    assert_eq!(probe_bytes_within(PROBE_BYTES, 1.0, full), Some(PROBE_BYTES));
    assert_eq!(probe_bytes_within(PROBE_BYTES, 1.0, full * 0.99), Some(PROBE_BYTES / 2));
    assert_eq!(probe_bytes_within(PROBE_BYTES, 1.0, full / 4.0), Some(PROBE_BYTES / 4));
    assert_eq!(probe_bytes_within(PROBE_BYTES, 4.0, full / 4.0), Some(PROBE_BYTES));
    let quick = full * QUICK_PROBE_BYTES as f64 / PROBE_BYTES as f64;
    assert_eq!(probe_bytes_within(PROBE_BYTES, 1.0, quick), Some(QUICK_PROBE_BYTES));
    assert_eq!(probe_bytes_within(PROBE_BYTES, 1.0, quick * 0.99), None, "never below the quick size");
}

#[test]
fn a_short_budget_measures_a_smaller_probe() {
    let _g = serial();
    let Some(ctx) = gpu_or_skip() else { return };
    if !ctx.has(wgpu::Features::TIMESTAMP_QUERY) {
        return;
    }
    // A budget whose share cannot hold even the quick probe keeps the quick probe's figure.
    let b = measure_bandwidth_within(&ctx, PROBE_BYTES, Some(1e-6)).unwrap().expect("timestamps");
    assert_eq!(b.buffer_bytes, QUICK_PROBE_BYTES.min(ctx.limits.max_buffer_size) / 16 * 16, "{}", b.method);
    assert!(b.method.contains(&sphlab::plan::fmt_bytes(b.buffer_bytes as f64)), "{}", b.method);
    // A budget whose share holds the full probe at any rate this adapter reaches measures it.
    let b = measure_bandwidth_within(&ctx, PROBE_BYTES, Some(1e6 / PROBE_BUDGET_SHARE)).unwrap().expect("timestamps");
    assert_eq!(b.buffer_bytes, PROBE_BYTES.min(ctx.limits.max_buffer_size) / 16 * 16, "{}", b.method);
}
