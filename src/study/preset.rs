//! `sphlab study --preset gpu` (and `scripts/gpu-report.sh`): one command that turns a short
//! GPU loan into the full report. It refuses a CPU adapter (lavapipe: wgpu `DeviceType::Cpu`)
//! with exit 2 unless `--allow-cpu-adapter`; prints the adapter, driver and limits and the plan
//! (`--dry-run` stops there); then, within `--budget` (default 8 min):
//!
//! 1. `variants.csv`: every variant and whether this adapter runs it;
//! 2. `verify/<scene>/`: every variant against the CPU reference on two scenes;
//! 3. `study/`: E1, E4 and scaling from N ≈ 10³ up to the largest N whose GPU buffers fit
//!    (`plan::Plan::check_gpu`), all variants to N ≈ 10⁵ and the recomputed one-particle-per-thread
//!    variants above it (to ≥ 10⁷ where the adapter allows), merged from the two sweeps by
//!    `report::merge`; the CPU rows stop at `CPU_MAX_N`;
//! 4. `validation/`: the impact case at full resolution for three angles (`sphlab validate`).
//!
//! Everything lands under `reports/gpu/<adapter>/` with `provenance.json` (adapter, driver,
//! date, commit).

use super::{report, StudyOptions};
use crate::gpu::variant::{Precision, VariantSpec};
use crate::gpu::GpuContext;
use crate::provenance::{GpuInfo, Provenance};
use crate::scene::builtin::builtin;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// CPU rows of the preset only up to this many particles.
pub const CPU_MAX_N: usize = 200_000;
/// Scaling resolutions of the preset (N ≈ nx²: 10³ … 4·10⁷), cut to what fits.
pub const SCALING_NX: [u32; 9] = [32, 100, 316, 1000, 1414, 2000, 3162, 4472, 6324];
/// Above this resolution only [`large_variants`] run.
pub const ALL_VARIANTS_MAX_NX: u32 = 316;
/// Scenes of the verification.
pub const VERIFY_SCENES: [&str; 2] = ["oscillating-drop", "sessile-90"];
/// Steps of the verification.
pub const VERIFY_STEPS: u64 = 20;
/// Impact angles at full resolution (run ids of `validate impact`).
pub const IMPACT_RUNS: [&str; 3] = ["theta50", "theta90", "theta160"];
/// Share of the budget kept for the impact validation.
pub const IMPACT_SHARE: f64 = 0.35;

/// Why the preset did not run: bad input or a refused adapter (exit 2), or a failure (exit 1).
#[derive(Debug)]
pub enum PresetError {
    /// Exit 2: a CPU adapter without `--allow-cpu-adapter`, no adapter, bad options.
    Refused(String),
    /// Exit 1: something failed while running.
    Failed(String),
}

/// The recomputed one-particle-per-thread variants (the thesis's best configuration), run to
/// the largest sizes.
pub fn large_variants() -> Vec<VariantSpec> {
    VariantSpec::all()
        .into_iter()
        .filter(|s| {
            s.to_string().contains(".thread.recomputed.") && s.search != crate::gpu::variant::SearchVariant::Direct
        })
        .collect()
}

/// A directory name from an adapter name (`NVIDIA H200` → `nvidia-h200`).
pub fn adapter_slug(name: &str) -> String {
    let s: String =
        name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '-' }).collect();
    let s = s.split('-').filter(|p| !p.is_empty()).collect::<Vec<_>>().join("-");
    if s.is_empty() {
        "adapter".into()
    } else {
        s
    }
}

/// The scaling resolutions whose host plan and GPU buffers fit this adapter.
pub fn fitting_sizes(ctx: &GpuContext) -> Vec<u32> {
    let device = crate::plan::gpu::DeviceLimits::of(ctx, None);
    let limits = crate::plan::Limits::default();
    SCALING_NX
        .iter()
        .copied()
        .filter(|&nx| {
            let Ok(scene) = super::study_scene_with(nx, &[]) else { return false };
            crate::plan::Plan::new(&scene, 8, false).check(&limits).is_ok()
                && crate::plan::Plan::new(&scene, 4, true).check_gpu(&device).is_ok()
        })
        .collect()
}

/// Adapter, driver and the limits that bound the sizes.
pub fn describe_adapter(ctx: &GpuContext) -> String {
    let i = &ctx.adapter_info;
    let l = &ctx.limits;
    format!(
        "adapter: {} ({:?}, {:?}); driver: {} {}\nlimits: max_buffer_size {}, max_storage_buffer_binding_size {}, \
         max_compute_workgroups_per_dimension {}; features: {:?}",
        i.name,
        i.backend,
        i.device_type,
        i.driver,
        i.driver_info,
        l.max_buffer_size,
        l.max_storage_buffer_binding_size,
        l.max_compute_workgroups_per_dimension,
        ctx.features
    )
}

/// The two study sweeps of the preset (all variants to [`ALL_VARIANTS_MAX_NX`], the large
/// variants above), each with its output directory under `dir`.
fn sweeps(dir: &Path, sizes: &[u32], budget_s: f64) -> Vec<StudyOptions> {
    let small: Vec<u32> = sizes.iter().copied().filter(|&n| n <= ALL_VARIANTS_MAX_NX).collect();
    let large: Vec<u32> = sizes.iter().copied().filter(|&n| n > ALL_VARIANTS_MAX_NX).collect();
    let mut experiments: Vec<String> = super::EXPERIMENTS.iter().map(|s| s.to_string()).collect();
    experiments.retain(|e| e != "scaling");
    experiments.push("scaling".into());
    let all = StudyOptions {
        experiments,
        sizes: small,
        cpu_max_n: Some(CPU_MAX_N),
        budget_s: Some(budget_s * 0.5),
        out: dir.join("study-all-variants"),
        ..Default::default()
    };
    let big = StudyOptions {
        experiments: vec!["scaling".into()],
        sizes: large,
        variants: large_variants(),
        cpu_max_n: Some(CPU_MAX_N),
        budget_s: Some(budget_s * 0.5),
        out: dir.join("study-large"),
        ..Default::default()
    };
    if big.sizes.is_empty() {
        vec![all]
    } else {
        vec![all, big]
    }
}

/// Runs the preset (or prints its plan with `dry_run`); `out_root` is `reports/gpu`.
pub fn run(out_root: &Path, budget_s: f64, allow_cpu_adapter: bool, dry_run: bool) -> Result<PathBuf, PresetError> {
    let t0 = Instant::now();
    let ctx = GpuContext::new()
        .map(Arc::new)
        .map_err(|e| PresetError::Refused(format!("--preset gpu: no GPU adapter ({e})")))?;
    let info = &ctx.adapter_info;
    if info.device_type == wgpu::DeviceType::Cpu && !allow_cpu_adapter {
        return Err(PresetError::Refused(format!(
            "--preset gpu: the adapter `{}` is a CPU adapter (device type Cpu, e.g. lavapipe), not a GPU; its times \
             are not GPU times. Pass --allow-cpu-adapter to run the preset on it anyway",
            info.name
        )));
    }
    let dir = out_root.join(adapter_slug(&info.name));
    let sizes = fitting_sizes(&ctx);
    let study_budget = budget_s * (1.0 - IMPACT_SHARE);
    let mut plan_text = String::new();
    let _ = writeln!(plan_text, "{}", describe_adapter(&ctx));
    let _ = writeln!(plan_text, "output: {}", dir.display());
    let _ = writeln!(plan_text, "budget: {budget_s:.0} s ({:.0} s study, the rest verify and impact)", study_budget);
    let _ = writeln!(plan_text, "1. variants.csv: {} variants", VariantSpec::all().len());
    let _ = writeln!(plan_text, "2. verify every variant on {} ({VERIFY_STEPS} steps)", VERIFY_SCENES.join(" and "));
    let sw = sweeps(&dir, &sizes, study_budget);
    for (k, s) in sw.iter().enumerate() {
        let vs = if s.variants.is_empty() {
            "all variants".to_string()
        } else {
            s.variants.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", ")
        };
        let _ = writeln!(
            plan_text,
            "3.{}: study {} at nx {:?} with {vs}; CPU rows to N = {CPU_MAX_N}; budget {:.0} s",
            k + 1,
            s.experiments.join(","),
            s.sizes,
            s.budget_s.unwrap_or(0.0)
        );
    }
    let _ = writeln!(plan_text, "4. validate impact at full resolution: {}", IMPACT_RUNS.join(", "));
    eprint!("{plan_text}");
    if dry_run {
        for s in &sw {
            let o = StudyOptions { dry_run: true, ..s.clone() };
            super::run_study_on(&o, Some(&ctx), Instant::now()).map_err(PresetError::Failed)?;
        }
        return Ok(dir);
    }
    let fail = |e: String| PresetError::Failed(e);
    std::fs::create_dir_all(&dir).map_err(|e| fail(format!("{}: {e}", dir.display())))?;
    std::fs::write(dir.join("plan.txt"), &plan_text).map_err(|e| fail(e.to_string()))?;
    let gpu = GpuInfo::from_adapter(info);
    let prov = Provenance::new("study --preset gpu", Some(gpu), crate::provenance::STUDY_UNITS);
    crate::output::write_json(dir.join("provenance.json"), &prov).map_err(|e| fail(e.to_string()))?;
    // 1. variants
    let mut csv = String::from("variant,status\n");
    for v in VariantSpec::all() {
        let st = v
            .support(&ctx)
            .map_or_else(|e| format!("\"unsupported: {}\"", e.replace('"', "'")), |()| "supported".into());
        let _ = writeln!(csv, "{v},{st}");
    }
    std::fs::write(dir.join("variants.csv"), csv).map_err(|e| fail(e.to_string()))?;
    // 2. verify
    for name in VERIFY_SCENES {
        let scene = builtin(name).expect("built-in");
        let verifier = crate::verify::Verifier::new(&scene, VERIFY_STEPS, false);
        let reports: Vec<_> = VariantSpec::all()
            .into_iter()
            .map(|v| {
                let r = verifier.variant(&ctx, v);
                eprintln!("verify {name} {} {}", r.variant, r.status);
                r
            })
            .collect();
        crate::verify::write_outputs(&dir.join("verify").join(name), &ctx.describe(), &scene, &reports)
            .map_err(fail)?;
    }
    // 3. study (two sweeps, merged), within what is left of the study's share
    let mut outs = Vec::new();
    for mut s in sw {
        let left = study_budget - t0.elapsed().as_secs_f64();
        s.budget_s = Some(s.budget_s.unwrap_or(left).min(left).max(1.0));
        super::run_study_on(&s, Some(&ctx), Instant::now()).map_err(fail)?;
        outs.push(s.out.clone());
    }
    report::merge(&outs, &dir.join("study")).map_err(fail)?;
    // 4. impact at full resolution, three angles, on the default GPU variant
    let vopts = crate::validate::ValidateOptions {
        backend: crate::backend::BackendId::Gpu(VariantSpec { precision: Precision::F32, ..VariantSpec::default() }),
        out: dir.join("validation"),
        only: IMPACT_RUNS.iter().map(|s| s.to_string()).collect(),
        full_impact: true,
        quiet: true,
        ..Default::default()
    };
    if let Err(e) = crate::validate::run_case("impact", &vopts) {
        eprintln!("preset: impact validation failed: {e}");
    }
    eprintln!("preset: {:.0} s of {budget_s:.0} s; report in {}", t0.elapsed().as_secs_f64(), dir.display());
    Ok(dir)
}
