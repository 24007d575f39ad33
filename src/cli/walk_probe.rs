//! `sphlab walk-probe`: the bare neighbour walk timed on the GPU (`gpu::walk_probe`), four forms
//! × two binding accesses at each lattice side; a table on stdout and, with `--out`,
//! `walk.csv` and `walk.json` (with provenance).

use super::common::{check_out, gpu_context, with_provenance};
use clap::Args;
use sphlab::error::Error;
use sphlab::gpu::walk_probe::{measure_walk, WalkTime};
use sphlab::provenance::{GpuInfo, Provenance};
use std::path::PathBuf;

/// Options of `sphlab walk-probe`.
#[derive(Args)]
pub struct WalkProbeArgs {
    /// Particles per side of each lattice (comma-separated, N = side²); each from 4 up to the
    /// largest whose position array fits one storage binding of the adapter.
    #[arg(long, value_delimiter = ',', default_value = "100,316,1000")]
    sides: Vec<u32>,
    /// Output directory (walk.csv, walk.json).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Smallest side: a 3×3 block of cells must exist.
const MIN_SIDE: u32 = 4;

/// Checks every side against the adapter's binding limit (exit 2) before allocating, then
/// times the walk at each.
pub fn run(a: WalkProbeArgs) -> Result<(), Error> {
    if let Some(dir) = &a.out {
        check_out("--out", dir)?;
    }
    if a.sides.is_empty() {
        return Err(Error::input("--sides: give at least one side"));
    }
    let ctx = gpu_context().map_err(|e| Error::input(format!("no GPU adapter: {e}")))?;
    let binding = ctx.buffer_cap();
    // The largest array is the positions (8 B per particle).
    let max_side = ((binding / 8) as f64).sqrt().floor() as u32;
    if let Some(bad) = a.sides.iter().find(|&&s| !(MIN_SIDE..=max_side).contains(&s)) {
        return Err(Error::input(format!(
            "--sides: {bad} is outside {MIN_SIDE}..={max_side} (this adapter binds at most {binding} bytes per \
             storage buffer; 8 bytes per particle)"
        )));
    }
    eprintln!("adapter: {}", ctx.describe());
    let mut rows: Vec<WalkTime> = Vec::new();
    for &side in &a.sides {
        let got = measure_walk(&ctx, side).map_err(|e| Error::Failed(format!("walk probe at side {side}: {e}")))?;
        let Some(times) = got else {
            return Err(Error::Failed("walk probe: the adapter has no TIMESTAMP_QUERY; nothing is timed".into()));
        };
        for r in &times {
            println!(
                "N {:>10}  {:<16} {:<10}  {:>9.3} ns/particle  {:>9.1} ps/candidate  ({:.1} candidates, {:.1} neighbours)",
                r.n, r.form, r.access, r.ns_per_particle, r.ps_per_candidate, r.candidates, r.neighbours
            );
        }
        rows.extend(times);
        if let Some(dir) = &a.out {
            write(dir, &ctx, &rows)?;
        }
    }
    Ok(())
}

/// `walk.csv` and `walk.json` of the rows so far.
fn write(dir: &std::path::Path, ctx: &sphlab::gpu::GpuContext, rows: &[WalkTime]) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::Failed(format!("{}: {e}", dir.display())))?;
    let p = dir.join("walk.csv");
    let mut w = csv::Writer::from_path(&p).map_err(|e| Error::Failed(format!("{}: {e}", p.display())))?;
    for r in rows {
        w.serialize(r).map_err(|e| Error::Failed(format!("{}: {e}", p.display())))?;
    }
    w.flush().map_err(|e| Error::Failed(format!("{}: {e}", p.display())))?;
    let units: &[(&str, &str)] =
        &[("best_ns", "ns"), ("ns_per_particle", "ns"), ("ps_per_candidate", "ps"), ("candidates, neighbours", "1")];
    let prov = Provenance::new("walk-probe", Some(GpuInfo::from_adapter(&ctx.adapter_info)), units);
    let doc = with_provenance(serde_json::json!({ "rows": rows }), &prov);
    sphlab::output::write_json(dir.join("walk.json"), &doc).map_err(|e| Error::Failed(e.to_string()))
}
