//! The memory plan's tests: the list format by N, list chunks, refusals with their numbers.

use super::*;

#[test]
fn direct_is_refused_on_lavapipe_past_the_loop_cap() {
    let direct: VariantSpec = "direct.thread.recomputed.f32".parse().unwrap();
    let cells: VariantSpec = "cells.thread.recomputed.f32".parse().unwrap();
    let lp = "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)";
    assert!(direct_loop_check(&direct, 11_664, 4, lp).is_ok());
    assert!(direct_loop_check(&direct, 16_126, 4, lp).is_ok());
    let e = direct_loop_check(&direct, 16_127, 4, lp).unwrap_err();
    assert!(e.contains("65535") && e.contains("16126 particles") && e.contains(&direct.to_string()), "{e}");
    assert!(direct_loop_check(&direct, 10_000_000, 4, "NVIDIA 580.95").is_ok());
    assert!(direct_loop_check(&cells, 10_000_000, 4, lp).is_ok());
}

#[test]
fn the_list_format_is_slots_while_they_fit_the_binding() {
    let lim = DeviceLimits::stated(140_000_000_000, 2 << 30, "test");
    let small = DeviceLimits::stated(1 << 40, 128 << 20, "test");
    let at = |id: &str, n: u64, lim: &DeviceLimits| {
        // The list format: the id's last part before a slot layout.
        let id = resolve_lists(&id.parse().unwrap(), n, n / 12, lim).to_string();
        id.trim_end_matches(".full").trim_end_matches(".pooled").rsplit('.').next().unwrap().to_string()
    };
    // Tracking candidates: 96 slots × 4 B per particle in one binding; cells lists: 64 slots.
    let cap_track = (2u64 << 30) / (96 * 4);
    assert_eq!(at("tracking.thread.recomputed.f32", cap_track, &lim), "slots");
    assert_eq!(at("tracking.thread.recomputed.f32", cap_track + 1, &lim), "masks");
    assert_eq!(at("cells.subgroup.recomputed.f32", (2u64 << 30) / 256, &lim), "slots");
    assert_eq!(at("cells.subgroup.recomputed.f32", (2u64 << 30) / 256 + 1, &lim), "masks");
    assert_eq!(at("cells.subgroup.recomputed.f32", 11_664, &small), "slots");
    assert_eq!(at("cells.subgroup.recomputed.f32", 600_000, &small), "masks");
    // Forced formats are kept; variants without the choice are left alone.
    assert_eq!(at("tracking.thread.recomputed.f32.masks", 1000, &lim), "masks");
    assert_eq!(at("tracking.thread.recomputed.f32.slots", 100_000_000, &lim), "slots");
    assert_eq!(at("direct.subgroup.recomputed.f32", (2u64 << 30) / 256, &lim), "slots");
    assert_eq!(at("direct.subgroup.recomputed.f32", 100_000_000, &lim), "masks");
    assert_eq!(at("direct.subgroup.cached.f32", 100_000_000, &lim), "f32");
    // The plan of an unresolved variant checks the format the solver would run.
    let auto: VariantSpec = "tracking.thread.recomputed.f32".parse().unwrap();
    assert!(GpuPlan::new(&auto, 100_000_000, 8_000_000).check(&lim).is_ok());
    let e = GpuPlan::new(&auto.with_lists(ListFormat::Slots).unwrap(), 100_000_000, 8_000_000).check(&lim);
    assert!(e.unwrap_err().contains("`cand`"));
    assert!(max_particles(&auto, 0.08, &lim, 1 << 28) > 100_000_000);
    // Slot lists and cached values past the binding are split into list chunks (2 GiB
    // each): a forced `.slots` and the cached variants fit 10⁸ particles by the plan; the
    // tracking candidates (96 slots, one binding) do not.
    let direct: VariantSpec = "direct.subgroup.recomputed.f32.slots".parse().unwrap();
    let p = GpuPlan::new(&direct, 100_000_000, 8_000_000);
    assert!(p.check(&lim).is_ok());
    assert_eq!((p.list_chunks(lim.buffer_cap()), p.largest(lim.buffer_cap()).0), (12, "nbr"));
    let cells: VariantSpec = "cells.thread.cached.f32".parse().unwrap();
    let p = GpuPlan::new(&cells, 100_000_000, 8_000_000);
    assert!(p.check(&lim).is_ok());
    assert_eq!(p.list_chunks(lim.buffer_cap()), 24);
    assert_eq!(p.largest(lim.buffer_cap()), ("cache_wf", 4_194_304 * 512));
    assert!(max_particles(&cells, 0.08, &lim, 1 << 28) > 100_000_000);
    // Cached tracking: slot candidates while they fit one binding, masks beyond (the list
    // slots and the cache stay slots, in chunks); forced slots are refused there.
    assert_eq!(at("tracking.thread.cached.f32", 5_000_000, &lim), "slots");
    assert_eq!(at("tracking.thread.cached.f32", 6_000_000, &lim), "masks");
    let cached: VariantSpec = "tracking.thread.cached.f32".parse().unwrap();
    assert!(max_particles(&cached, 0.08, &lim, 1 << 28) > 100_000_000);
    let slots = cached.with_lists(ListFormat::Slots).unwrap();
    let e = GpuPlan::new(&slots, 6_000_000, 400_000).check(&lim).unwrap_err();
    assert!(e.contains("`cand`") && !e.contains("chunks"), "{e}");
    // A binding below one chunk of 256 particles is refused, naming the chunk: forced full
    // slots with their 512 B per particle, else the pooled layout tried last (392 B).
    let tiny = DeviceLimits::stated(1 << 40, 64 << 10, "test");
    let e = GpuPlan::new(&cells.with_slots(SlotLayout::Full).unwrap(), 1024, 100).check(&tiny).unwrap_err();
    assert!(
        e.contains("`cache_wf`") && e.contains("(512 B of list slots") && e.contains("at least 256 particles"),
        "{e}"
    );
    let e = GpuPlan::new(&cells, 1024, 100).check(&tiny).unwrap_err();
    assert!(e.contains(".pooled for") && e.contains("(392 B of list slots"), "{e}");
    let e = GpuPlan::new(&auto, 100_000_000, 8_000_000).check(&small).unwrap_err();
    assert!(!e.contains("per-pair"), "{e}");
}

#[test]
fn cached_variants_take_pooled_slots_where_full_ones_do_not_fit() {
    use crate::gpu::pooled_lists::{POOL_BLOCK, POOL_REGION};
    let lim = DeviceLimits::stated(140_000_000_000, 2 << 30, "test");
    let n = 100_000_000u64;
    let cells = (n as f64 * 0.0798).ceil() as u64;
    // Every variant fits 10⁸ particles on the stated 140 GB adapter, each in the layout the
    // plan chooses: full 64 slots while they fit, pooled (the f64 caches) beyond.
    for v in VariantSpec::all() {
        let p = GpuPlan::resolved(&v, n, cells, &lim);
        assert!(p.check(&lim).is_ok(), "{v}: {:?}", p.check(&lim));
        let want = match (v.kernel_values, v.precision) {
            (KernelValues::Recomputed, _) => SlotLayout::Auto,
            (KernelValues::Cached, crate::real::Precision::F32) => SlotLayout::Full,
            (KernelValues::Cached, crate::real::Precision::F64) => SlotLayout::Pooled,
        };
        assert_eq!(p.spec.slots, want, "{v}");
    }
    // The f64 cache with 64 slots does not fit; forced, it is refused by the device memory.
    let full: VariantSpec = "tracking.block-tree.fixed.cached.f64.full".parse().unwrap();
    let e = GpuPlan::new(&full, n, cells).check(&lim).unwrap_err();
    assert!(e.contains("device memory"), "{e}");
    // Below that size the full layout is kept; a forced pooled layout is kept at any size.
    let auto: VariantSpec = "cells.thread.cached.f64".parse().unwrap();
    assert_eq!(resolve_lists(&auto, 8_000_000, 640_000, &lim).slots, SlotLayout::Full);
    let pooled = auto.with_slots(SlotLayout::Pooled).unwrap();
    assert_eq!(resolve_lists(&pooled, 1000, 80, &lim).slots, SlotLayout::Pooled);
    // Pooled bytes: one region (a header word and 48 entries per particle) per block of 64,
    // the last block whole; `nbr` in words, the cache a real pair per word.
    let bytes =
        |n: u64, name: &str| GpuPlan::new(&pooled, n, n / 12).buffers.iter().find(|b| b.name == name).unwrap().bytes;
    assert_eq!(bytes(640, "nbr"), 10 * POOL_REGION as u64 * 4);
    assert_eq!(bytes(641, "cache_wf"), 11 * POOL_REGION as u64 * 16);
    assert_eq!(POOL_REGION, POOL_BLOCK * 49);
    assert!(auto.with_slots(SlotLayout::Full).unwrap().to_string().ends_with(".full"));
    let recomputed: VariantSpec = "cells.thread.recomputed.f64".parse().unwrap();
    assert!(recomputed.with_slots(SlotLayout::Pooled).is_none());
}

#[test]
fn plan_refuses_with_the_buffer_and_numbers() {
    let spec: VariantSpec = "cells.thread.recomputed.f32".parse().unwrap();
    let lim = DeviceLimits::stated(1 << 40, 128 << 20, "test");
    // The per-particle vec2 arrays (N × 8 B, pos first) are the largest buffers: 128 MiB at
    // N = 16,777,216 (r⁰, v⁰ and the two gradient slots are separate bindings; the
    // renumbering keeps 4 B per particle in the one reorder buffer, its scratch is arrays
    // the evaluation recomputes: `GpuSolver::record_renumbered`). nx = 3000 of the drop
    // (9,048,064 particles) fits.
    assert!(GpuPlan::new(&spec, 16_777_216, 1000).check(&lim).is_ok());
    assert!(GpuPlan::new(&spec, 9_048_064, 9_000_000).check(&lim).is_ok());
    let e = GpuPlan::new(&spec, 16_777_217, 1000).check(&lim).unwrap_err();
    assert!(e.contains("`pos`") && e.contains("134217736") && e.contains("134217728"), "{e}");
    assert_eq!(max_particles(&spec, 0.0, &lim, 1 << 28), 16_777_216);
    let f64_spec: VariantSpec = "cells.thread.recomputed.f64".parse().unwrap();
    assert_eq!(max_particles(&f64_spec, 0.0, &lim, 1 << 28), 8_388_608);
    let reorder =
        |p: &GpuPlan| p.buffers.iter().filter(|b| b.name.starts_with("reorder")).map(|b| b.bytes).sum::<u64>();
    assert_eq!(reorder(&GpuPlan::new(&spec, 1000, 10)), 4 * (1000 + 8), "permutation + control words");
    // The direct search never renumbers: the control words alone.
    let direct: VariantSpec = "direct.thread.recomputed.f32".parse().unwrap();
    assert_eq!(reorder(&GpuPlan::new(&direct, 1000, 10)), 4 * 8);
    let small = DeviceLimits::stated(1 << 30, 2 << 30, "test");
    let e = GpuPlan::new(&spec, 20_000_000, 1000).check(&small).unwrap_err();
    assert!(e.contains("device memory") && e.contains("1073741824"), "{e}");
    let cached: VariantSpec = "cells.thread.cached.f64".parse().unwrap();
    assert!(bytes_per_particle(&cached, 0.0) > 64.0 * 16.0, "the 64-slot f64 (W, F′) cache");
}
