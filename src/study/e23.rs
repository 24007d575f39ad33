//! The study's E2 (residency hybrids, [`super::e2_residency`]) and E3 (subdomain budgets,
//! [`super::e3_subdomains`]) runs: each hybrid and each (configuration, budget) is verified
//! first, then timed, and becomes one [`Record`] of `records.csv` with the E2/E3 columns
//! (residency, bytes per step, budget, subdomains, halo, device bytes, GPU busy, verification).
//! A run that fails (error, blow-up, overflow) is reported and not recorded; a run that fails
//! verification is recorded `inaccurate` with its verdict and no timing (NaN).

use super::e2_residency::{time_hybrid, verify_hybrid, HybridSolver, HYBRIDS};
use super::e3_subdomains::{time_split, time_unsplit, verify_split, SplitSolver, SplitTiming, CONFIGS};
use super::{study_scene, Record};
use crate::backend::Backend;
use crate::cpu::CpuSolver;
use crate::exec::Exec;
use crate::gpu::solver::GpuSolver;
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::scene::build::{build_layout, Layout};
use crate::scene::initial::initial_velocities;
use crate::scene::Scene;
use crate::verify::Check;
use std::sync::Arc;

/// Settings of E2 and E3.
#[derive(Clone, Debug)]
pub struct E23Options {
    /// E2 resolution (particles across the box; 45 = 2,025 fluid particles).
    pub e2_nx: u32,
    /// E3 resolution (100 = 10,000 fluid particles).
    pub e3_nx: u32,
    /// E3 timed iterations (thesis: 200).
    pub e3_steps: u64,
    /// E3 particle budgets per subdomain.
    pub e3_budgets: Vec<usize>,
    /// Steps before each hybrid / split is compared with its reference.
    pub verify_steps: u64,
}

impl Default for E23Options {
    fn default() -> Self {
        Self { e2_nx: 45, e3_nx: 100, e3_steps: 200, e3_budgets: vec![1500, 3000, 4500, 6000], verify_steps: 3 }
    }
}

fn base(experiment: &str, variant: String, scene: &Scene, layout: &Layout, ctx: &GpuContext, steps: u64) -> Record {
    let i = &ctx.adapter_info;
    Record {
        experiment: experiment.into(),
        variant,
        scene: scene.name.clone(),
        nx: scene.domain.nx,
        n: layout.pos.len(),
        n_fluid: layout.n_fluid,
        steps,
        backend: "gpu".into(),
        adapter: i.name.clone(),
        driver: format!("{} {}", i.driver, i.driver_info),
        device_type: format!("{:?}", i.device_type),
        cpu_model: crate::provenance::cpu_model(),
        cpu_threads: 1,
        precision: "f32".into(),
        timing: "wall".into(),
        commit: crate::output::git_commit(),
        date: crate::output::now_utc_iso8601(),
        ..Record::default()
    }
}

/// Timing of a run that finished and verified: `status = ok`, median/min/max of the sorted
/// per-step times.
fn set_times(r: &mut Record, ms: &[f64], evals: f64) {
    let median = super::stats::percentile(ms, 0.5);
    r.status = "ok".into();
    r.ms_per_step_median = Some(median);
    r.ms_per_step_min = ms.first().copied();
    r.ms_per_step_max = ms.last().copied();
    r.ms_per_step_p10 = Some(super::stats::percentile(ms, 0.1));
    r.ms_per_step_p90 = Some(super::stats::percentile(ms, 0.9));
    let (lo, hi) = super::stats::bootstrap_median_ci(ms);
    (r.ms_per_step_ci_lo, r.ms_per_step_ci_hi) = (Some(lo), Some(hi));
    r.particle_evals_per_s = Some(r.n as f64 * evals / (median * 1e-3));
}

/// A record of a run that is not a measurement: its status and reason, no timing.
fn set_failed(r: &mut Record, status: &str, reason: String) {
    r.status = status.into();
    r.reason = reason;
}

/// A device error as the E2/E3 runs report it.
pub(super) fn gpu_err(e: impl std::fmt::Display) -> String {
    format!("GPU: {e}")
}

/// The host solver an E2 hybrid or an E3 split runs on: f32, one thread, cells, restarted from
/// `vel0`; both need a fixed dt (`what` names the experiment in the refusal).
pub(super) fn host_solver(
    scene: &Scene,
    layout: &Layout,
    vel0: &[[f64; 2]],
    what: &str,
) -> Result<CpuSolver<f32>, String> {
    let mut host = CpuSolver::<f32>::new(scene, layout, Exec::Serial, SearchKind::Cells);
    host.restart_with_velocities(vel0);
    if host.model.dt_fixed <= 0.0 {
        return Err(format!("{what} needs a fixed dt (time.dt > 0)"));
    }
    Ok(host)
}

/// The verdict of an E2/E3 verification: `Err(failed checks)` when any fails, else
/// `Ok("pass (worst NAME max_rel)")` by the worst ratio to its tolerance.
pub(super) fn verdict(checks: &[Check]) -> Result<String, String> {
    let failed: Vec<String> = checks
        .iter()
        .filter(|c| !c.pass)
        .map(|c| format!("{} {:.2e} > {:.0e}", c.name, c.max_rel, c.tolerance))
        .collect();
    if !failed.is_empty() {
        return Err(failed.join(", "));
    }
    let worst = checks
        .iter()
        .filter(|c| c.tolerance > 0.0 && c.max_rel.is_finite())
        .max_by(|a, b| (a.max_rel / a.tolerance).total_cmp(&(b.max_rel / b.tolerance)));
    Ok(match worst {
        Some(c) if c.max_rel > 0.0 => format!("pass (worst {} {:.1e})", c.name, c.max_rel),
        _ => "pass (identical)".into(),
    })
}

fn setup(nx: u32) -> Result<(Scene, Layout, Vec<[f64; 2]>), String> {
    let scene = study_scene(nx);
    let layout = build_layout(&scene).map_err(|e| e.to_string())?;
    let vel0 = initial_velocities(&scene, &layout, None);
    Ok((scene, layout, vel0))
}

fn evals(scene: &Scene) -> f64 {
    if scene.time.integrator == crate::scene::Integrator::Midpoint {
        2.0
    } else {
        1.0
    }
}

/// E2: every hybrid of [`HYBRIDS`] on the default variant, `steps` timed steps each.
pub fn run_e2(o: &E23Options, steps: u64, ctx: &Arc<GpuContext>, out: &mut Vec<Record>) -> Result<(), String> {
    let (scene, layout, vel0) = setup(o.e2_nx)?;
    let spec = VariantSpec::default();
    for h in HYBRIDS {
        let id = format!("hybrid.{}", h.name);
        let mut r = base("e2", id.clone(), &scene, &layout, ctx, steps);
        r.residency_cpu = h.cpu_groups();
        r.config = spec.to_string();
        match verify_hybrid(ctx, &scene, &layout, spec, h, &vel0, o.verify_steps) {
            Ok(v) => r.verified = v,
            Err(e) if e.starts_with("GPU") => {
                eprintln!("e2 {id}: skipped: {e}");
                continue;
            }
            Err(e) => {
                eprintln!("e2 {id}: verification FAILED: {e}");
                r.verified = format!("FAIL: {e}");
                set_failed(&mut r, "inaccurate", format!("verification failed: {e}"));
                out.push(r);
                continue;
            }
        }
        let timed =
            HybridSolver::new(ctx, &scene, &layout, spec, h, &vel0).and_then(|mut s| time_hybrid(&mut s, 2, steps));
        match timed {
            Ok(t) => {
                set_times(&mut r, &t.ms, evals(&scene));
                r.bytes_h2d_per_step = Some(t.h2d_per_step);
                r.bytes_d2h_per_step = Some(t.d2h_per_step);
                eprintln!(
                    "e2 {id:<36} {:>10.3} ms/step {:>12.0} B/step copied  {}",
                    r.ms(),
                    t.h2d_per_step + t.d2h_per_step,
                    r.verified
                );
                out.push(r);
            }
            Err(e) => {
                eprintln!("e2 {id}: failed: {e}");
                set_failed(&mut r, "failed", e);
                out.push(r);
            }
        }
    }
    Ok(())
}

fn e3_record(r: &mut Record, t: &SplitTiming, evals: f64) {
    set_times(r, &t.ms, evals);
    if let Some(d) = t.device_ms {
        r.timing = "wall+timestamps".into();
        r.gpu_ms_per_step = Some(d / r.steps.max(1) as f64);
        r.gpu_busy = Some(d / t.wall_ms.max(1e-300));
    }
    r.bytes_h2d_per_step = Some(t.h2d_per_step);
    r.bytes_d2h_per_step = Some(t.d2h_per_step);
    r.subdomains = Some(t.subdomains);
    r.halo_particles = Some(t.halo);
    r.device_bytes = Some(t.device_bytes);
}

/// E3: for each configuration of [`CONFIGS`], the unsplit run and every budget.
pub fn run_e3(o: &E23Options, ctx: &Arc<GpuContext>, out: &mut Vec<Record>) -> Result<(), String> {
    let (scene, layout, vel0) = setup(o.e3_nx)?;
    let steps = o.e3_steps;
    let ev = evals(&scene);
    for c in CONFIGS {
        let spec: VariantSpec = c.variant.parse()?;
        if let Err(e) = spec.support(ctx) {
            eprintln!("e3 {} {}: unsupported on this adapter: {e}", c.symbol, c.variant);
            continue;
        }
        let mut r = base("e3", c.variant.to_string(), &scene, &layout, ctx, steps);
        r.config = format!("{} {}", c.symbol, c.label);
        let unsplit =
            GpuSolver::<f32>::new(ctx.clone(), &scene, &layout, spec).map_err(|e| e.to_string()).and_then(|mut g| {
                g.restart_with_velocities(&vel0);
                time_unsplit(&mut g, steps)
            });
        match unsplit {
            Ok(t) => {
                e3_record(&mut r, &t, ev);
                r.verified = "reference (unsplit)".into();
                eprintln!("e3 {} {:<40} unsplit {:>10.3} ms/step", c.symbol, c.variant, r.ms());
                out.push(r.clone());
            }
            Err(e) => {
                eprintln!("e3 {} {}: unsplit run failed, skipped: {e}", c.symbol, c.variant);
                continue;
            }
        }
        for &budget in &o.e3_budgets {
            let mut r = base("e3", c.variant.to_string(), &scene, &layout, ctx, steps);
            r.config = format!("{} {}", c.symbol, c.label);
            r.budget = Some(budget);
            match verify_split(ctx, &scene, &layout, spec, budget, &vel0, o.verify_steps) {
                Ok(v) => r.verified = v,
                Err(e) if e.starts_with("GPU") || e.starts_with("unsplit") => {
                    eprintln!("e3 {} budget {budget}: skipped: {e}", c.symbol);
                    continue;
                }
                Err(e) => {
                    eprintln!("e3 {} budget {budget}: verification FAILED: {e}", c.symbol);
                    r.verified = format!("FAIL: {e}");
                    set_failed(&mut r, "inaccurate", format!("verification failed: {e}"));
                    out.push(r);
                    continue;
                }
            }
            let timed =
                SplitSolver::new(ctx, &scene, &layout, spec, budget, &vel0).and_then(|mut s| time_split(&mut s, steps));
            match timed {
                Ok(t) => {
                    e3_record(&mut r, &t, ev);
                    eprintln!(
                        "e3 {} {:<40} budget {budget:>6}: {} subdomains, {:.0} halo, {:>10.3} ms/step, {:.0} B/step, busy {}",
                        c.symbol,
                        c.variant,
                        t.subdomains,
                        t.halo,
                        r.ms(),
                        t.h2d_per_step + t.d2h_per_step,
                        r.gpu_busy.map_or("-".into(), |b| format!("{:.0} %", 100.0 * b))
                    );
                    out.push(r);
                }
                Err(e) => {
                    eprintln!("e3 {} budget {budget}: failed: {e}", c.symbol);
                    set_failed(&mut r, "failed", e);
                    out.push(r);
                }
            }
        }
    }
    Ok(())
}
