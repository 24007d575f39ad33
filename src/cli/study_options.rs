//! The options of `sphlab study` (without a preset), checked in the order the user reads them:
//! every bad value is bad input (exit 2) naming its option, before anything runs.

use super::common::{check_out, gpu_variants};
use super::study::{Experiment, StudyArgs};
use clap::ValueEnum;
use sphlab::error::Error;
use sphlab::gpu::variant::{Mapping, VariantSpec, Workgroup};
use sphlab::plan::Limits;
use sphlab::study::{self, e23::E23Options, timing::Protocol, StudyOptions};
use std::path::PathBuf;

/// The experiments to run by name: `all` is [`study::EXPERIMENTS`] (and `engine` when named too).
fn experiments(list: &[Experiment]) -> Vec<String> {
    if list.contains(&Experiment::All) {
        let named = list.contains(&Experiment::Engine).then_some("engine");
        study::EXPERIMENTS.iter().copied().chain(named).map(|s| s.to_string()).collect()
    } else {
        list.iter().filter_map(|e| e.to_possible_value()).map(|v| v.get_name().to_string()).collect()
    }
}

/// `--sizes`: resolutions ≥ 10 whose study scenes are valid and, together, within the limits.
fn sizes(text: &str, sets: &[String], limits: &Limits) -> Result<Vec<u32>, Error> {
    let (mut sizes, mut earlier) = (Vec::new(), 0.0);
    for s in text.split(',') {
        let n = match s.trim().parse::<u32>() {
            Ok(n) if n >= 10 => n,
            _ => return Err(Error::input(format!("--sizes: `{s}` is not a resolution ≥ 10"))),
        };
        // The study scene at this size must be a valid scene within the resource limits.
        let scene = study::study_scene_with(n, sets).map_err(|e| Error::input(format!("--sizes {n}: {e}")))?;
        let plan = study::plan::resource_plan(&scene, earlier);
        plan.check(limits).map_err(|e| Error::input(format!("--sizes {n}: {e}")))?;
        earlier += plan.n_total;
        sizes.push(n);
    }
    Ok(sizes)
}

/// `--e4-sizes` and `--probe-sizes`: each study scene valid and within the limits on its own.
fn check_extra_sizes(extra: &[u32], sets: &[String], limits: &Limits) -> Result<(), Error> {
    for &nx in extra {
        let scene = study::study_scene_with(nx, sets).map_err(Error::Input)?;
        study::plan::resource_plan(&scene, 0.0)
            .check(limits)
            .map_err(|e| Error::input(format!("--e4-sizes/--probe-sizes {nx}: {e}")))?;
    }
    Ok(())
}

/// `--e3-budgets`: particle counts ≥ 100.
fn e3_budgets(text: &str) -> Result<Vec<usize>, Error> {
    text.split(',')
        .map(|s| match s.trim().parse::<usize>() {
            Ok(b) if b >= 100 => Ok(b),
            _ => Err(Error::input(format!("--e3-budgets: `{s}` is not a particle count ≥ 100"))),
        })
        .collect()
}

/// The study's options from its arguments; the first bad value is the error.
pub fn options(a: StudyArgs) -> Result<StudyOptions, Error> {
    if a.allow_cpu_adapter {
        return Err(Error::input("--allow-cpu-adapter: applies only to --preset gpu"));
    }
    if a.archive.is_some() {
        return Err(Error::input("--archive: applies only to --preset gpu"));
    }
    let probe_sizes = match a.probe_sizes.as_slice() {
        &[p, q] if p < q => [p, q],
        other => return Err(Error::input(format!("--probe-sizes: two increasing resolutions, got {other:?}"))),
    };
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("reports/study"));
    check_out("--out", &out)?;
    let limits = a.limits.limits()?;
    if limits.gpu_binding.is_some() {
        return Err(Error::input(
            "--gpu-binding: not for the study, whose records time the adapter as it is; use it with run or verify",
        ));
    }
    let shard = sphlab::sweep::Shard::parse(&a.shard).map_err(Error::Input)?;
    let experiments = experiments(&a.experiments);
    let sizes = sizes(&a.sizes, &a.sets, &limits)?;
    check_extra_sizes(&[a.e4_sizes.as_slice(), &probe_sizes].concat(), &a.sets, &limits)?;
    let variants = with_workgroups(
        match a.variants.as_str() {
            "all" => Vec::new(),
            list => gpu_variants(list)?,
        },
        &a.workgroup_sizes,
    )?;
    let e23 = E23Options {
        e2_nx: a.e2_nx,
        e3_nx: a.e3_nx,
        e3_steps: a.e3_steps,
        e3_budgets: e3_budgets(&a.e3_budgets)?,
        ..Default::default()
    };
    Ok(StudyOptions {
        e23,
        engine_nx: a.engine_nx,
        experiments,
        sizes,
        protocol: Protocol { steps: a.steps, repeats: a.repeats as usize, warmup_s: a.warmup, ..Default::default() },
        variants,
        sets: a.sets,
        cpu_max_n: a.cpu_max_n,
        shard,
        budget_s: a.budget,
        dry_run: a.dry_run,
        out,
        e4_sizes: a.e4_sizes,
        probe_sizes,
        perturb: Vec::new(),
    })
}

/// `variants` (empty: every variant) with each thread variant's twins at the other sizes of
/// `--workgroup-sizes`; unchanged (still empty for `all`) when that is just 64.
fn with_workgroups(variants: Vec<VariantSpec>, sizes: &str) -> Result<Vec<VariantSpec>, Error> {
    let mut wanted = Vec::new();
    for t in sizes.split(',').map(str::trim).filter(|t| !t.is_empty()) {
        let w = t.parse().ok().and_then(Workgroup::of).ok_or_else(|| {
            Error::input(format!("--workgroup-sizes: `{t}` is not a workgroup size; accepted: 64, 128, 256"))
        })?;
        if !wanted.contains(&w) {
            wanted.push(w);
        }
    }
    if wanted.is_empty() {
        return Err(Error::input("--workgroup-sizes: give at least one of 64, 128, 256"));
    }
    if wanted == [Workgroup::W64] {
        return Ok(variants);
    }
    let base = if variants.is_empty() { VariantSpec::all() } else { variants };
    let mut out = Vec::new();
    for v in base {
        let sizes = if v.mapping == Mapping::Thread { wanted.clone() } else { vec![v.workgroup] };
        for s in sizes.into_iter().filter_map(|w| v.with_workgroup(w)) {
            if !out.contains(&s) {
                out.push(s);
            }
        }
    }
    Ok(out)
}
