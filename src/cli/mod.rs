//! The `sphlab` command line: the commands ([`Cmd`]), one module each with its arguments beside
//! its glue, and [`dispatch`], which runs one. Every command returns `Result<(), Error>`; the
//! binary turns the error into its message and exit code in one place
//! ([`sphlab::error::Error::exit_code`]).

mod analytic;
mod common;
mod forces;
mod info;
mod report;
mod run;
mod scene;
mod stability;
mod study;
mod study_options;
mod validate;
mod variants;
mod verify;
mod walk_probe;

use clap::{Parser, Subcommand};
use sphlab::error::Error;
use sphlab::provenance;

#[derive(Parser)]
#[command(
    name = "sphlab",
    version = provenance::long_version(),
    about = "GPU-vs-CPU performance laboratory for 2D multiphase SPH"
)]
pub struct Cli {
    /// Worker threads of the CPU backend (default: every logical CPU); recorded in every output.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..=1024))]
    threads: Option<u16>,
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a scene (built-in name or TOML file) and write series.csv, snapshots and summary.json.
    Run(run::RunArgs),
    /// Built-in scenes.
    Scene {
        #[command(subcommand)]
        cmd: scene::SceneCmd,
    },
    /// List the GPU variants, what each needs, and whether this adapter runs it.
    Variants(variants::VariantsArgs),
    /// Check GPU variants against the CPU reference (fields, stages, observables).
    Verify(verify::VerifyArgs),
    /// The Chapter 6 timing study: E1 (search × backend), E4 (speedup), scaling; records.csv + summary.md.
    Study(study::StudyArgs),
    /// Merge the records of several study runs (shards, adapters) into one summary.md and plots.
    Report(report::ReportArgs),
    /// Validation cases against the thesis and analytic references (reports/validation).
    Validate(validate::ValidateArgs),
    /// Stability map: dt factor × density/viscosity ratio × resolution × kernel per backend/precision.
    Stability(stability::StabilityArgs),
    /// Analytic drop-spread models (thesis §5.1, Table 1).
    Analytic {
        #[command(subcommand)]
        cmd: analytic::AnalyticCmd,
    },
    /// Force balance of a run's saved state: each fluid particle's pair forces split by term
    /// (pressure, viscous, surface) and partner (same phase, other phase, wall), summed in a
    /// window around the right contact point, by row (CPU f64, one evaluation).
    Forces(forces::ForcesArgs),
    /// Time the bare neighbour walk on the GPU (no physics): cell ranges, through an index, through
    /// a by-value `Params` call per candidate, with a pair sum; read and read_write bindings.
    WalkProbe(walk_probe::WalkProbeArgs),
    /// The machine: build commit, CPU and threads, memory, every GPU adapter with its features and limits.
    Info {
        /// JSON output.
        #[arg(long)]
        json: bool,
    },
}

/// Runs the command of `cli` (after sizing the CPU worker pool to `--threads`).
pub fn dispatch(cli: Cli) -> Result<(), Error> {
    if let Some(n) = cli.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n as usize)
            .build_global()
            .map_err(|e| Error::input(format!("--threads: {e}")))?;
    }
    match cli.cmd {
        Cmd::Run(a) => run::run(a),
        Cmd::Scene { cmd } => scene::run(cmd),
        Cmd::Analytic { cmd } => analytic::run(cmd),
        Cmd::Variants(a) => variants::run(a),
        Cmd::Study(a) => study::run(a),
        Cmd::Report(a) => report::run(a),
        Cmd::Verify(a) => verify::run(a),
        Cmd::Validate(a) => validate::run(a),
        Cmd::Info { json } => info::run(json),
        Cmd::WalkProbe(a) => walk_probe::run(a),
        Cmd::Forces(a) => forces::run(a, cli.threads),
        Cmd::Stability(a) => stability::run(a),
    }
}
