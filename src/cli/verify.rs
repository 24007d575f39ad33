//! `sphlab verify`: every chosen GPU variant against the CPU reference, as a table or JSON
//! (and verify.csv / verify.json with `--out`); a disagreeing variant fails the check (exit 1).

use super::common::{check_out, gpu_variants, load_scene, print_json, with_provenance, LimitArgs};
use clap::Args;
use sphlab::error::Error;
use sphlab::provenance::{self, GpuInfo, Provenance};
use sphlab::verify::VariantReport;
use std::path::PathBuf;

#[derive(Args)]
pub struct VerifyArgs {
    /// Built-in scene name or a scene TOML file.
    #[arg(default_value = "oscillating-drop")]
    scene: String,
    /// `all` or a comma-separated list of variant ids.
    #[arg(long, default_value = "all")]
    variants: String,
    /// Steps for the observable comparison.
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u64).range(1..))]
    steps: u64,
    /// Override a scene field by its TOML path.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print JSON (the same document as verify.json) instead of the table.
    #[arg(long)]
    json: bool,
    /// Also run every stage alone on the CPU's inputs (pinpoints a disagreeing stage).
    #[arg(long)]
    per_stage: bool,
    /// Write verify.csv and verify.json here (rewritten after every variant).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Wall-time budget (e.g. 90s, 2m): variants not started when it is spent are listed as
    /// `skipped`.
    #[arg(long, value_parser = sphlab::sweep::parse_duration)]
    budget: Option<f64>,
    #[command(flatten)]
    limits: LimitArgs,
}

/// Checks the options, the scene and every variant's plan (exit 2), then verifies the variants
/// one by one.
pub fn run(a: VerifyArgs) -> Result<(), Error> {
    if let Some(dir) = &a.out {
        check_out("--out", dir)?;
    }
    let limits = a.limits.limits()?;
    let scene = load_scene(&a.scene, &a.sets)?;
    // The CPU f64 reference and a GPU variant run side by side: plan both.
    let plan = sphlab::resources::run_plan(&scene, 8, false);
    plan.check(&limits).map_err(Error::input)?;
    let specs = gpu_variants(&a.variants)?;
    let ctx = sphlab::gpu::GpuContext::new()
        .map(|c| {
            std::sync::Arc::new(match limits.gpu_binding {
                Some(b) => c.with_binding_cap(b),
                None => c,
            })
        })
        .map_err(|e| Error::input(format!("no GPU adapter: {e}")))?;
    let lim = sphlab::gpu::plan::DeviceLimits::of(&ctx, limits.gpu_memory);
    for spec in &specs {
        sphlab::resources::run_plan(&scene, 4, true).for_variant(spec).check_gpu(&lim).map_err(Error::input)?;
    }
    if !a.json {
        eprintln!("adapter: {}; scene {}; {} variants; {} steps", ctx.describe(), scene.name, specs.len(), a.steps);
    }
    let mut reports = Vec::new();
    let verifier = sphlab::verify::Verifier::new(&scene, a.steps, a.per_stage);
    let started = std::time::Instant::now();
    let prov = Provenance::new("verify", Some(GpuInfo::from_adapter(&ctx.adapter_info)), provenance::VERIFY_UNITS);
    // One document for --json and verify.json.
    let doc = |reports: &[VariantReport]| {
        with_provenance(serde_json::json!({"scene": scene.name, "steps": a.steps, "variants": reports}), &prov)
    };
    for spec in specs {
        let r = match a.budget {
            Some(b) if started.elapsed().as_secs_f64() > b => {
                VariantReport::skipped(spec, format!("not run: the --budget of {b:.0} s was spent"))
            }
            _ => verifier.variant(&ctx, spec),
        };
        if !a.json {
            eprintln!("{} {}", r.variant, r.status);
        }
        reports.push(r);
        if let Some(dir) = &a.out {
            sphlab::verify::write_outputs(dir, &ctx.describe(), &scene, &reports)
                .and_then(|()| {
                    sphlab::output::write_json(dir.join("verify.json"), &doc(&reports)).map_err(|e| e.to_string())
                })
                .map_err(Error::Failed)?;
        }
    }
    let failed = reports.iter().any(|r| r.status == "FAIL" || r.status == "error");
    if a.json {
        print_json(&doc(&reports));
    } else {
        print!("{}", sphlab::verify::format_table(&reports));
    }
    // The table (or the JSON) says which variant failed.
    if failed {
        Err(Error::CheckFailed(String::new()))
    } else {
        Ok(())
    }
}
