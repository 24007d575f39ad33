//! The parts of `sphlab study --preset gpu`, most valuable first, each a `sphlab` command of its
//! own with a weight (its share of the budget) and a floor below which it is skipped:
//!
//! smoke → the bare neighbour walk (`walk-probe`) → scaling of the leading variants → E4 (2,025 and 10,000 fluid particles) → E1 → E3 →
//! E2 → verify every variant on one scene → verify Mode A's unbalanced Young force (its own
//! contact-angle kernel) → verify lists split into list chunks → impact at full resolution, one
//! part per angle.
//!
//! Two scales: `gpu` (the thesis's sizes; scaling from the E4 size N ≈ 10⁴, where the one-thread
//! CPU references are measured, to the largest N whose buffers fit, probed at 10⁵ and 10⁶, with
//! CPU rows only at the E4 size so the budget goes to GPU rows) and `rehearsal` (a CPU adapter under
//! `--allow-cpu-adapter`: every part at a size lavapipe runs in seconds, so the whole pipeline
//! is exercised; its times are no measurement).

use crate::gpu::variant::VariantSpec;
use std::path::Path;

/// The part's budget placeholder in its arguments (replaced by the share in seconds).
pub const BUDGET: &str = "{budget}";
/// The part's output directory placeholder in its arguments.
pub const OUT: &str = "{out}";

/// One part: a `sphlab` command run as a child process within its share of the budget.
#[derive(Clone, Debug)]
pub struct Part {
    /// Directory name under `parts/` (`01-smoke`, …).
    pub name: String,
    /// What it runs, for the plan and the summary.
    pub what: String,
    /// Weight of its share of the budget (ignored for the smoke test, see [`SMOKE_MAX_S`]).
    pub weight: f64,
    /// `sphlab` arguments, with [`BUDGET`] and [`OUT`] placeholders.
    pub args: Vec<String>,
    /// The part's output is a study directory (merged into `study/`).
    pub study: bool,
    /// A failure stops the preset (the smoke test).
    pub gate: bool,
}

/// The longest the smoke test may take (s); it also takes at most a fifth of the budget.
pub const SMOKE_MAX_S: f64 = 60.0;
/// A part whose share is below this (s) is skipped: it could not even start its adapter.
pub const MIN_SHARE_S: f64 = 4.0;
/// The smoke test's variants: the default one-particle-per-thread variant and a block variant.
pub const SMOKE_VARIANTS: [&str; 2] = ["cells.thread.recomputed.f32", "cells.block-tree.fixed.recomputed.f32"];
/// Variants verified with their list slots split into list chunks (`verify --gpu-binding`,
/// `gpu::list_chunks`): cached values of every mapping family, f32 and f64, in the full and the
/// pooled slot layout (`gpu::pooled_lists`), the cached tracking candidates as masks, slot
/// lists with recomputed values.
pub const CHUNK_VARIANTS: [&str; 5] = [
    "cells.thread.cached.f32",
    "direct.block-atomic.cas.cached.f32",
    "cells.subgroup.cached.f64.pooled",
    "tracking.block-tree.fixed.cached.f64.masks",
    "cells.subgroup.recomputed.f32.slots",
];
/// The per-buffer cap of that part: four chunks of the f64 cache at nx = 24 (1,024 particles).
pub const CHUNK_BINDING: &str = "256K";
/// The scene overrides of the unbalanced Young force's part: relax-60 at nx = 33, Mode A with
/// the force (docs/PHYSICS.md §8.2.5), from a jittered lattice so the measured angle moves.
pub const YOUNG_SETS: [&str; 4] =
    ["domain.nx=33", "contact.mode=\"a\"", "contact.wall_tension=\"unbalanced\"", "domain.jitter=0.1"];
/// Impact angles at full resolution (run ids of `validate impact`), one part each: the two
/// extremes of the thesis's angles.
pub const IMPACT_RUNS: [&str; 2] = ["theta50", "theta160"];
/// Scaling resolutions (N ≈ nx²: 10³ … 4·10⁷); the `gpu` scale starts at [`GPU_SCALING_FROM_NX`].
pub const SCALING_NX: [u32; 9] = [32, 100, 316, 1000, 1414, 2000, 3162, 4472, 6324];
/// First scaling resolution of the `gpu` scale (the E4 size, N = 11,664).
pub const GPU_SCALING_FROM_NX: u32 = 100;
/// Probe resolutions of the `gpu` scale's scaling part (N ≈ 10⁵ and 10⁶: a GPU's step at 10⁴ is
/// mostly its fixed floor, which says nothing of the cost per particle).
pub const GPU_SCALING_PROBE_NX: [u32; 2] = [316, 1000];
/// CPU rows of the `gpu` scale's scaling part only up to this many particles (the E4 size):
/// larger GPU rows compare with them scaled by N, and the budget goes to the GPU rows (a
/// one-thread CPU step at N ≈ 10⁵ takes about a third of a second, so its rows alone would
/// fill the part's share).
pub const GPU_SCALING_CPU_MAX_N: usize = 12_000;
/// Scaling resolutions of the `rehearsal` scale.
pub const REHEARSAL_SCALING_NX: [u32; 3] = [16, 32, 64];
/// Lattice sides of the walk probe on a GPU (N ≈ 10⁴ … 10⁷). The part takes seconds: its weight,
/// 10, is mostly handed on to the parts after it, but keeps a rehearsal's share above
/// [`MIN_SHARE_S`].
pub const GPU_WALK_SIDES: &str = "100,316,1000,3162";
/// Lattice sides of the walk probe in a rehearsal.
pub const REHEARSAL_WALK_SIDES: &str = "16,32";
/// CPU rows of the study parts only up to this many particles.
pub const CPU_MAX_N: usize = 200_000;

/// The sizes and protocol of one scale.
#[derive(Clone, Debug)]
pub struct Scale {
    /// `gpu` or `rehearsal`.
    pub name: &'static str,
    /// `--steps`, `--repeats`, `--warmup` of every study part.
    pub protocol: [&'static str; 6],
    /// Scaling resolutions that fit this adapter (ascending).
    pub scaling_nx: Vec<u32>,
    /// The scaling part's probe resolutions.
    pub scaling_probe_nx: Vec<u32>,
    /// The scaling part's `--cpu-max-n`.
    pub scaling_cpu_max_n: usize,
    /// The scaling part's variants.
    pub leading: Vec<VariantSpec>,
    /// E4 resolutions.
    pub e4_nx: &'static str,
    /// Extra E2 arguments.
    pub e2: Vec<&'static str>,
    /// Extra E3 arguments.
    pub e3: Vec<&'static str>,
    /// Scene overrides and steps of the verification parts (smoke and verify).
    pub verify: Vec<&'static str>,
    /// `--sides` of the walk probe.
    pub walk_sides: &'static str,
}

impl Scale {
    /// The thesis's sizes on a real GPU; `fitting` are the scaling sizes whose buffers fit.
    pub fn gpu(fitting: &[u32]) -> Scale {
        Scale {
            name: "gpu",
            protocol: ["--steps", "20", "--repeats", "5", "--warmup", "0.2"],
            scaling_nx: fitting.iter().copied().filter(|&n| n >= GPU_SCALING_FROM_NX).collect(),
            scaling_probe_nx: GPU_SCALING_PROBE_NX.iter().copied().filter(|n| fitting.contains(n)).collect(),
            scaling_cpu_max_n: GPU_SCALING_CPU_MAX_N,
            leading: leading_variants(),
            e4_nx: "45,100",
            e2: vec![],
            e3: vec![],
            verify: vec!["--steps", "20"],
            walk_sides: GPU_WALK_SIDES,
        }
    }

    /// Seconds-long sizes for a CPU adapter: the pipeline is exercised, nothing is measured.
    pub fn rehearsal() -> Scale {
        Scale {
            name: "rehearsal",
            protocol: ["--steps", "2", "--repeats", "2", "--warmup", "0.1"],
            scaling_nx: REHEARSAL_SCALING_NX.to_vec(),
            scaling_probe_nx: REHEARSAL_SCALING_NX[..2].to_vec(),
            scaling_cpu_max_n: CPU_MAX_N,
            leading: leading_variants().into_iter().filter(|v| v.precision.name() == "f32").collect(),
            e4_nx: "45",
            e2: vec!["--e2-nx", "20"],
            e3: vec!["--e3-nx", "30", "--e3-steps", "5", "--e3-budgets", "300,600"],
            verify: vec!["--set", "domain.nx=24", "--steps", "3"],
            walk_sides: REHEARSAL_WALK_SIDES,
        }
    }
}

/// The recomputed one-particle-per-thread variants (the thesis's best configuration) with cell
/// and tracking search: the scaling part's variants.
pub fn leading_variants() -> Vec<VariantSpec> {
    VariantSpec::all()
        .into_iter()
        .filter(|s| s.to_string().contains(".thread.recomputed.") && s.search != crate::neighbours::SearchKind::Direct)
        .collect()
}

fn strs(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

/// Every part of the preset in run order.
pub fn parts(scale: &Scale) -> Vec<Part> {
    let mut out = Vec::new();
    let mut push = |what: String, weight: f64, args: Vec<String>, study: bool, gate: bool| {
        let name = format!("{:02}-{}", out.len() + 1, args_name(&args));
        out.push(Part { name, what, weight, args, study, gate });
    };
    let verify = |variants: &str| {
        let mut a = strs(&["verify", "oscillating-drop", "--variants", variants]);
        a.extend(strs(&scale.verify));
        a.extend(strs(&["--budget", BUDGET, "--out", OUT]));
        a
    };
    push(
        format!("smoke: {} against the CPU reference", SMOKE_VARIANTS.join(", ")),
        0.0,
        verify(&SMOKE_VARIANTS.join(",")),
        false,
        true,
    );
    push(
        format!("the bare neighbour walk in four forms, lattice sides {}", scale.walk_sides),
        10.0,
        strs(&["walk-probe", "--sides", scale.walk_sides, "--out", OUT]),
        false,
        false,
    );
    let study_capped = |experiment: &str, extra: Vec<String>, cpu_max_n: usize| {
        let mut a = strs(&["study", "--experiments", experiment]);
        a.extend(strs(&scale.protocol));
        a.extend(extra);
        a.extend(strs(&["--cpu-max-n", &cpu_max_n.to_string(), "--budget", BUDGET, "--out", OUT]));
        a
    };
    let study = |experiment: &str, extra: Vec<String>| study_capped(experiment, extra, CPU_MAX_N);
    let sizes: Vec<String> = scale.scaling_nx.iter().map(|n| n.to_string()).collect();
    let probe: Vec<String> = scale.scaling_probe_nx.iter().map(|n| n.to_string()).collect();
    if sizes.len() >= 2 && probe.len() == 2 {
        let leading: Vec<String> = scale.leading.iter().map(|v| v.to_string()).collect();
        let extra = vec![
            "--sizes".into(),
            sizes.join(","),
            "--probe-sizes".into(),
            probe.join(","),
            "--variants".into(),
            leading.join(","),
        ];
        let what = format!(
            "scaling of {} at nx {} (probed at nx {}; CPU rows up to N = {})",
            leading.join(", "),
            sizes.join(", "),
            probe.join(", "),
            scale.scaling_cpu_max_n
        );
        push(what, 23.0, study_capped("scaling", extra, scale.scaling_cpu_max_n), true, false);
    }
    push(
        format!("E4: every variant at nx {}", scale.e4_nx),
        26.5,
        study("e4", strs(&["--e4-sizes", scale.e4_nx])),
        true,
        false,
    );
    push("E1: searches × CPU one thread and GPU at nx 45".into(), 4.0, study("e1", vec![]), true, false);
    for (e, w, what, extra) in [
        ("e3", 6.0, "E3: subdomains (thesis ○ ∆ □)", &scale.e3),
        ("e2", 4.0, "E2: CPU/GPU residency hybrids", &scale.e2),
    ] {
        let sizes = if extra.is_empty() { "thesis sizes".to_string() } else { extra.join(" ") };
        push(format!("{what}, {sizes}"), w, study(e, strs(extra)), true, false);
    }
    push("verify every variant on oscillating-drop".into(), 6.0, verify("all"), false, false);
    let mut young = strs(&["verify", "relax-60", "--variants", &SMOKE_VARIANTS.join(",")]);
    young.extend(YOUNG_SETS.iter().flat_map(|kv| ["--set".to_string(), kv.to_string()]));
    young.extend(strs(&["--steps", "20", "--per-stage", "--budget", BUDGET, "--out", OUT]));
    push("verify Mode A's unbalanced Young force on relax-60 at nx 33".into(), 1.5, young, false, false);
    let mut chunks = strs(&["verify", "oscillating-drop", "--variants", &CHUNK_VARIANTS.join(",")]);
    chunks.extend(strs(&["--set", "domain.nx=24", "--steps", "20", "--per-stage", "--gpu-binding", CHUNK_BINDING]));
    chunks.extend(strs(&["--budget", BUDGET, "--out", OUT]));
    push(format!("verify lists in chunks ({CHUNK_BINDING} bindings)"), 2.0, chunks, false, false);
    let variant = VariantSpec::default().to_string();
    let impact = |extra: &[&str]| {
        let mut a = strs(&["validate", "impact", "--backend", "gpu", "--variant", &variant, "--quiet", "--out", OUT]);
        a.extend(strs(extra));
        a
    };
    if scale.name == "gpu" {
        for id in IMPACT_RUNS {
            push(
                format!("impact at full resolution: {id}"),
                17.0 / IMPACT_RUNS.len() as f64,
                impact(&["--full-impact", "--only", id]),
                false,
                false,
            );
        }
    } else {
        push("impact, quick case (coarse, short)".into(), 17.0, impact(&["--quick"]), false, false);
    }
    out
}

/// A short name for a part's directory from its arguments.
fn args_name(args: &[String]) -> String {
    let get = |flag: &str| args.iter().position(|a| a == flag).and_then(|k| args.get(k + 1)).cloned();
    match args[0].as_str() {
        "verify" if get("--variants").as_deref() == Some("all") => "verify".into(),
        "verify" if get("--gpu-binding").is_some() => "chunks".into(),
        "verify" if args.get(1).map(String::as_str) == Some("relax-60") => "young".into(),
        "verify" => "smoke".into(),
        "study" => get("--experiments").unwrap_or_default(),
        "walk-probe" => "walk".into(),
        _ => match get("--only") {
            Some(id) => format!("impact-{id}"),
            None => "impact".into(),
        },
    }
}

/// The part's arguments with its budget (s) and output directory filled in.
pub fn command(part: &Part, budget_s: f64, out: &Path) -> Vec<String> {
    part.args
        .iter()
        .map(|a| match a.as_str() {
            BUDGET => format!("{:.0}s", budget_s.max(1.0)),
            OUT => out.display().to_string(),
            _ => a.clone(),
        })
        .collect()
}

/// The share (s) of `parts[k]` when `left_s` seconds remain for it and the parts after it.
pub fn share(parts: &[Part], k: usize, left_s: f64) -> f64 {
    let rest: f64 = parts[k..].iter().map(|p| p.weight).sum();
    if rest <= 0.0 {
        return left_s.max(0.0);
    }
    left_s.max(0.0) * parts[k].weight / rest
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_run_most_valuable_first_with_one_dir_each() {
        let p = parts(&Scale::gpu(&SCALING_NX));
        let names: Vec<&str> = p.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "01-smoke",
                "02-walk",
                "03-scaling",
                "04-e4",
                "05-e1",
                "06-e3",
                "07-e2",
                "08-verify",
                "09-young",
                "10-chunks",
                "11-impact-theta50",
                "12-impact-theta160"
            ]
        );
        assert!(p[0].gate && p.iter().skip(1).all(|p| !p.gate));
        let walk = command(&p[1], 1.0, Path::new("x"));
        assert_eq!(walk, ["walk-probe", "--sides", GPU_WALK_SIDES, "--out", "x"]);
        let scaling = command(&p[2], 123.4, Path::new("x"));
        let at = |f: &str| scaling[scaling.iter().position(|a| a == f).unwrap() + 1].clone();
        assert_eq!(at("--sizes"), "100,316,1000,1414,2000,3162,4472,6324");
        assert_eq!(at("--probe-sizes"), "316,1000", "probed near 10⁵–10⁶, not at the floor of 10⁴");
        assert_eq!(at("--cpu-max-n"), "12000", "CPU rows at the E4 size only");
        let e4 = command(&p[3], 1.0, Path::new("x"));
        assert_eq!(e4[e4.iter().position(|a| a == "--cpu-max-n").unwrap() + 1], CPU_MAX_N.to_string());
        let weights: f64 = p.iter().map(|p| p.weight).sum();
        assert!((weights - 100.0).abs() < 1e-9, "the weights are percentages of the budget: {weights}");
        assert_eq!((at("--budget").as_str(), at("--out").as_str()), ("123s", "x"));
    }

    #[test]
    fn shares_follow_the_weights_of_the_parts_left() {
        let p = parts(&Scale::rehearsal());
        let total: f64 = p[1..].iter().map(|p| p.weight).sum();
        let s = share(&p, 1, 100.0);
        assert!((s - 100.0 * p[1].weight / total).abs() < 1e-9);
        let last = p.len() - 1;
        assert!((share(&p, last, 7.0) - 7.0).abs() < 1e-12, "the last part takes what is left");
        assert_eq!(share(&p, 1, -3.0), 0.0);
    }
}
