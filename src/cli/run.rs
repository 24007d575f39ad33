//! `sphlab run`: one scene on one backend, writing series.csv, snapshots and summary.json.

use super::common::{check_out, install_interrupt_handler, load_scene, search_parser, BackendArgs, LimitArgs};
use clap::Args;
use sphlab::error::Error;
use sphlab::neighbours::SearchKind;
use sphlab::run::RunOptions;
use std::path::PathBuf;

#[derive(Args)]
pub struct RunArgs {
    /// Built-in scene name (see `sphlab scene list`) or a scene TOML file.
    #[arg(default_value = "oscillating-drop")]
    scene: String,
    #[command(flatten)]
    backend: BackendArgs,
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
    /// At most N steps per GPU submission (one readback each, read one batch late while the
    /// next batches run), cut at output steps; 0: 64.
    #[arg(long, default_value_t = 0)]
    steps_per_submit: u64,
    /// CPU neighbour search (default cells); a GPU variant's is part of its id.
    #[arg(long, value_parser = search_parser())]
    search: Option<SearchKind>,
    /// No progress bar or console lines.
    #[arg(long)]
    quiet: bool,
    #[command(flatten)]
    limits: LimitArgs,
}

/// Checks the options (exit 2 before any output), then runs the scene.
pub fn run(a: RunArgs) -> Result<(), Error> {
    check_out("--out", &a.out)?;
    let limits = a.limits.limits()?;
    let backend = a.backend.id(a.search)?;
    let scene = load_scene(&a.scene, &a.sets)?;
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
    sphlab::run::run(&scene, &opts).map(|_| ()).map_err(|e| Error::from_run(e, &opts.out))
}
