//! The `sphlab` command line: `run`, `scene`, `analytic`, `variants`, `verify`, `validate`,
//! `study`, `report` and `info`. Exit codes mean one thing each: 0 success, 2 bad input of any kind
//! (scene fields, options, `--out`, variant ids, a resource plan over the limits), always before
//! an output directory is created; 3 a numerical blow-up naming step and particle; 130 an
//! interrupt (Ctrl-C) after a final snapshot and `status: "interrupted"`; 1 anything else
//! (an output that cannot be written, a failed verification).

use clap::{Args, Parser, Subcommand, ValueEnum};
use sphlab::backend_id::BackendId;
use sphlab::gpu::variant::VariantSpec;
use sphlab::plan::{parse_bytes, Limits};
use sphlab::provenance::{self, GpuInfo, Provenance};
use sphlab::run::{RunError, RunOptions};
use sphlab::scene::{builtin, overrides::apply_overrides, Scene};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "sphlab",
    version = provenance::long_version(),
    about = "GPU-vs-CPU performance laboratory for 2D multiphase SPH"
)]
struct Cli {
    /// Worker threads of the CPU backend (default: every logical CPU); recorded in every output.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..=1024))]
    threads: Option<u16>,
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a scene (built-in name or TOML file) and write series.csv, snapshots and summary.json.
    Run(RunArgs),
    /// Built-in scenes.
    Scene {
        #[command(subcommand)]
        cmd: SceneCmd,
    },
    /// List the GPU variants, what each needs, and whether this adapter runs it.
    Variants {
        /// JSON output.
        #[arg(long)]
        json: bool,
        /// The GPU memory plan instead: bytes per particle of every variant, its total for N
        /// particles, and the largest N on this adapter and on a stated 140 GB adapter with
        /// 2 GiB bindings.
        #[arg(long, value_name = "N")]
        memory: Option<u64>,
        /// Device memory of this adapter for the plan (default: host memory on a CPU adapter).
        #[arg(long, value_parser = parse_bytes)]
        gpu_memory: Option<u64>,
    },
    /// Check GPU variants against the CPU reference (fields, stages, observables).
    Verify(VerifyArgs),
    /// The Chapter 6 timing study: E1 (search × backend), E4 (speedup), scaling; records.csv + summary.md.
    Study(StudyArgs),
    /// Merge the records of several study runs (shards, adapters) into one summary.md and plots.
    Report(ReportArgs),
    /// Validation cases against the thesis and analytic references (reports/validation).
    Validate(ValidateArgs),
    /// Stability map: dt factor × density/viscosity ratio × resolution × kernel per backend/precision.
    Stability(sphlab::stability::args::StabilityArgs),
    /// Analytic drop-spread models (thesis §5.1, Table 1).
    Analytic {
        #[command(subcommand)]
        cmd: AnalyticCmd,
    },
    /// Force balance of a run's saved state: each fluid particle's pair forces split by term
    /// (pressure, viscous, surface) and partner (same phase, other phase, wall), summed in a
    /// window around the right contact point, by row (CPU f64, one evaluation).
    Forces(ForcesArgs),
    /// The machine: build commit, CPU and threads, memory, every GPU adapter with its features and limits.
    Info {
        /// JSON output.
        #[arg(long)]
        json: bool,
    },
}

/// Working precision of the CPU backends.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum Precision {
    F64,
    F32,
}

impl Precision {
    fn as_str(self) -> &'static str {
        match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
        }
    }
}

/// CPU neighbour search.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum Search {
    /// All pairs, O(N²).
    Direct,
    /// Uniform cell grid rebuilt every evaluation.
    Cells,
    /// Tracking lists with a skin (thesis §6.3).
    Tracking,
}

impl Search {
    fn as_str(self) -> &'static str {
        match self {
            Search::Direct => "direct",
            Search::Cells => "cells",
            Search::Tracking => "tracking",
        }
    }
}

/// Study experiments.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum Experiment {
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

/// Validation cases.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum Case {
    Oscillation,
    #[value(name = "sessile-90")]
    Sessile90,
    #[value(name = "relax-60")]
    Relax60,
    Convergence,
    Impact,
    Spurious,
    SpeedVsError,
    All,
}

/// Analytic spread models.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum Model {
    All,
    Axisym,
    A,
    B,
    C,
}

/// `--max-particles` and `--max-memory`: the limits of the resource plan.
#[derive(Args)]
struct LimitArgs {
    /// Refuse scenes of more particles (fluid + wall) than this (default and most: 2^28 − 1).
    #[arg(long)]
    max_particles: Option<u64>,
    /// Refuse scenes whose planned host memory exceeds this (e.g. 4G, 512M); the machine's
    /// limits apply too (80% of MemAvailable, ulimit -v, the cgroup's memory.max): the smallest binds.
    #[arg(long, value_parser = parse_bytes)]
    max_memory: Option<u64>,
    /// Device memory of the GPU for its memory plan (e.g. 80G; default: host memory on a CPU
    /// adapter such as lavapipe, else unknown and only the per-buffer limits are checked).
    #[arg(long, value_parser = parse_bytes)]
    gpu_memory: Option<u64>,
}

impl LimitArgs {
    fn limits(&self) -> Result<Limits, String> {
        Limits::with(self.max_particles, self.max_memory)?.with_gpu_memory(self.gpu_memory)
    }
}

#[derive(Args)]
struct RunArgs {
    /// Built-in scene name (see `sphlab scene list`) or a scene TOML file.
    #[arg(default_value = "oscillating-drop")]
    scene: String,
    /// cpu (all cores), cpu1 (one thread) or gpu.
    #[arg(long, default_value = "cpu")]
    backend: String,
    /// GPU variant id (see `sphlab variants`); only with --backend gpu.
    #[arg(long)]
    variant: Option<String>,
    /// Precision of the CPU backends (default f64); a GPU variant's is part of its id.
    #[arg(long, value_enum)]
    precision: Option<Precision>,
    /// End time (overrides the scene's time.t_end).
    #[arg(long, conflicts_with = "steps")]
    t_end: Option<f64>,
    /// Run exactly N steps.
    #[arg(long)]
    steps: Option<u64>,
    /// Override a scene field by its TOML path, e.g. `--set contact.theta_deg=60`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// A particle snapshot at every step that is a multiple of N (0: only the first and the last).
    #[arg(long, default_value_t = 1000)]
    every: u64,
    /// Also write VTK (.vtu + .pvd) snapshots (binary from 20,000 particles).
    #[arg(long)]
    vtk: bool,
    /// At most N steps per GPU submission (one readback each), cut at output steps; 0: 64.
    #[arg(long, default_value_t = 0)]
    steps_per_submit: u64,
    /// CPU neighbour search (default cells); a GPU variant's is part of its id.
    #[arg(long, value_enum)]
    search: Option<Search>,
    /// No progress bar or console lines.
    #[arg(long)]
    quiet: bool,
    #[command(flatten)]
    limits: LimitArgs,
}

#[derive(Args)]
struct VerifyArgs {
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

/// Presets of `sphlab study`.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum Preset {
    /// The full report of a GPU loan: variants, verify, E1–E4, scaling to the largest N, impact
    /// validation, under reports/gpu/<adapter>/ (refuses a CPU adapter).
    Gpu,
}

#[derive(Args)]
struct StudyArgs {
    /// Experiments (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "all")]
    experiments: Vec<Experiment>,
    /// Scaling resolutions (particles across the box).
    #[arg(long, default_value = "30,60,120")]
    sizes: String,
    /// Steps per device sync (K): the accuracy snapshot and each timed block.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    steps: u64,
    /// Timed blocks of K steps per backend (median, fastest and slowest are reported).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=1000))]
    repeats: u64,
    /// Warm-up wall time per backend before timing (e.g. 0.5, 0.5s, 2s).
    #[arg(long, default_value = "0.5", value_parser = parse_warmup)]
    warmup: f64,
    /// GPU variants: `all` or comma-separated ids.
    #[arg(long, default_value = "all")]
    variants: String,
    /// Override a field of every study scene by its TOML path.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// CPU rows only up to this many particles; above it GPU rows compare with the largest CPU
    /// size, scaled by N.
    #[arg(long)]
    cpu_max_n: Option<usize>,
    /// Run only part i of n of the sweep (`i/n`, 0 ≤ i < n; disjoint parts, merge with `sphlab report`).
    #[arg(long, default_value = "0/1")]
    shard: String,
    /// Wall-time budget (e.g. 90s, 8m): plan from a short probe, drop the largest sizes first.
    #[arg(long, value_parser = sphlab::sweep::parse_duration)]
    budget: Option<f64>,
    /// Print the plan (experiments, backends, sizes, estimated time) and stop.
    #[arg(long)]
    dry_run: bool,
    /// A preset: `gpu` runs the full report of a GPU loan (default budget 8m) under
    /// reports/gpu/<adapter>/.
    #[arg(long, value_enum)]
    preset: Option<Preset>,
    /// With --preset gpu: run even on a CPU adapter (lavapipe).
    #[arg(long)]
    allow_cpu_adapter: bool,
    /// Output directory (with --preset gpu: the root, default reports/gpu).
    #[arg(long)]
    out: Option<PathBuf>,
    /// E2 resolution (particles across the box; 45 = 2,025 fluid particles).
    #[arg(long, default_value_t = 45, value_parser = clap::value_parser!(u32).range(10..=200))]
    e2_nx: u32,
    /// E3 resolution (100 = 10,000 fluid particles).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(10..=400))]
    e3_nx: u32,
    /// E3 timed iterations per configuration and budget (thesis: 200).
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..))]
    e3_steps: u64,
    /// E3 particle budgets per subdomain (comma-separated, each ≥ 100).
    #[arg(long, default_value = "1500,3000,4500,6000")]
    e3_budgets: String,
    /// Resolution of the `engine` experiment (100 = the E4 size, 11,236 particles).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(10..=400))]
    engine_nx: u32,
    /// E4 resolutions (45 = the thesis's 2,025 fluid particles, 100 = 10,000).
    #[arg(long, value_delimiter = ',', default_value = "45,100", value_parser = clap::value_parser!(u32).range(10..=4000))]
    e4_sizes: Vec<u32>,
    /// The two resolutions the cost probe times (near the sweep's sizes: the largest sizes are
    /// then not extrapolated from small ones).
    #[arg(long, value_delimiter = ',', default_value = "16,32", num_args = 1, value_parser = clap::value_parser!(u32).range(10..=10_000))]
    probe_sizes: Vec<u32>,
    /// With --preset gpu: write DIR/gpu-report.tar.gz and DIR/summary.md, refreshed after every
    /// part (a kill loses at most the part in flight).
    #[arg(long, value_name = "DIR")]
    archive: Option<PathBuf>,
    #[command(flatten)]
    limits: LimitArgs,
}

/// `--warmup`: a duration of at least zero seconds.
fn parse_warmup(text: &str) -> Result<f64, String> {
    if text.trim().trim_end_matches('s').trim().parse::<f64>() == Ok(0.0) {
        return Ok(0.0);
    }
    sphlab::sweep::parse_duration(text).map_err(|e| e.replace("--budget", "--warmup"))
}

#[derive(Args)]
struct ReportArgs {
    /// Study output directories (each with records.csv), e.g. the shards of one sweep or runs on
    /// several adapters.
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Output directory of the merged report.
    #[arg(long)]
    out: PathBuf,
}

#[derive(Args)]
struct ValidateArgs {
    /// The case.
    #[arg(value_enum)]
    case: Case,
    /// Coarse resolution and short times (seconds per case; direction and rough size only).
    #[arg(long)]
    quick: bool,
    /// cpu, cpu1 or gpu.
    #[arg(long, default_value = "cpu")]
    backend: String,
    /// GPU variant id; only with --backend gpu.
    #[arg(long)]
    variant: Option<String>,
    /// Precision of the CPU backends (default f64).
    #[arg(long, value_enum)]
    precision: Option<Precision>,
    /// Report directory.
    #[arg(long, default_value = "reports/validation")]
    out: PathBuf,
    /// Reuse finished runs of exactly the same scene and end time found in the report directory.
    #[arg(long)]
    reuse: bool,
    /// With --reuse: skip runs that have no finished output (they are listed as not run).
    #[arg(long, requires = "reuse")]
    skip_missing: bool,
    /// Run only these run ids (comma-separated, e.g. `nx45,nx65`); every other run is reused if
    /// finished, else skipped and listed.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// End time of the long sessile-90 / relax-60 / convergence runs (default: the thesis's 5).
    #[arg(long)]
    t_end: Option<f64>,
    /// Resolution of the long sessile-90 / relax-60 runs (default: the thesis's 65; p_b follows
    /// the scene's rule at that resolution: σ/Δx for sessile-90, max(11.25σ/R, 0.2314σ/Δx) for relax-60).
    #[arg(long)]
    nx_long: Option<u32>,
    /// Run the impact case at full resolution (hours per angle on a CPU).
    #[arg(long)]
    full_impact: bool,
    /// No console lines.
    #[arg(long)]
    quiet: bool,
}

#[derive(Args)]
struct ForcesArgs {
    /// A `sphlab run` output folder (its summary.json gives the scene).
    run_dir: PathBuf,
    /// Step of the snapshot `particles_<step>.csv` (default: the last).
    #[arg(long)]
    step: Option<u64>,
    /// Average the balances of the K snapshots ending at --step (or at the last).
    #[arg(long, default_value_t = 1, value_name = "K")]
    last: usize,
    /// x of the window's centre (default: the right contact point).
    #[arg(long)]
    at: Option<f64>,
    /// Half-width of the window, in Δx.
    #[arg(long, default_value_t = 6.0)]
    half_width: f64,
    /// Height of the window above the wall, in Δx.
    #[arg(long, default_value_t = 6.0)]
    height: f64,
    /// x of the two cuts (under the liquid, under the gas) whose wall-band tensions are
    /// measured, as X1,X2 (default: half-way to the contact point from either side).
    #[arg(long, value_delimiter = ',', num_args = 2)]
    cuts: Option<Vec<f64>>,
    /// Also write every fluid particle's split (18 components) to this CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
}

#[derive(Subcommand)]
enum SceneCmd {
    /// List the built-in scenes.
    List {
        /// JSON output.
        #[arg(long)]
        json: bool,
    },
    /// Print a built-in scene as TOML (edit it and pass the file to `sphlab run`).
    Show {
        /// Scene name.
        name: String,
    },
    /// Print the overrides (one `KEY=VALUE` a line, for `--set`) that start relax-60 at another
    /// contact angle: the cap of the half-disc's area meeting the wall at THETA (none at 90°).
    RelaxStart {
        /// Starting contact angle in degrees, in (0, 180).
        theta: f64,
    },
}

#[derive(Subcommand)]
enum AnalyticCmd {
    /// Maximum spread D_max/D0 of every model for one impact.
    Spread {
        /// Reynolds number ρV0D0/μ.
        #[arg(long)]
        re: f64,
        /// Weber number ρV0²D0/σ.
        #[arg(long)]
        we: f64,
        /// Contact angle in degrees.
        #[arg(long, conflicts_with = "theta_rad", required_unless_present = "theta_rad")]
        theta_deg: Option<f64>,
        /// Contact angle in radians.
        #[arg(long)]
        theta_rad: Option<f64>,
        /// The model.
        #[arg(long, value_enum, default_value = "all")]
        model: Model,
        /// JSON output (with the provenance envelope).
        #[arg(long)]
        json: bool,
    },
    /// The thesis's Table 1 beside sphlab's values, with the relative error of each cell.
    Table1 {
        /// JSON output (with the provenance envelope).
        #[arg(long)]
        json: bool,
    },
}

/// Loads a scene by built-in name or TOML path, then applies `--set` overrides.
fn load_scene(name: &str, sets: &[String]) -> Result<Scene, String> {
    let base = if let Some(s) = builtin::builtin(name) {
        s
    } else if Path::new(name).is_file() {
        let text = std::fs::read_to_string(name).map_err(|e| format!("cannot read scene file {name}: {e}"))?;
        Scene::from_toml(&text).map_err(|e| format!("{name}: {e}"))?
    } else if Path::new(name).exists() {
        return Err(format!("scene `{name}` is not a regular file"));
    } else {
        return Err(format!(
            "unknown scene `{name}`: not a built-in ({}) and no such file",
            builtin::BUILTIN.join(", ")
        ));
    };
    apply_overrides(&base, sets).map_err(|e| e.to_string())
}

fn fail(code: u8, msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {msg}");
    ExitCode::from(code)
}

/// Exit code and message of a run error.
fn run_failure(e: RunError, out: &Path) -> ExitCode {
    match e {
        e @ RunError::BlowUp(_) => fail(3, format!("{e}; outputs so far are in {}", out.display())),
        e @ RunError::Interrupted { .. } => fail(130, format!("{e} in {}", out.display())),
        e => fail(e.exit_code() as u8, e),
    }
}

/// Ctrl-C asks the running simulation to stop after its current step (final snapshot, summary
/// `interrupted`, exit 130); a second Ctrl-C exits at once. The `ctrlc` crate does this
/// portably in a few lines (a dedicated handler thread, no unsafe code here).
fn install_interrupt_handler() {
    let _ = ctrlc::set_handler(|| {
        if sphlab::run::request_interrupt() {
            std::process::exit(130);
        }
        eprintln!("\ninterrupt: stopping after this step (Ctrl-C again to quit at once)");
    });
}

/// `--out DIR` checked before anything else happens (exit 2 names the option).
fn check_out(opt: &str, dir: &Path) -> Result<(), String> {
    sphlab::output::check_out_dir(dir).map_err(|e| format!("{opt}: {e}"))
}

fn cmd_run(a: RunArgs) -> ExitCode {
    if let Err(e) = check_out("--out", &a.out) {
        return fail(2, e);
    }
    let limits = match a.limits.limits() {
        Ok(l) => l,
        Err(e) => return fail(2, e),
    };
    let backend = match BackendId::from_cli(
        &a.backend,
        a.variant.as_deref(),
        a.precision.map(Precision::as_str),
        a.search.map(Search::as_str),
    ) {
        Ok(b) => b,
        Err(e) => return fail(2, e),
    };
    let scene = match load_scene(&a.scene, &a.sets) {
        Ok(s) => s,
        Err(e) => return fail(2, e),
    };
    let opts = RunOptions {
        backend,
        t_end: a.t_end,
        steps: a.steps,
        out: a.out,
        every: a.every,
        vtk: a.vtk,
        quiet: a.quiet,
        limits,
        steps_per_submit: a.steps_per_submit,
    };
    install_interrupt_handler();
    match sphlab::run::run(&scene, &opts) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => run_failure(e, &opts.out),
    }
}

fn cmd_validate(a: ValidateArgs) -> ExitCode {
    use sphlab::validate::{self, ValidateError, ValidateOptions};
    if a.t_end.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
        return fail(2, "--t-end: must be a positive finite time");
    }
    if let Err(e) = check_out("--out", &a.out) {
        return fail(2, e);
    }
    let backend = match BackendId::from_cli(&a.backend, a.variant.as_deref(), a.precision.map(Precision::as_str), None)
    {
        Ok(b) => b,
        Err(e) => return fail(2, e),
    };
    let opts = ValidateOptions {
        quick: a.quick,
        backend,
        out: a.out,
        reuse: a.reuse,
        skip_missing: a.skip_missing,
        only: a.only,
        t_end_long: a.t_end,
        nx_long: a.nx_long,
        full_impact: a.full_impact,
        quiet: a.quiet,
    };
    install_interrupt_handler();
    let case = a.case.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default();
    let res = if case == "all" {
        validate::run_all(&opts).map(|r| r.len())
    } else {
        validate::run_case(&case, &opts).map(|_| 1)
    };
    match res {
        Ok(n) => {
            // Every run's summary.json carries its own envelope; this one is the report's.
            let prov =
                Provenance::new(format!("validate --backend {}", opts.backend), None, provenance::VALIDATE_UNITS);
            if let Err(e) = sphlab::output::write_json(opts.out.join("provenance.json"), &prov) {
                return fail(1, e);
            }
            if !opts.quiet {
                eprintln!("{n} case(s) written under {}", opts.out.display());
            }
            ExitCode::SUCCESS
        }
        Err(ValidateError::Run { err: RunError::Interrupted { .. }, id }) => fail(130, format!("run {id} interrupted")),
        Err(e @ ValidateError::Input(_)) => fail(2, e),
        Err(ValidateError::Run { err: e @ RunError::Input(_), id }) => fail(2, format!("run {id}: {e}")),
        Err(e) => fail(1, e),
    }
}

/// A JSON value with the provenance envelope added: objects get a `provenance` key, anything
/// else becomes `{"provenance": …, "result": …}`.
fn with_provenance(v: serde_json::Value, prov: &Provenance) -> serde_json::Value {
    let p = serde_json::to_value(prov).expect("provenance serialises");
    match v {
        serde_json::Value::Object(mut m) => {
            m.insert("provenance".into(), p);
            serde_json::Value::Object(m)
        }
        other => serde_json::json!({ "provenance": p, "result": other }),
    }
}

fn cmd_analytic(cmd: AnalyticCmd) -> ExitCode {
    use sphlab::analytic;
    let prov = || Provenance::new("analytic", None, provenance::ANALYTIC_UNITS);
    match cmd {
        AnalyticCmd::Spread { re, we, theta_deg, theta_rad, model, json } => {
            let theta = theta_rad.unwrap_or_else(|| theta_deg.unwrap_or(f64::NAN).to_radians());
            let r = match analytic::spread_all(re, we, theta) {
                Ok(r) => r,
                Err(e) => return fail(2, e),
            };
            if json {
                let v = serde_json::to_value(r).expect("serialisable");
                let v = match model {
                    Model::Axisym => serde_json::json!({"model": "axisym", "xi": r.axisym}),
                    Model::A => serde_json::json!({"model": "a", "xi": r.model_a}),
                    Model::B => serde_json::json!({"model": "b", "xi": r.model_b}),
                    Model::C => serde_json::json!({"model": "c", "xi": r.model_c}),
                    Model::All => v,
                };
                let v = with_provenance(v, &prov());
                println!("{}", serde_json::to_string_pretty(&v).expect("json"));
            } else {
                match model {
                    Model::Axisym => println!("D_max/D0 (axisymmetric) = {:.4}", r.axisym),
                    Model::A => println!("D_max/D0 (2D a) = {:.4}", r.model_a),
                    Model::B => println!("D_max/D0 (2D b) = {:.4}", r.model_b),
                    Model::C => println!("D_max/D0 (2D c, eq. 93) = {:.4}", r.model_c),
                    Model::All => print!("{}", analytic::format_spread(&r)),
                }
            }
            ExitCode::SUCCESS
        }
        AnalyticCmd::Table1 { json } => {
            let rows = analytic::table1_comparison();
            if json {
                let v = serde_json::json!({ "rows": rows });
                println!("{}", serde_json::to_string_pretty(&with_provenance(v, &prov())).expect("json"));
            } else {
                print!("{}", analytic::format_table1(&rows));
            }
            ExitCode::SUCCESS
        }
    }
}

fn gpu_context() -> Result<std::sync::Arc<sphlab::gpu::GpuContext>, String> {
    sphlab::gpu::GpuContext::new().map(std::sync::Arc::new).map_err(|e| e.to_string())
}

fn cmd_variants(json: bool) -> ExitCode {
    let ctx = gpu_context();
    let mut rows = Vec::new();
    for v in VariantSpec::all() {
        let status = match &ctx {
            Err(_) => "unknown: no adapter".to_string(),
            Ok(c) => match v.support(c) {
                Ok(()) => "supported".to_string(),
                Err(e) => format!("unsupported: {e}"),
            },
        };
        let needs: Vec<&str> = v.features().into_iter().map(|(_, name)| name).collect();
        rows.push((v.to_string(), needs, status));
    }
    if json {
        let gpu = ctx.as_ref().ok().map(|c| GpuInfo::from_adapter(&c.adapter_info));
        let variants: Vec<serde_json::Value> = rows
            .iter()
            .map(|(id, needs, status)| serde_json::json!({"id": id, "needs": needs, "status": status}))
            .collect();
        let doc = serde_json::json!({
            "adapter_error": ctx.as_ref().err(),
            "variants": variants,
        });
        let doc = with_provenance(doc, &Provenance::new("variants", gpu, &[]));
        println!("{}", serde_json::to_string_pretty(&doc).expect("json"));
        return ExitCode::SUCCESS;
    }
    match &ctx {
        Ok(c) => println!("adapter: {}", c.describe()),
        Err(e) => println!("adapter: none ({e})"),
    }
    for (id, needs, status) in rows {
        let needs = if needs.is_empty() { "-".to_string() } else { needs.join("+") };
        println!("{id:<44} needs {needs:<34} {status}");
    }
    ExitCode::SUCCESS
}

/// `sphlab variants --memory N`: the GPU memory plan of every variant (`plan::gpu`), cells per
/// particle as in `oscillating-drop` at nx = 300.
fn cmd_variants_memory(n: u64, gpu_memory: Option<u64>, json: bool) -> ExitCode {
    use sphlab::gpu::plan::{bytes_per_particle, max_particles, DeviceLimits, GpuPlan};
    use sphlab::plan::{fmt_bytes, HARD_MAX_PARTICLES};
    if n == 0 || n > HARD_MAX_PARTICLES {
        return fail(2, format!("--memory: N must lie in [1, {HARD_MAX_PARTICLES}], got {n}"));
    }
    let scene = apply_overrides(&builtin::builtin("oscillating-drop").expect("built-in"), &["domain.nx=300".into()])
        .expect("valid override");
    let p = sphlab::resources::run_plan(&scene, 4, true);
    let cpp = p.cells / p.n_total;
    let ctx = gpu_context();
    let here = ctx.as_ref().ok().map(|c| DeviceLimits::of(c, gpu_memory));
    let big = DeviceLimits::stated(140_000_000_000, 2 << 30, "stated: 140 GB device memory, 2 GiB per buffer");
    let mut rows = Vec::new();
    for v in VariantSpec::all() {
        let plan = GpuPlan::new(&v, n, (n as f64 * cpp).ceil() as u64);
        let fits = here.as_ref().map(|l| plan.check(l));
        rows.push(serde_json::json!({
            "id": v.to_string(),
            "bytes_per_particle": bytes_per_particle(&v, cpp),
            "total_bytes": plan.total_bytes,
            "largest_buffer": plan.largest().name,
            "largest_buffer_bytes": plan.largest().bytes,
            "fits_here": fits.as_ref().map(|r| r.is_ok()),
            "refusal_here": fits.and_then(|r| r.err()),
            "max_n_here": here.as_ref().map(|l| max_particles(&v, cpp, l, HARD_MAX_PARTICLES)),
            "max_n_stated": max_particles(&v, cpp, &big, HARD_MAX_PARTICLES),
        }));
    }
    if json {
        let doc = serde_json::json!({
            "n": n, "cells_per_particle": cpp, "adapter_error": ctx.as_ref().err(),
            "limits_here": here, "limits_stated": big, "variants": rows,
        });
        let gpu = ctx.as_ref().ok().map(|c| GpuInfo::from_adapter(&c.adapter_info));
        println!(
            "{}",
            serde_json::to_string_pretty(&with_provenance(doc, &Provenance::new("variants", gpu, &[]))).expect("json")
        );
        return ExitCode::SUCCESS;
    }
    match (&ctx, &here) {
        (Ok(c), Some(l)) => println!(
            "adapter: {}; per buffer {} (max_buffer_size {}, max_storage_buffer_binding_size {}); device memory {} ({})",
            c.describe(),
            fmt_bytes(l.buffer_cap() as f64),
            l.max_buffer_size,
            l.max_binding_size,
            l.memory.map_or("unknown".into(), |m| fmt_bytes(m as f64)),
            l.memory_source
        ),
        _ => println!("adapter: none ({})", ctx.as_ref().err().cloned().unwrap_or_default()),
    }
    println!("stated adapter: {}; cells per particle {cpp:.4} (oscillating-drop)", big.memory_source);
    println!(
        "{:<44} {:>9} {:>12} {:>22} {:>12} {:>12}",
        "variant",
        "B/part.",
        format!("N={n}"),
        "largest buffer",
        "max N here",
        "max N 140G"
    );
    for r in rows {
        let s = |k: &str| r[k].as_str().unwrap_or("").to_string();
        let u = |k: &str| r[k].as_u64().map_or("-".into(), |x| x.to_string());
        let largest =
            format!("{} {}", s("largest_buffer"), fmt_bytes(r["largest_buffer_bytes"].as_f64().unwrap_or(0.0)));
        println!(
            "{:<44} {:>9.1} {:>12} {:>22} {:>12} {:>12}",
            s("id"),
            r["bytes_per_particle"].as_f64().unwrap_or(0.0),
            fmt_bytes(r["total_bytes"].as_f64().unwrap_or(0.0)),
            largest,
            u("max_n_here"),
            u("max_n_stated")
        );
    }
    ExitCode::SUCCESS
}

/// GPU variant ids of `--variants` (`all` or comma-separated); a CPU id, a bad id or an empty
/// list is an error naming the flag.
fn gpu_variants(list: &str) -> Result<Vec<VariantSpec>, String> {
    if list == "all" {
        return Ok(VariantSpec::all());
    }
    let mut v = Vec::new();
    for id in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        match id.parse::<BackendId>() {
            Ok(BackendId::Gpu(s)) => v.push(s),
            Ok(cpu) => return Err(format!("--variants: `{cpu}` is a CPU backend, not a GPU variant")),
            Err(e) => return Err(format!("--variants: {e}")),
        }
    }
    if v.is_empty() {
        return Err("--variants: give `all` or at least one variant id".into());
    }
    Ok(v)
}

fn cmd_verify(a: VerifyArgs) -> ExitCode {
    if let Some(dir) = &a.out {
        if let Err(e) = check_out("--out", dir) {
            return fail(2, e);
        }
    }
    let limits = match a.limits.limits() {
        Ok(l) => l,
        Err(e) => return fail(2, e),
    };
    let scene = match load_scene(&a.scene, &a.sets) {
        Ok(s) => s,
        Err(e) => return fail(2, e),
    };
    // The CPU f64 reference and a GPU variant run side by side: plan both.
    let plan = sphlab::resources::run_plan(&scene, 8, false);
    if let Err(e) = plan.check(&limits) {
        return fail(2, e);
    }
    let specs = match gpu_variants(&a.variants) {
        Ok(v) => v,
        Err(e) => return fail(2, e),
    };
    let ctx = match gpu_context() {
        Ok(c) => c,
        Err(e) => return fail(2, format!("no GPU adapter: {e}")),
    };
    let lim = sphlab::gpu::plan::DeviceLimits::of(&ctx, limits.gpu_memory);
    for spec in &specs {
        if let Err(e) = sphlab::resources::run_plan(&scene, 4, true).for_variant(spec).check_gpu(&lim) {
            return fail(2, e);
        }
    }
    if !a.json {
        eprintln!("adapter: {}; scene {}; {} variants; {} steps", ctx.describe(), scene.name, specs.len(), a.steps);
    }
    let mut reports = Vec::new();
    let verifier = sphlab::verify::Verifier::new(&scene, a.steps, a.per_stage);
    let started = std::time::Instant::now();
    let prov = Provenance::new("verify", Some(GpuInfo::from_adapter(&ctx.adapter_info)), provenance::VERIFY_UNITS);
    // One document for --json and verify.json.
    let doc = |reports: &[sphlab::verify::VariantReport]| {
        with_provenance(serde_json::json!({"scene": scene.name, "steps": a.steps, "variants": reports}), &prov)
    };
    for spec in specs {
        let r = match a.budget {
            Some(b) if started.elapsed().as_secs_f64() > b => {
                sphlab::verify::VariantReport::skipped(spec, format!("not run: the --budget of {b:.0} s was spent"))
            }
            _ => verifier.variant(&ctx, spec),
        };
        if !a.json {
            eprintln!("{} {}", r.variant, r.status);
        }
        reports.push(r);
        if let Some(dir) = &a.out {
            let written = sphlab::verify::write_outputs(dir, &ctx.describe(), &scene, &reports).and_then(|()| {
                sphlab::output::write_json(dir.join("verify.json"), &doc(&reports)).map_err(|e| e.to_string())
            });
            if let Err(e) = written {
                return fail(1, e);
            }
        }
    }
    let failed = reports.iter().any(|r| r.status == "FAIL" || r.status == "error");
    let doc = doc(&reports);
    if a.json {
        println!("{}", serde_json::to_string_pretty(&doc).expect("json"));
    } else {
        print!("{}", sphlab::verify::format_table(&reports));
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

fn cmd_study(a: StudyArgs) -> ExitCode {
    if a.preset == Some(Preset::Gpu) {
        let root = a.out.clone().unwrap_or_else(|| PathBuf::from("reports/gpu"));
        if let Err(e) = check_out("--out", &root) {
            return fail(2, e);
        }
        if let Some(dir) = &a.archive {
            if let Err(e) = check_out("--archive", dir) {
                return fail(2, e);
            }
        }
        let opts = sphlab::study::preset::PresetOptions {
            out_root: root,
            budget_s: a.budget.unwrap_or(sphlab::study::preset::DEFAULT_BUDGET_S),
            allow_cpu_adapter: a.allow_cpu_adapter,
            dry_run: a.dry_run,
            archive: a.archive.clone(),
        };
        return match sphlab::study::preset::run(&opts) {
            Ok(code) => ExitCode::from(code),
            Err(sphlab::study::preset::PresetError::Refused(e)) => fail(2, e),
            Err(sphlab::study::preset::PresetError::Failed(e)) => fail(1, e),
        };
    }
    if a.allow_cpu_adapter {
        return fail(2, "--allow-cpu-adapter: applies only to --preset gpu");
    }
    if a.archive.is_some() {
        return fail(2, "--archive: applies only to --preset gpu");
    }
    let probe_sizes = match a.probe_sizes.as_slice() {
        &[p, q] if p < q => [p, q],
        other => return fail(2, format!("--probe-sizes: two increasing resolutions, got {other:?}")),
    };
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("reports/study"));
    if let Err(e) = check_out("--out", &out) {
        return fail(2, e);
    }
    let limits = match a.limits.limits() {
        Ok(l) => l,
        Err(e) => return fail(2, e),
    };
    let shard = match sphlab::sweep::Shard::parse(&a.shard) {
        Ok(s) => s,
        Err(e) => return fail(2, e),
    };
    let experiments: Vec<String> = if a.experiments.contains(&Experiment::All) {
        let named = a.experiments.contains(&Experiment::Engine).then_some("engine");
        sphlab::study::EXPERIMENTS.iter().copied().chain(named).map(|s| s.to_string()).collect()
    } else {
        a.experiments.iter().filter_map(|e| e.to_possible_value()).map(|v| v.get_name().to_string()).collect()
    };
    let (mut sizes, mut earlier) = (Vec::new(), 0.0);
    for s in a.sizes.split(',') {
        let n = match s.trim().parse::<u32>() {
            Ok(n) if n >= 10 => n,
            _ => return fail(2, format!("--sizes: `{s}` is not a resolution ≥ 10")),
        };
        // The study scene at this size must be a valid scene within the resource limits.
        let scene = match sphlab::study::study_scene_with(n, &a.sets) {
            Ok(sc) => sc,
            Err(e) => return fail(2, format!("--sizes {n}: {e}")),
        };
        let plan = sphlab::study::plan::resource_plan(&scene, earlier);
        if let Err(e) = plan.check(&limits) {
            return fail(2, format!("--sizes {n}: {e}"));
        }
        earlier += plan.n_total;
        sizes.push(n);
    }
    for &nx in a.e4_sizes.iter().chain(&probe_sizes) {
        match sphlab::study::study_scene_with(nx, &a.sets) {
            Ok(scene) => {
                if let Err(e) = sphlab::study::plan::resource_plan(&scene, 0.0).check(&limits) {
                    return fail(2, format!("--e4-sizes/--probe-sizes {nx}: {e}"));
                }
            }
            Err(e) => return fail(2, e),
        }
    }
    let variants = match a.variants.as_str() {
        "all" => Vec::new(),
        list => match gpu_variants(list) {
            Ok(v) => v,
            Err(e) => return fail(2, e),
        },
    };
    let mut e3_budgets = Vec::new();
    for s in a.e3_budgets.split(',') {
        match s.trim().parse::<usize>() {
            Ok(b) if b >= 100 => e3_budgets.push(b),
            _ => return fail(2, format!("--e3-budgets: `{s}` is not a particle count ≥ 100")),
        }
    }
    let e23 = sphlab::study::e23::E23Options {
        e2_nx: a.e2_nx,
        e3_nx: a.e3_nx,
        e3_steps: a.e3_steps,
        e3_budgets,
        ..Default::default()
    };
    let opts = sphlab::study::StudyOptions {
        e23,
        engine_nx: a.engine_nx,
        experiments,
        sizes,
        protocol: sphlab::study::timing::Protocol {
            steps: a.steps,
            repeats: a.repeats as usize,
            warmup_s: a.warmup,
            ..Default::default()
        },
        variants,
        sets: a.sets,
        cpu_max_n: a.cpu_max_n,
        shard,
        budget_s: a.budget,
        dry_run: a.dry_run,
        out,
        e4_sizes: a.e4_sizes,
        probe_sizes,
    };
    match sphlab::study::run_study(&opts) {
        Ok(_) if opts.dry_run => ExitCode::SUCCESS,
        Ok(r) => {
            let gpu = gpu_context().ok().map(|c| GpuInfo::from_adapter(&c.adapter_info));
            let prov = Provenance::new("study", gpu, provenance::STUDY_UNITS);
            if let Err(e) = sphlab::output::write_json(opts.out.join("provenance.json"), &prov) {
                return fail(1, e);
            }
            eprintln!("{} records; {}", r.len(), opts.out.join("summary.md").display());
            ExitCode::SUCCESS
        }
        Err(e) if e.starts_with("--") => fail(2, e),
        Err(e) => fail(1, e),
    }
}

fn cmd_report(a: ReportArgs) -> ExitCode {
    if let Err(e) = check_out("--out", &a.out) {
        return fail(2, e);
    }
    for d in &a.dirs {
        let journal = d.join(sphlab::study::report::JOURNAL);
        if !d.join("records.csv").is_file() && !journal.is_file() {
            return fail(
                2,
                format!(
                    "{}: no records.csv nor {} (not a study output directory)",
                    d.display(),
                    sphlab::study::report::JOURNAL
                ),
            );
        }
    }
    match sphlab::study::report::merge(&a.dirs, &a.out) {
        Ok(r) => {
            let prov = Provenance::new("report", None, provenance::STUDY_UNITS);
            if let Err(e) = sphlab::output::write_json(a.out.join("provenance.json"), &prov) {
                return fail(1, e);
            }
            eprintln!("{} records from {} runs; {}", r.len(), a.dirs.len(), a.out.join("summary.md").display());
            ExitCode::SUCCESS
        }
        Err(e) => fail(1, e),
    }
}

/// Every adapter wgpu finds, with the features and limits sphlab cares about.
fn adapters_json() -> Vec<serde_json::Value> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    adapters
        .iter()
        .map(|ad| {
            let l = ad.limits();
            let features: Vec<&str> = ad.features().iter_names().map(|(n, _)| n).collect();
            serde_json::json!({
                "adapter": GpuInfo::from_adapter(&ad.get_info()),
                "features": features,
                "limits": {
                    "max_buffer_size": l.max_buffer_size,
                    "max_storage_buffer_binding_size": l.max_storage_buffer_binding_size,
                    "max_storage_buffers_per_shader_stage": l.max_storage_buffers_per_shader_stage,
                    "max_compute_workgroup_storage_size": l.max_compute_workgroup_storage_size,
                    "max_compute_invocations_per_workgroup": l.max_compute_invocations_per_workgroup,
                    "max_compute_workgroup_size_x": l.max_compute_workgroup_size_x,
                    "max_compute_workgroups_per_dimension": l.max_compute_workgroups_per_dimension,
                },
            })
        })
        .collect()
}

fn cmd_info(json: bool) -> ExitCode {
    let prov = Provenance::new("info", None, &[]);
    let limits = Limits::default();
    let adapters = adapters_json();
    // What the solver's device was granted (the adapter's own limits, requested in full) and
    // the device memory its memory plan assumes.
    let device = gpu_context().ok().map(|c| (c.describe(), sphlab::gpu::plan::DeviceLimits::of(&c, None)));
    let doc = with_provenance(
        serde_json::json!({
            "memory_available_bytes": sphlab::plan::available_memory(),
            "default_limits": limits,
            "adapters": adapters,
            "device": device.as_ref().map(|(name, l)| serde_json::json!({"adapter": name, "limits": l})),
        }),
        &prov,
    );
    if json {
        println!("{}", serde_json::to_string_pretty(&doc).expect("json"));
        return ExitCode::SUCCESS;
    }
    println!("sphlab {}", provenance::long_version());
    println!(
        "host: {} ({} logical CPUs, {} worker threads, {})",
        prov.host.cpu, prov.host.cpus, prov.host.threads, prov.host.os
    );
    println!(
        "memory: {} available; default limits: {} particles, {} ({})",
        sphlab::plan::available_memory().map_or("unknown".into(), |b| sphlab::plan::fmt_bytes(b as f64)),
        limits.max_particles,
        sphlab::plan::fmt_bytes(limits.max_memory as f64),
        limits.memory_source
    );
    if adapters.is_empty() {
        println!("GPU adapters: none");
    }
    for a in &adapters {
        let ad = &a["adapter"];
        println!(
            "adapter: {} ({}, {}, driver {})",
            ad["adapter"].as_str().unwrap_or(""),
            ad["api"].as_str().unwrap_or(""),
            ad["device_type"].as_str().unwrap_or(""),
            ad["driver"].as_str().unwrap_or("")
        );
        let f: Vec<&str> =
            a["features"].as_array().map(|v| v.iter().filter_map(|x| x.as_str()).collect()).unwrap_or_default();
        println!("  features: {}", if f.is_empty() { "-".into() } else { f.join(" ") });
        if let Some(l) = a["limits"].as_object() {
            for (k, v) in l {
                println!("  {k}: {v}");
            }
        }
    }
    if let Some((name, l)) = &device {
        println!(
            "solver device: {name}: granted max_buffer_size {}, max_storage_buffer_binding_size {}, \
             max_compute_workgroups_per_dimension {}; device memory {} ({})",
            l.max_buffer_size,
            l.max_binding_size,
            l.max_groups_per_dim,
            l.memory.map_or("unknown".into(), |m| sphlab::plan::fmt_bytes(m as f64)),
            l.memory_source
        );
    }
    ExitCode::SUCCESS
}

fn cmd_scene_list(json: bool) -> ExitCode {
    let rows: Vec<(&str, String)> =
        builtin::BUILTIN.iter().map(|n| (*n, builtin::builtin(n).expect("built-in").description)).collect();
    if json {
        let v: Vec<serde_json::Value> =
            rows.iter().map(|(n, d)| serde_json::json!({"name": n, "description": d})).collect();
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "scenes": v })).expect("json"));
    } else {
        for (n, d) in rows {
            println!("{n:18} {d}");
        }
    }
    ExitCode::SUCCESS
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(n) = cli.threads {
        if let Err(e) = rayon::ThreadPoolBuilder::new().num_threads(n as usize).build_global() {
            return fail(2, format!("--threads: {e}"));
        }
    }
    match cli.cmd {
        Cmd::Run(a) => cmd_run(a),
        Cmd::Scene { cmd: SceneCmd::List { json } } => cmd_scene_list(json),
        Cmd::Scene { cmd: SceneCmd::Show { name } } => match builtin::builtin(&name) {
            Some(s) => {
                print!("{}", s.to_toml());
                ExitCode::SUCCESS
            }
            None => fail(2, format!("unknown scene `{name}` (built-in: {})", builtin::BUILTIN.join(", "))),
        },
        Cmd::Scene { cmd: SceneCmd::RelaxStart { theta } } => {
            if !(theta > 0.0 && theta < 180.0) {
                return fail(2, format!("THETA = {theta}: the starting contact angle must be in (0, 180) degrees"));
            }
            for s in sphlab::validate::relax_start_sets(theta) {
                println!("{s}");
            }
            ExitCode::SUCCESS
        }
        Cmd::Analytic { cmd } => cmd_analytic(cmd),
        Cmd::Variants { json, memory: Some(n), gpu_memory } => cmd_variants_memory(n, gpu_memory, json),
        Cmd::Variants { json, .. } => cmd_variants(json),
        Cmd::Study(a) => cmd_study(a),
        Cmd::Report(a) => cmd_report(a),
        Cmd::Verify(a) => cmd_verify(a),
        Cmd::Validate(a) => cmd_validate(a),
        Cmd::Info { json } => cmd_info(json),
        Cmd::Forces(a) => {
            let o = sphlab::forces::report::ForceOptions {
                step: a.step,
                last: a.last,
                at: a.at,
                half_width_dx: a.half_width,
                height_dx: a.height,
                cuts: a.cuts.map(|c| [c[0], c[1]]),
                csv: a.csv,
                exec: if cli.threads == Some(1) { sphlab::exec::Exec::Serial } else { sphlab::exec::Exec::Parallel },
            };
            match sphlab::forces::report::force_report(&a.run_dir, &o) {
                Ok(md) => {
                    print!("{md}");
                    ExitCode::SUCCESS
                }
                Err(e) => fail(2, e),
            }
        }
        Cmd::Stability(a) => match load_scene(&a.scene, &a.sets) {
            Ok(s) => ExitCode::from(sphlab::stability::args::run(&a, &s)),
            Err(e) => fail(2, e),
        },
    }
}
