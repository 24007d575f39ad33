//! `sphlab report`: the records of several study runs (shards, adapters) merged into one
//! summary.md and its plots.

use super::common::check_out;
use clap::Args;
use sphlab::error::Error;
use sphlab::provenance::{self, Provenance};
use sphlab::study::report::{merge, JOURNAL};
use std::path::PathBuf;

#[derive(Args)]
pub struct ReportArgs {
    /// Study output directories (each with records.csv), e.g. the shards of one sweep or runs on
    /// several adapters.
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Output directory of the merged report.
    #[arg(long)]
    out: PathBuf,
}

/// Checks `--out` and that every directory is a study's output (exit 2), then merges them.
pub fn run(a: ReportArgs) -> Result<(), Error> {
    check_out("--out", &a.out)?;
    for d in &a.dirs {
        if !d.join("records.csv").is_file() && !d.join(JOURNAL).is_file() {
            return Err(Error::input(format!(
                "{}: no records.csv nor {JOURNAL} (not a study output directory)",
                d.display()
            )));
        }
    }
    let r = merge(&a.dirs, &a.out).map_err(Error::Failed)?;
    let prov = Provenance::new("report", None, provenance::STUDY_UNITS);
    sphlab::output::write_json(a.out.join("provenance.json"), &prov).map_err(Error::failed)?;
    eprintln!("{} records from {} runs; {}", r.len(), a.dirs.len(), a.out.join("summary.md").display());
    Ok(())
}
