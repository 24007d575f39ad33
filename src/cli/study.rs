//! `sphlab study`: the timing study's arguments, the `--preset gpu` branch, and the run of the
//! study whose options [`super::study_options`] checks and builds.

use super::common::{check_out, gpu_context, LimitArgs};
use clap::{Args, ValueEnum};
use sphlab::error::Error;
use sphlab::provenance::{self, GpuInfo, Provenance};
use sphlab::study::preset::{self, PresetOptions};
use std::path::PathBuf;

/// Study experiments.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Experiment {
    /// Search × backend at 2,025 fluid particles.
    E1,
    /// Residency hybrids (stage groups on the CPU or GPU) at 2,025 fluid particles.
    E2,
    /// Subdomain budgets × the thesis's three configurations at 10,000 fluid particles.
    E3,
    /// Every GPU variant against the single-thread CPU at 10,000.
    E4,
    /// Time per step against N.
    Scaling,
    /// The legacy GPU engine against the current one at the E4 size (`--engine-nx`); only when named.
    Engine,
    /// e1, e2, e3, e4 and scaling (sphlab::study::EXPERIMENTS; not `engine`, which is unbudgeted).
    All,
}

/// Presets of `sphlab study`.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Preset {
    /// The full report of a GPU loan: variants, verify, E1–E4, scaling to the largest N, impact
    /// validation, under reports/gpu/<adapter>/ (refuses a CPU adapter).
    Gpu,
}

#[derive(Args)]
pub struct StudyArgs {
    /// Experiments (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "all")]
    pub experiments: Vec<Experiment>,
    /// Scaling resolutions (particles across the box).
    #[arg(long, default_value = "30,60,120")]
    pub sizes: String,
    /// Steps per device sync (K): the accuracy snapshot and each timed block.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub steps: u64,
    /// Timed blocks of K steps per backend (median, fastest and slowest are reported).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub repeats: u64,
    /// Warm-up wall time per backend before timing (e.g. 0.5, 0.5s, 2s).
    #[arg(long, default_value = "0.5", value_parser = parse_warmup)]
    pub warmup: f64,
    /// GPU variants: `all` or comma-separated ids.
    #[arg(long, default_value = "all")]
    pub variants: String,
    /// Workgroup sizes of the thread mapping's kernels (comma-separated, of 64, 128, 256):
    /// each thread variant is timed at each (ids `….wg128`, `….wg256`), a study axis.
    #[arg(long, default_value = "64")]
    pub workgroup_sizes: String,
    /// Override a field of every study scene by its TOML path.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// CPU rows only up to this many particles; above it GPU rows compare with the largest CPU
    /// size, scaled by N.
    #[arg(long)]
    pub cpu_max_n: Option<usize>,
    /// Run only part i of n of the sweep (`i/n`, 0 ≤ i < n; disjoint parts, merge with `sphlab report`).
    #[arg(long, default_value = "0/1")]
    pub shard: String,
    /// Wall-time budget (e.g. 90s, 8m): plan from a short probe, drop the largest sizes first.
    #[arg(long, value_parser = sphlab::sweep::parse_duration)]
    pub budget: Option<f64>,
    /// Print the plan (experiments, backends, sizes, estimated time) and stop.
    #[arg(long)]
    pub dry_run: bool,
    /// A preset: `gpu` runs the full report of a GPU loan (default budget 8m) under
    /// reports/gpu/<adapter>/.
    #[arg(long, value_enum)]
    pub preset: Option<Preset>,
    /// With --preset gpu: run even on a CPU adapter (lavapipe).
    #[arg(long)]
    pub allow_cpu_adapter: bool,
    /// Output directory (with --preset gpu: the root, default reports/gpu).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// E2 resolution (particles across the box; 45 = 2,025 fluid particles).
    #[arg(long, default_value_t = 45, value_parser = clap::value_parser!(u32).range(10..=200))]
    pub e2_nx: u32,
    /// E3 resolution (100 = 10,000 fluid particles).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(10..=400))]
    pub e3_nx: u32,
    /// E3 timed iterations per configuration and budget (thesis: 200).
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..))]
    pub e3_steps: u64,
    /// E3 particle budgets per subdomain (comma-separated, each ≥ 100).
    #[arg(long, default_value = "1500,3000,4500,6000")]
    pub e3_budgets: String,
    /// Resolution of the `engine` experiment (100 = the E4 size, 11,236 particles).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(10..=400))]
    pub engine_nx: u32,
    /// E4 resolutions (45 = the thesis's 2,025 fluid particles, 100 = 10,000).
    #[arg(long, value_delimiter = ',', default_value = "45,100", value_parser = clap::value_parser!(u32).range(10..=4000))]
    pub e4_sizes: Vec<u32>,
    /// The two resolutions the cost probe times (near the sweep's sizes: the largest sizes are
    /// then not extrapolated from small ones).
    #[arg(long, value_delimiter = ',', default_value = "16,32", num_args = 1, value_parser = clap::value_parser!(u32).range(10..=10_000))]
    pub probe_sizes: Vec<u32>,
    /// With --preset gpu: write DIR/gpu-report.tar.gz and DIR/summary.md, refreshed after every
    /// part (a kill loses at most the part in flight).
    #[arg(long, value_name = "DIR")]
    pub archive: Option<PathBuf>,
    #[command(flatten)]
    pub limits: LimitArgs,
}

/// `--warmup`: a duration of at least zero seconds.
fn parse_warmup(text: &str) -> Result<f64, String> {
    if text.trim().trim_end_matches('s').trim().parse::<f64>() == Ok(0.0) {
        return Ok(0.0);
    }
    sphlab::sweep::parse_duration(text).map_err(|e| e.replace("--budget", "--warmup"))
}

/// The preset, or the study; then the study's provenance next to its records.
pub fn run(a: StudyArgs) -> Result<(), Error> {
    if a.preset == Some(Preset::Gpu) {
        return run_preset(&a);
    }
    let opts = super::study_options::options(a)?;
    let r = sphlab::study::run_study(&opts)?;
    if opts.dry_run {
        return Ok(());
    }
    let gpu = gpu_context().ok().map(|c| GpuInfo::from_adapter(&c.adapter_info));
    let prov = Provenance::new("study", gpu, provenance::STUDY_UNITS);
    sphlab::output::write_json(opts.out.join("provenance.json"), &prov).map_err(Error::failed)?;
    eprintln!("{} records; {}", r.len(), opts.out.join("summary.md").display());
    Ok(())
}

/// `--preset gpu`: the output options checked (exit 2), then the preset.
fn run_preset(a: &StudyArgs) -> Result<(), Error> {
    let root = a.out.clone().unwrap_or_else(|| PathBuf::from("reports/gpu"));
    check_out("--out", &root)?;
    if let Some(dir) = &a.archive {
        check_out("--archive", dir)?;
    }
    preset::run(&PresetOptions {
        out_root: root,
        budget_s: a.budget.unwrap_or(preset::DEFAULT_BUDGET_S),
        allow_cpu_adapter: a.allow_cpu_adapter,
        dry_run: a.dry_run,
        archive: a.archive.clone(),
    })
}
