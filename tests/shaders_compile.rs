//! Ladder step 1 (no GPU): every WGSL file composes and validates with naga in f32 and f64,
//! the preprocessor behaves (`#ifdef`, de-duplicated imports, errors naming file and line), and
//! every constant WGSL shares with Rust (stage flags, enumerated `Params` codes, `ctl`/`vctl`
//! words, list slots, the neighbour packing, colours, kernel ids) has Rust's value.

use sphlab::gpu::compose::{
    self, compose, compose_mapped, compose_variant_mapped, validate, F64, SHADERS, VARIANT_FILES,
};
use sphlab::gpu::GpuError;

const PRECISIONS: [&[&str]; 2] = [&[], &[F64]];

#[test]
fn every_shared_module_validates_in_f32_and_f64() {
    for (name, _) in SHADERS {
        for defines in PRECISIONS {
            let c = compose_mapped("<test>", &format!("#import {name}\n"), defines).expect("composes");
            if let Err(e) = validate(&c) {
                panic!("shaders/{name}.wgsl with {defines:?} does not validate:\n{e}\n{}", c.source);
            }
        }
    }
}

#[test]
fn all_modules_together_validate() {
    let entry: String = SHADERS.iter().map(|(n, _)| format!("#import {n}\n")).collect();
    for defines in PRECISIONS {
        let c = compose_mapped("<test>", &entry, defines).expect("composes");
        validate(&c).unwrap_or_else(|e| panic!("{defines:?}: {e}"));
    }
}

#[test]
fn every_variant_file_validates() {
    for (path, _) in VARIANT_FILES {
        for defines in PRECISIONS {
            let c = compose_variant_mapped(path, defines).expect("composes");
            validate(&c).unwrap_or_else(|e| panic!("{path} {defines:?}: {e}"));
        }
    }
}

#[test]
fn shared_modules_have_no_bindings_or_entry_points() {
    for (name, src) in SHADERS {
        for bad in ["@group", "@binding", "@compute", "@vertex", "@fragment"] {
            assert!(!src.contains(bad), "shaders/{name}.wgsl contains {bad}: shared modules hold functions only");
        }
    }
}

#[test]
fn precision_prelude_switches_real() {
    let f32src = compose("", &[]).expect("composes");
    let f64src = compose("", &[F64]).expect("composes");
    assert!(f32src.contains("alias real = f32;") && f32src.contains("alias real2 = vec2<f32>;"), "{f32src}");
    assert!(f64src.contains("alias real = f64;") && f64src.contains("alias real2 = vec2<f64>;"), "{f64src}");
}

#[test]
fn ifdef_else_endif_select_lines() {
    let src =
        "#ifdef A\nconst X: u32 = 1u;\n#else\nconst X: u32 = 2u;\n#endif\n#ifndef B\nconst Y: u32 = 3u;\n#endif\n";
    let a = compose(src, &["A"]).expect("composes");
    assert!(a.contains("X: u32 = 1u") && !a.contains("X: u32 = 2u") && a.contains("Y: u32 = 3u"), "{a}");
    let b = compose(src, &["B"]).expect("composes");
    assert!(b.contains("X: u32 = 2u") && !b.contains("X: u32 = 1u") && !b.contains("Y: u32"), "{b}");
    // Nested: the inner branch is dropped whenever the outer one is.
    let nested = "#ifdef A\n#ifdef B\nconst Z: u32 = 1u;\n#else\nconst Z: u32 = 2u;\n#endif\n#endif\n";
    assert!(!compose(nested, &["B"]).expect("composes").contains("const Z"), "outer A unset hides both");
    assert!(compose(nested, &["A"]).expect("composes").contains("Z: u32 = 2u"), "A set, B unset");
    // An import inside a dropped branch is not expanded.
    assert!(!compose("#ifdef NOPE\n#import kernel\n#endif\n", &[]).expect("composes").contains("kernel_f"));
}

#[test]
fn duplicate_and_transitive_imports_are_deduplicated() {
    // pair imports stress; stress imported again explicitly, pair twice.
    let src =
        compose("#import stress\n#import pair\n#import pair\n#import shaders/stress.wgsl\n", &[]).expect("composes");
    assert_eq!(src.matches("struct Sym2").count(), 1, "Sym2 once");
    assert_eq!(src.matches("fn grad_w_ij").count(), 1, "pair once");
    let c = compose_mapped("<test>", "#import pair\n", &[]).expect("composes");
    assert!(c.source.contains("struct Sym2"), "pair pulls in stress transitively");
    validate(&c).expect("valid");
}

fn expect_compose_error(r: Result<impl std::fmt::Debug, GpuError>, file: &str, line: usize) -> String {
    match r {
        Err(GpuError::ShaderCompose { file: f, line: l, msg }) => {
            assert_eq!((f.as_str(), l), (file, line), "error located at the wrong place: {msg}");
            msg
        }
        other => panic!("expected a ShaderCompose error at {file}:{line}, got {other:?}"),
    }
}

#[test]
fn composer_errors_name_file_and_line() {
    expect_compose_error(compose_mapped("broken.wgsl", "fn a() {}\n#import nowhere\n", &[]), "broken.wgsl", 2);
    expect_compose_error(compose_mapped("broken.wgsl", "\n\n#ifdef A\nfn a() {}\n", &[]), "broken.wgsl", 3);
    expect_compose_error(compose_mapped("broken.wgsl", "#endif\n", &[]), "broken.wgsl", 1);
    expect_compose_error(compose_mapped("broken.wgsl", "#ifdef A\n#else\n#else\n#endif\n", &[]), "broken.wgsl", 3);
    expect_compose_error(compose_mapped("broken.wgsl", "#pragma once\n", &[]), "broken.wgsl", 1);
    expect_compose_error(compose_variant_mapped("nope.wgsl", &[]), "kernels-variants/nope.wgsl", 0);
}

#[test]
fn naga_errors_are_mapped_back_to_the_original_line() {
    // A type error on line 4 of the entry, after a 30-odd-line import: the flat line differs.
    let src = "#import stress\n\nfn broken() -> real {\n    return sym2_mul_vec(1.0);\n}\n";
    let c = compose_mapped("broken.wgsl", src, &[]).expect("composes");
    let msg = expect_compose_error(validate(&c).map(|_| ()), "broken.wgsl", 4);
    assert!(!msg.is_empty(), "naga message kept");
    // A syntax error is located the same way.
    let c =
        compose_mapped("syntax.wgsl", "#import kernel\nfn x() -> real { return real(1.0) }\n", &[]).expect("composes");
    expect_compose_error(validate(&c).map(|_| ()), "syntax.wgsl", 2);
    // Unknown flat lines fall back to a placeholder rather than panicking.
    assert_eq!(c.locate(usize::MAX).0, "<composed>");
    let _ = compose::shader_source("kernel").expect("kernel is embedded");
}

/// The value of every `u32`/`i32` constant of a composed module, by name.
fn wgsl_constants(entry: &str) -> std::collections::HashMap<String, i64> {
    constants_of(&validate(&compose_mapped("<constants>", entry, &[]).expect("composes")).expect("validates"))
}

/// The value of every `u32`/`i32` constant of a validated module, by name.
fn constants_of(m: &wgpu::naga::Module) -> std::collections::HashMap<String, i64> {
    use wgpu::naga::{Expression, Literal};
    let mut out = std::collections::HashMap::new();
    for (_, c) in m.constants.iter() {
        let v = match m.global_expressions[c.init] {
            Expression::Literal(Literal::U32(v)) => v as i64,
            Expression::Literal(Literal::I32(v)) => v as i64,
            _ => continue,
        };
        out.insert(c.name.clone().expect("named constant"), v);
    }
    out
}

#[test]
fn wgsl_constants_equal_rust_values() {
    use sphlab::cpu::contact_angle::{ANGLE_REACH_DX, ANGLE_ROWS};
    use sphlab::gpu::mask_lists;
    use sphlab::gpu::params::{code, flags};
    use sphlab::gpu::solver_buffers::ctl;
    use sphlab::gpu::variant_buffers::{vctl, vparam, CAND_SLOTS, NBR_SLOTS};
    use sphlab::model::{COLOUR_WALL, CONTACT_WORDS, MAX_CONTACTS, NO_COLOUR, SIDE_WALL_HALF_DX};
    use sphlab::neighbours::{IMAGE_SHIFT, INDEX_MASK};
    use sphlab::physics::kernel::KernelKind;
    let w = wgsl_constants("#import common/variant_bindings\n");
    let rust: &[(&str, i64)] = &[
        ("STAGE_HOLMES", flags::HOLMES as i64),
        ("STAGE_CONTACT_LINE", flags::CONTACT_LINE as i64),
        ("STAGE_WALL_TYPING", flags::WALL_TYPING as i64),
        ("STAGE_WALL_PRESSURE", flags::WALL_PRESSURE as i64),
        ("STAGE_SURFACE", flags::SURFACE as i64),
        ("STAGE_NORMAL_CORRECTION", flags::NORMAL_CORRECTION as i64),
        ("STAGE_VISCOSITY", flags::VISCOSITY as i64),
        ("STAGE_LJ", flags::LJ as i64),
        ("STAGE_XSPH", flags::XSPH as i64),
        ("STAGE_YOUNG_UNBALANCED", flags::YOUNG_UNBALANCED as i64),
        ("IMAGE_NONE", code::IMAGE_NONE as i64),
        ("IMAGE_MIRROR", code::IMAGE_MIRROR as i64),
        ("IMAGE_SHIFT", code::IMAGE_SHIFT as i64),
        ("CONTACT_MODE_NONE", code::CONTACT_MODE_NONE as i64),
        ("CONTACT_MODE_A", code::CONTACT_MODE_A as i64),
        ("CONTACT_MODE_B", code::CONTACT_MODE_B as i64),
        ("WALL_VELOCITY_MORRIS", code::WALL_VELOCITY_MORRIS as i64),
        ("WALL_VELOCITY_HOLMES", code::WALL_VELOCITY_HOLMES as i64),
        ("NO_COLOUR", NO_COLOUR as i64),
        ("COLOUR_WALL", COLOUR_WALL as i64),
        ("MAX_CONTACTS", MAX_CONTACTS as i64),
        ("CONTACT_WORDS", CONTACT_WORDS as i64),
        ("ANGLE_ROWS", ANGLE_ROWS as i64),
        ("ANGLE_REACH_DX", ANGLE_REACH_DX as i64),
        ("SIDE_WALL_HALF_DX", SIDE_WALL_HALF_DX as i64),
        ("KERNEL_CUBIC_SPLINE", KernelKind::CubicSpline.id() as i64),
        ("KERNEL_QUINTIC", KernelKind::Quintic.id() as i64),
        ("KERNEL_JOHNSON", KernelKind::Johnson.id() as i64),
        ("KERNEL_GAUSSIAN", KernelKind::Gaussian.id() as i64),
        ("KERNEL_WENDLAND_C2", KernelKind::WendlandC2.id() as i64),
        ("CTL_CONTACTS_FOUND", ctl::CONTACTS_FOUND as i64),
        ("CTL_CONTACTS", ctl::CONTACTS as i64),
        ("CTL_BAD_STEP", ctl::BAD_STEP as i64),
        ("CTL_BAD", ctl::BAD as i64),
        ("CTL_VMAX", ctl::VMAX as i64),
        ("CTL_AMAX", ctl::AMAX as i64),
        ("CTL_CONTACTS_MAX", ctl::CONTACTS_MAX as i64),
        ("CTL_STEP", ctl::STEP as i64),
        ("CTL_OVER_STEP", ctl::OVER_STEP as i64),
        ("CTL_DONE", ctl::DONE as i64),
        ("CTL_SCAN_MISS", ctl::SCAN_MISS as i64),
        ("NBR_SLOTS", NBR_SLOTS as i64),
        ("CAND_SLOTS", CAND_SLOTS as i64),
        ("NBR_WORDS_CELLS", mask_lists::NBR_WORDS_CELLS as i64),
        ("NBR_WORDS_TRACK", mask_lists::NBR_WORDS_TRACK as i64),
        ("CAND_WORDS", mask_lists::CAND_WORDS as i64),
        ("CAND_LO_WORDS", mask_lists::CAND_LO_WORDS as i64),
        ("PACK_SHIFT", IMAGE_SHIFT as i64),
        ("PACK_MASK", INDEX_MASK as i64),
        ("V_NBR_OVER", vctl::NBR_OVER as i64),
        ("V_NBR_MAX", vctl::NBR_MAX as i64),
        ("V_CAND_OVER", vctl::CAND_OVER as i64),
        ("V_CAND_MAX", vctl::CAND_MAX as i64),
        ("V_REBUILD", vctl::REBUILD as i64),
        ("V_SINCE", vctl::SINCE as i64),
        ("V_DISP2", vctl::DISP2 as i64),
        ("V_REBUILDS", vctl::REBUILDS as i64),
        ("V_EVERY", vctl::EVERY as i64),
        ("V_FIXED_OVER", vctl::FIXED_OVER as i64),
        ("V_OVER_FIRST", vctl::OVER_FIRST as i64),
        ("V_CAND_STALE", vctl::CAND_STALE as i64),
        ("V_NBR_EVAL", vctl::NBR_EVAL as i64),
        ("V_NBR_NEED", vctl::NBR_NEED as i64),
        ("V_POOL_NEED", vctl::POOL_NEED as i64),
        ("VP_ADAPTIVE", vparam::ADAPTIVE as i64),
        ("VP_PHYSICAL", vparam::PHYSICAL as i64),
    ];
    for (name, value) in rust {
        assert_eq!(w.get(*name), Some(value), "WGSL `{name}` differs from Rust");
    }
    // Every stage flag, ctl and vctl word of WGSL is tied above.
    let tied = |n: &str| ["STAGE_", "CTL_", "V_", "VP_ADAPTIVE", "VP_PHYSICAL"].iter().any(|p| n.starts_with(p));
    for name in w.keys().filter(|n| tied(n)) {
        assert!(rust.iter().any(|(r, _)| r == name), "WGSL `{name}` has no Rust twin in this test");
    }
    assert!(
        (ctl::DONE as i64) < ctl::LEN as i64
            && (ctl::SCAN_MISS as i64) < ctl::LEN as i64
            && (ctl::CONTACTS_MAX as i64) < ctl::LEN as i64
            && (vctl::NBR_EVAL as i64) < vctl::LEN as i64
            && (vctl::POOL_NEED as i64) < vctl::LEN as i64
    );
    // The pooled slot lists' blocks (`gpu::pooled_lists`), composed with their define.
    let pooled = constants_of(
        &validate(
            &compose_mapped("<constants>", "#import common/variant_bindings\n", &["POOLED_LISTS"]).expect("composes"),
        )
        .expect("validates"),
    );
    use sphlab::gpu::pooled_lists::{POOL_BLOCK, POOL_MEAN, POOL_REGION};
    for (name, value) in [("POOL_BLOCK", POOL_BLOCK), ("POOL_MEAN", POOL_MEAN), ("POOL_REGION", POOL_REGION)] {
        assert_eq!(pooled.get(name), Some(&(value as i64)), "WGSL `{name}` differs from Rust");
    }
    // The direct search's candidates per loop iteration: the WGSL chunk and the plan's bound.
    let nb = wgsl_constants("#import common/neighbours\n");
    assert_eq!(
        nb.get("DIRECT_CHUNK"),
        Some(&(sphlab::gpu::plan::DIRECT_CHUNK as i64)),
        "WGSL DIRECT_CHUNK differs from Rust"
    );
}

/// The subgroup kernels' `LANES` is `SUBGROUP_LANES` without a define and each count
/// `stages::lanes_define` accepts under its define; any other count is refused.
#[test]
fn subgroup_lanes_equal_rust_values() {
    use sphlab::gpu::stages::lanes_define;
    use sphlab::gpu::variant::SUBGROUP_LANES;
    for lanes in [2, 4, 8, SUBGROUP_LANES] {
        let defs: Vec<&str> = lanes_define(lanes).expect("accepted").into_iter().collect();
        let c = compose_variant_mapped("subgroup/pair_sums.wgsl", &defs).expect("composes");
        let w = constants_of(&validate(&c).expect("validates"));
        assert_eq!(w.get("LANES"), Some(&(lanes as i64)), "WGSL `LANES` with {defs:?} differs from Rust");
    }
    assert_eq!(lanes_define(SUBGROUP_LANES), Ok(None));
    for bad in [0, 1, 3, 32, 64] {
        assert!(lanes_define(bad).unwrap_err().contains("must be 2, 4, 8 or 16"), "{bad}");
    }
}
