//! `sphlab stability`: its arguments, parsed into [`StabilityOptions`] (a bad value is bad input
//! naming the option and what it accepts), then the sweep and the report.

use super::common::load_scene;
use clap::Args;
use sphlab::backend_id::BackendId;
use sphlab::error::Error;
use sphlab::gpu::GpuContext;
use sphlab::stability::{backend, StabilityOptions, BACKENDS};
use std::path::PathBuf;
use std::sync::Arc;

/// Arguments of `sphlab stability`.
#[derive(Args, Debug)]
pub struct StabilityArgs {
    /// Built-in scene name or a scene TOML file.
    #[arg(default_value = "oscillating-drop")]
    pub scene: String,
    /// Override a scene field by its TOML path (applied before the sweep).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Backends/precisions: comma-separated from cpu.f64, cpu.f32, gpu.f32, gpu.f64 (gpu.* use
    /// the default variant in that precision), or `all`.
    #[arg(long, default_value = "cpu.f64,gpu.f32")]
    pub backend: String,
    /// GPU variant ids (comma-separated) to map besides --backend.
    #[arg(long, default_value = "")]
    pub variants: String,
    /// dt as multiples of the tightest limit at load.
    #[arg(long, default_value = "0.25,0.5,1,2,4,8")]
    pub dt_factors: String,
    /// Density ratios ρ_0/ρ_1 (two-phase scenes; `none` to skip the axis).
    #[arg(long, default_value = "10,100,1000")]
    pub density_ratios: String,
    /// Viscosity ratios μ_0/μ_1 (two-phase scenes; `none` to skip the axis).
    #[arg(long, default_value = "10,100")]
    pub viscosity_ratios: String,
    /// Resolutions (domain.nx) besides the scene's own (`none` to skip the axis).
    #[arg(long, default_value = "none")]
    pub resolutions: String,
    /// Kernels as kind:h_ratio, e.g. `cubic-spline:1.2,wendland-c2:1.3` (`none` to skip).
    #[arg(long, default_value = "none")]
    pub kernels: String,
    /// Steps per point.
    #[arg(long, default_value_t = 100)]
    pub steps: u64,
    /// A sampled state every N steps.
    #[arg(long, default_value_t = 10)]
    pub sample: u64,
    /// Largest |ρ/ρ0 − 1| of a stable state.
    #[arg(long, default_value_t = 0.2)]
    pub density_cap: f64,
    /// Start at rest (no initial velocities): the largest speed is then the spurious speed.
    #[arg(long)]
    pub at_rest: bool,
    /// Run only shard i of n (`i/n`, 0 ≤ i < n): every n-th point.
    #[arg(long, default_value = "0/1")]
    pub shard: String,
    /// Stop starting points after this long (seconds, or `90s`, `8m`, `1h`).
    #[arg(long, value_parser = sphlab::sweep::parse_duration)]
    pub budget: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "reports/stability")]
    pub out: PathBuf,
    /// No console lines.
    #[arg(long)]
    pub quiet: bool,
}

fn list<T: std::str::FromStr>(opt: &str, text: &str, ok: impl Fn(&T) -> bool, range: &str) -> Result<Vec<T>, String> {
    if text.trim() == "none" || text.trim().is_empty() {
        return Ok(vec![]);
    }
    text.split(',')
        .map(|s| s.trim().parse::<T>().ok().filter(|v| ok(v)).ok_or_else(|| format!("--{opt}: `{s}` is not {range}")))
        .collect()
}

/// The options of `a` (without the scene), or the message of a bad value.
fn options(a: &StabilityArgs) -> Result<StabilityOptions, String> {
    let mut targets = Vec::new();
    let all = BACKENDS.join(",");
    let backends = if a.backend == "all" { all.as_str() } else { a.backend.as_str() };
    for b in backends.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let id = backend(b).ok_or_else(|| format!("--backend: `{b}` is not one of {}, all", BACKENDS.join(", ")))?;
        targets.push(id);
    }
    for v in a.variants.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        targets.push(BackendId::Gpu(v.parse().map_err(|e: String| format!("--variants: {e}"))?));
    }
    if targets.is_empty() {
        return Err(format!("--backend: name at least one backend ({})", BACKENDS.join(", ")));
    }
    let pos = |x: &f64| x.is_finite() && *x > 0.0;
    let dt_factors = list("dt-factors", &a.dt_factors, pos, "a positive number")?;
    if dt_factors.is_empty() {
        return Err("--dt-factors: give at least one positive factor".into());
    }
    let mut kernels = Vec::new();
    if a.kernels.trim() != "none" {
        for k in a.kernels.split(',') {
            let (kind, h) = k.trim().split_once(':').ok_or(format!("--kernels: `{k}` is not kind:h_ratio"))?;
            let h: f64 = h.parse().ok().filter(pos).ok_or(format!("--kernels: h_ratio in `{k}` is not positive"))?;
            let probe: Result<sphlab::physics::kernel::KernelKind, _> = toml::Value::String(kind.into()).try_into();
            probe.map_err(|_| format!("--kernels: unknown kernel `{kind}`"))?;
            kernels.push((kind.to_string(), h));
        }
    }
    let shard = sphlab::sweep::Shard::parse(&a.shard)?;
    if a.steps == 0 || a.steps > 1_000_000 {
        return Err(format!("--steps: {} is not in 1..=1000000", a.steps));
    }
    if a.sample == 0 {
        return Err("--sample: must be at least 1".into());
    }
    if !(a.density_cap > 0.0) {
        return Err("--density-cap: must be positive".into());
    }
    if a.budget.is_some_and(|b| !(b > 0.0)) {
        return Err("--budget: must be a positive number of seconds".into());
    }
    Ok(StabilityOptions {
        dt_factors,
        density_ratios: list("density-ratios", &a.density_ratios, pos, "a positive ratio")?,
        viscosity_ratios: list("viscosity-ratios", &a.viscosity_ratios, pos, "a positive ratio")?,
        resolutions: list(
            "resolutions",
            &a.resolutions,
            |n: &u32| (4..=20_000).contains(n),
            "a resolution in 4..=20000",
        )?,
        kernels,
        targets,
        steps: a.steps,
        sample: a.sample,
        density_cap: a.density_cap,
        at_rest: a.at_rest,
        shard: (shard.index, shard.count),
        budget_s: a.budget,
    })
}

/// Loads the scene and checks the options (exit 2), runs the sweep and writes the report.
pub fn run(a: StabilityArgs) -> Result<(), Error> {
    let scene = load_scene(&a.scene, &a.sets)?;
    let o = options(&a).map_err(Error::Input)?;
    let wants_gpu = o.targets.iter().any(|t| matches!(t, BackendId::Gpu(_)));
    let gpu = if wants_gpu {
        GpuContext::new()
            .map(Arc::new)
            .map_err(|e| eprintln!("stability: no GPU adapter ({e}); GPU points not run"))
            .ok()
    } else {
        None
    };
    let sweep = sphlab::stability::sweep(&scene, &o, gpu.as_ref(), a.quiet);
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    sphlab::stability::report::write(&a.out, &scene, &o, &sweep, gpu.map(|g| g.describe()), &command)
        .map_err(Error::Failed)?;
    if !a.quiet {
        eprintln!(
            "stability: {} points, {} not run; report in {}",
            sweep.records.len(),
            sweep.not_run.len(),
            a.out.display()
        );
    }
    Ok(())
}
