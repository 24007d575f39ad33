//! The stability report: `records.csv` (one row per point), `summary.md` (provenance, per
//! backend/precision the largest stable and first unstable dt factor of every case, the
//! backends side by side) and `map-<target>.svg` per backend/precision ([`super::map`]).

use super::{cases, first_unstable, Record, StabilityOptions, Sweep};
use crate::output::SeriesWriter;
use crate::scene::Scene;
use std::fmt::Write as _;
use std::path::Path;

fn factor_text(f: Option<f64>, max: f64) -> String {
    f.map_or(format!("> {max}"), |f| format!("{f}"))
}

/// Writes `records.csv`, `summary.md` and the maps into `dir`.
pub fn write(
    dir: &Path,
    base: &Scene,
    o: &StabilityOptions,
    sweep: &Sweep,
    adapter: Option<String>,
    command: &str,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut w = SeriesWriter::create(dir.join("records.csv")).map_err(|e| e.to_string())?;
    for r in &sweep.records {
        w.write(r).map_err(|e| e.to_string())?;
    }
    w.finish().map_err(|e| e.to_string())?;
    let case_labels: Vec<String> = cases(base, o).iter().map(|c| c.label()).collect();
    let max_f = o.dt_factors.iter().cloned().fold(0.0, f64::max);
    let mut md = String::new();
    let _ = writeln!(md, "# Stability map: `{}`\n", base.name);
    let commit = sweep.records.first().map_or_else(crate::output::git_commit, |r| r.commit.clone());
    let _ = writeln!(
        md,
        "* commit `{commit}`, {}; CPU {} ({} threads); GPU adapter: {}\n* command: `{command}`",
        crate::output::now_utc_iso8601(),
        crate::provenance::cpu_model(),
        rayon::current_num_threads(),
        adapter.as_deref().unwrap_or("none")
    );
    let _ = writeln!(
        md,
        "* {} steps per point from the scene's start without relaxation{}, a sampled state every {} steps; \
         dt fixed at a multiple of the tightest stability limit at load (CFL / viscous / force / capillary, \
         `scene::dt_policy`); shard {}/{}\n* unstable: the solver stopped (NaN, a particle out of the box, an \
         overflow), a fluid speed above c_max, or |ρ/ρ0 − 1| > {}\n",
        o.steps,
        if o.at_rest { ", at rest" } else { "" },
        o.sample,
        o.shard.0,
        o.shard.1,
        o.density_cap
    );
    let targets: Vec<String> = o.targets.iter().map(super::label).collect();
    for t in &targets {
        let recs: Vec<&Record> = sweep.records.iter().filter(|r| &r.target == t).collect();
        if recs.is_empty() {
            continue;
        }
        let _ = writeln!(md, "## {t}\n\n![map](map-{t}.svg)\n");
        let _ = writeln!(
            md,
            "| case | n_fluid | tightest limit at load | largest stable factor | first unstable factor (step: reason) | max \\|ρ/ρ0 − 1\\| at 1× | max speed at 1× | ms/step at 1× |\n|---|---|---|---|---|---|---|---|"
        );
        for c in &case_labels {
            let cr: Vec<&Record> = recs.iter().copied().filter(|r| &r.case == c).collect();
            let Some(first) = cr.first() else { continue };
            let fu = first_unstable(&cr);
            let stable_max = cr
                .iter()
                .filter(|r| r.stable && fu.is_none_or(|u| r.dt_factor < u))
                .map(|r| r.dt_factor)
                .fold(f64::NAN, f64::max);
            let why = fu.and_then(|u| cr.iter().find(|r| r.dt_factor == u)).map_or(String::new(), |r| {
                format!(
                    " (step {}: {})",
                    r.fail_step.unwrap_or(0),
                    r.reason.chars().take(140).collect::<String>().replace('|', "\\|")
                )
            });
            let one = cr.iter().find(|r| r.dt_factor == 1.0);
            let at1 = |f: &dyn Fn(&Record) -> f64| one.map_or("—".into(), |r| format!("{:.3e}", f(r)));
            let _ = writeln!(
                md,
                "| {c} | {} | {} {:.3e} | {} | {}{why} | {} | {} | {} |",
                first.n_fluid,
                first.tightest_limit,
                first.tightest_limit_value,
                if stable_max.is_nan() { "none".into() } else { format!("{stable_max}") },
                factor_text(fu, max_f),
                at1(&|r| r.max_density_error),
                at1(&|r| r.max_speed),
                one.map_or("—".into(), |r| format!("{:.2}", r.ms_per_step)),
            );
        }
        let title = format!("{} — {t} ({} steps)", base.name, o.steps);
        super::map::write_svg(&dir.join(format!("map-{t}.svg")), &title, &case_labels, &o.dt_factors, &recs)?;
        md.push('\n');
    }
    if targets.len() > 1 {
        let _ = writeln!(md, "## First unstable dt factor, side by side\n");
        let _ = writeln!(md, "| case | {} |\n|---|{}", targets.join(" | "), "---|".repeat(targets.len()));
        for c in &case_labels {
            let cells: Vec<String> = targets
                .iter()
                .map(|t| {
                    let cr: Vec<&Record> = sweep.records.iter().filter(|r| &r.target == t && &r.case == c).collect();
                    if cr.is_empty() {
                        "—".into()
                    } else {
                        factor_text(first_unstable(&cr), max_f)
                    }
                })
                .collect();
            let _ = writeln!(md, "| {c} | {} |", cells.join(" | "));
        }
        md.push('\n');
    }
    if !sweep.not_run.is_empty() {
        let _ = writeln!(md, "## Not measured\n");
        for (p, why) in &sweep.not_run {
            let _ = writeln!(md, "* {p}: {why}");
        }
    }
    std::fs::write(dir.join("summary.md"), md).map_err(|e| format!("summary.md: {e}"))
}
