//! `sphlab validate`: the validation cases against the thesis and analytic references, written
//! under the report directory with its provenance.

use super::common::{check_out, install_interrupt_handler, BackendArgs};
use clap::{Args, ValueEnum};
use sphlab::error::Error;
use sphlab::provenance::{self, Provenance};
use sphlab::validate::{self, ValidateOptions};
use std::path::PathBuf;

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
    CrossCode,
    SpeedVsError,
    CapillaryWave,
    All,
}

#[derive(Args)]
pub struct ValidateArgs {
    /// The case.
    #[arg(value_enum)]
    case: Case,
    /// Coarse resolution and short times (seconds per case; direction and rough size only).
    #[arg(long)]
    quick: bool,
    #[command(flatten)]
    backend: BackendArgs,
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
    /// Resolution of the long sessile-90 / relax-60 runs (default: the thesis's 65; p_b and c0
    /// follow the capillary rule at that resolution, docs/PHYSICS.md §3.1).
    #[arg(long)]
    nx_long: Option<u32>,
    /// Run the impact case at full resolution (hours per angle on a CPU).
    #[arg(long)]
    full_impact: bool,
    /// No console lines.
    #[arg(long)]
    quiet: bool,
    /// Apply the verdicts again to the committed case.json (no run, no measure): for reports
    /// whose particle snapshots are not committed.
    #[arg(long, conflicts_with_all = ["reuse", "quick", "only"])]
    rejudge: bool,
}

/// Checks the options (exit 2), runs the case (or all), then writes the report's provenance.
pub fn run(a: ValidateArgs) -> Result<(), Error> {
    if a.t_end.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
        return Err(Error::input("--t-end: must be a positive finite time"));
    }
    check_out("--out", &a.out)?;
    let backend = a.backend.id(None)?;
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
        rejudge: a.rejudge,
    };
    install_interrupt_handler();
    let case = a.case.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default();
    let n = if case == "all" {
        validate::run_all(&opts).map(|r| r.len())?
    } else {
        validate::run_case(&case, &opts).map(|_| 1)?
    };
    // Every run's summary.json carries its own envelope; this one is the report's.
    let prov = Provenance::new(format!("validate --backend {}", opts.backend), None, provenance::VALIDATE_UNITS);
    sphlab::output::write_json(opts.out.join("provenance.json"), &prov).map_err(Error::failed)?;
    if !opts.quiet {
        eprintln!("{n} case(s) written under {}", opts.out.display());
    }
    Ok(())
}
