//! `sphlab forces`: the pair forces of a run folder's saved state split by term and partner, in
//! a window around the right contact point (the report is printed as markdown).

use clap::Args;
use sphlab::error::Error;
use sphlab::exec::Exec;
use sphlab::forces::report::{force_report, ForceOptions};
use std::path::PathBuf;

#[derive(Args)]
pub struct ForcesArgs {
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
    /// x of the cuts whose wall-band tensions are measured, as X1,X2,… (each on the liquid or
    /// the gas side of the contact point by where it lies; default: --cuts-per-side).
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    cuts: Option<Vec<f64>>,
    /// Without --cuts: N cuts evenly spaced on each side of the contact point (1: half-way to
    /// it from either side); with N > 1 the report adds each side's mean and range, the
    /// band tension's scatter along the wall.
    #[arg(long, default_value_t = 1, value_name = "N")]
    cuts_per_side: usize,
    /// Also write every fluid particle's split (18 components) to this CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// The report of `a.run_dir`, one thread with `--threads 1`; any failure is bad input.
pub fn run(a: ForcesArgs, threads: Option<u16>) -> Result<(), Error> {
    let o = ForceOptions {
        step: a.step,
        last: a.last,
        at: a.at,
        half_width_dx: a.half_width,
        height_dx: a.height,
        cuts: a.cuts,
        cuts_per_side: a.cuts_per_side,
        csv: a.csv,
        exec: if threads == Some(1) { Exec::Serial } else { Exec::Parallel },
    };
    print!("{}", force_report(&a.run_dir, &o).map_err(Error::Input)?);
    Ok(())
}
