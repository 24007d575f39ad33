//! Tests of the variant ids: every id round-trips, the list-format and workgroup choices are
//! offered exactly where they make sense.

use super::*;

#[test]
fn ids_round_trip() {
    let all = VariantSpec::all();
    // thread and subgroup layouts: 3 searches × 2 kernel values × 2 precisions; block
    // layouts: 3 searches × 2 kernel values × (3 accumulations in f32 + fixed in f64).
    let blocks = Mapping::ALL.iter().filter(|m| m.layout() == SumLayout::Block).count();
    assert_eq!(all.len(), 3 * 2 * 2 * (Mapping::ALL.len() - blocks) + 3 * 2 * 4 * blocks);
    assert!(all.iter().all(|s| s.implemented().is_ok()));
    let f64cas = VariantSpec {
        precision: Precision::F64,
        ..all.iter().find(|s| s.accumulation == Accumulation::Cas).copied().unwrap()
    };
    assert!(f64cas.implemented().is_err() && !all.contains(&f64cas));
    assert!(f64cas.to_string().parse::<VariantSpec>().unwrap_err().contains("not meaningful"));
    for s in &all {
        assert_eq!(s.to_string().parse::<VariantSpec>().unwrap(), *s, "{s}");
    }
    assert_eq!(VariantSpec::default().to_string(), DEFAULT_VARIANT);
    assert!("tracking.block-atomic.fixed.cached.f32".parse::<VariantSpec>().is_ok());
    for bad in [
        "cells.thread.cas.recomputed.f32",
        "cells.block-tree.recomputed.f32",
        "x",
        "cells.thread.none.recomputed.f32",
        "cells.thread.recomputed.f32.wg64",
        "cells.thread.recomputed.f32.wg96",
        "cells.subgroup.recomputed.f32.wg128",
        "cells.block-tree.fixed.recomputed.f32.wg256",
    ] {
        assert!(bad.parse::<VariantSpec>().is_err(), "{bad}");
    }
    for s in all.iter().filter(|s| s.mapping == Mapping::Thread) {
        for &w in &Workgroup::ALL[1..] {
            let wide = s.with_workgroup(w).expect("thread variants take every size");
            assert_eq!(wide.to_string(), format!("{s}.{}", w.name()));
            assert_eq!(wide.to_string().parse::<VariantSpec>().unwrap(), wide);
        }
    }
    assert!(all.iter().filter(|s| s.mapping != Mapping::Thread).all(|s| s.with_workgroup(Workgroup::W128).is_none()));
    // A forced list format round-trips, after the workgroup size; only where it is a choice.
    let t: VariantSpec = "tracking.thread.recomputed.f32.wg256.masks".parse().unwrap();
    assert_eq!((t.lists, t.workgroup), (ListFormat::Masks, Workgroup::W256));
    assert_eq!(t.to_string().parse::<VariantSpec>().unwrap(), t);
    for s in &all {
        for l in [ListFormat::Slots, ListFormat::Masks] {
            match s.with_lists(l) {
                Some(f) => assert_eq!(f.to_string().parse::<VariantSpec>().unwrap(), f, "{f}"),
                None => assert!(format!("{s}.{}", l.suffix().unwrap()).parse::<VariantSpec>().is_err()),
            }
        }
    }
    let chosen = all.iter().filter(|s| s.list_format_matters()).count();
    assert!(chosen > 0 && chosen < all.len());
    assert!("cells.thread.recomputed.f32.slots".parse::<VariantSpec>().unwrap_err().contains("list format"));
    assert!("direct.subgroup.cached.f32.masks".parse::<VariantSpec>().is_err());
    assert!("direct.subgroup.recomputed.f32.masks".parse::<VariantSpec>().unwrap().sorts_cells());
    assert!(!"direct.subgroup.recomputed.f32.slots".parse::<VariantSpec>().unwrap().sorts_cells());
    assert!("cells.subgroup.cached.f32.slots".parse::<VariantSpec>().is_err());
    // Slot layouts: a choice of the cached variants only, after the list format in the id.
    for s in &all {
        for l in [SlotLayout::Full, SlotLayout::Pooled] {
            match s.with_slots(l) {
                Some(f) => assert_eq!(f.to_string().parse::<VariantSpec>().unwrap(), f, "{f}"),
                None => assert!(s.kernel_values == KernelValues::Recomputed, "{s}"),
            }
        }
    }
    let id = "tracking.block-tree.fixed.cached.f64.masks.pooled";
    assert_eq!(id.parse::<VariantSpec>().unwrap().to_string(), id);
    let e = "cells.thread.recomputed.f32.pooled".parse::<VariantSpec>().unwrap_err();
    assert!(e.contains("cached kernel values"), "{e}");
}
