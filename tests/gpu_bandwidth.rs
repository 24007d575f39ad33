//! The adapter's measured streaming bandwidth (`gpu::bandwidth::measure_bandwidth`): the study's
//! probe moves [`PROBE_BYTES`] per buffer (capped by the adapter's buffer size) in chunks of at
//! most the binding limit, one dispatch each, and gives a finite positive figure; the quick probe
//! of `sphlab run` stays one chunk on any adapter whose binding limit holds it.

mod common;

use common::{gpu_or_skip, serial};
use sphlab::gpu::bandwidth::{measure_bandwidth, PROBE_BYTES, QUICK_PROBE_BYTES};

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
