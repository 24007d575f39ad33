//! `sphlab stability`: the measured stability map of a scene. Around the scene as given (the
//! *base* case) it varies one hard axis at a time — density ratio ρ_0/ρ_1, viscosity ratio
//! μ_0/μ_1, resolution, kernel — and for every case sweeps a fixed dt as a multiple of the
//! tightest limit at load ([`crate::scene::dt_policy`]), on every backend/precision asked for
//! (CPU f64, CPU f32, GPU variants in f32 and, where the adapter has it, f64). Each point runs a
//! fixed number of steps from the same start and records: stable or not (with the step and the
//! reason), the largest fluid speed (the spurious speed in a scene that starts at rest), mass
//! and momentum drift, the largest |ρ/ρ0 − 1|, and the wall time per step.
//!
//! A point is unstable when the solver stops (NaN, a particle out of the box, an overflow) or a
//! sampled state is past the weakly compressible model: a fluid speed above the largest sound
//! speed, or |ρ/ρ0 − 1| above `density_cap`. `--shard i/n` runs every n-th point; `--budget`
//! stops starting points after that many seconds (the rest are listed as not run).
//! The report ([`report`]) writes `records.csv`, `summary.md` and one map per backend.

pub(crate) mod map;
pub mod report;

use crate::backend::Backend;
use crate::backend_id::BackendId;
use crate::exec::Exec;
use crate::gpu::variant::{VariantSpec, DEFAULT_VARIANT};
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::run::measure;
use crate::scene::build::build_layout;
use crate::scene::initial::initial_velocities;
use crate::scene::overrides::apply_overrides;
use crate::scene::{dt_policy, DtPolicy, Scene};
use serde::Serialize;
use std::sync::Arc;
use std::time::Instant;

/// The spellings of `--backend` (besides `all`, which is all of them): the CPU reference on
/// all threads with the cell search, or the default GPU variant, in either precision.
pub const BACKENDS: [&str; 4] = ["cpu.f64", "cpu.f32", "gpu.f32", "gpu.f64"];

/// The backend a [`BACKENDS`] spelling names (`None` for any other text).
pub fn backend(spelling: &str) -> Option<BackendId> {
    let (kind, precision) = spelling.split_once('.')?;
    let precision = Precision::parse(precision)?;
    match kind {
        "cpu" => Some(BackendId::Cpu { exec: Exec::Parallel, search: SearchKind::Cells, precision }),
        "gpu" => Some(BackendId::Gpu(VariantSpec { precision, ..DEFAULT_VARIANT.parse().expect("default id parses") })),
        _ => None,
    }
}

/// The label of a backend in the map's outputs: `cpu.f64` or `cpu.f32` for the map's CPU
/// reference (all threads, cells), `gpu.<variant id>` for a GPU variant, the full id for any
/// other CPU backend.
pub fn label(id: &BackendId) -> String {
    match id {
        BackendId::Cpu { exec: Exec::Parallel, search: SearchKind::Cells, precision } => format!("cpu.{precision}"),
        BackendId::Cpu { .. } => id.to_string(),
        BackendId::Gpu(v) => format!("gpu.{v}"),
    }
}

/// One variation of the base scene: a label and its `--set` overrides.
#[derive(Clone, Debug)]
pub struct Case {
    /// The axis (`base`, `density_ratio`, `viscosity_ratio`, `nx`, `kernel`).
    pub axis: String,
    /// The value on that axis, as text.
    pub value: String,
    /// Overrides applied to the base scene.
    pub sets: Vec<String>,
}

impl Case {
    /// `axis=value` (`base` alone for the base case).
    pub fn label(&self) -> String {
        if self.axis == "base" {
            "base".into()
        } else {
            format!("{}={}", self.axis, self.value)
        }
    }
}

/// What to sweep.
#[derive(Clone, Debug)]
pub struct StabilityOptions {
    /// dt as multiples of the tightest limit at load.
    pub dt_factors: Vec<f64>,
    /// ρ_0/ρ_1 values (two-phase scenes; phase 1's ρ0 and p_b change).
    pub density_ratios: Vec<f64>,
    /// μ_0/μ_1 values (two-phase scenes; phase 1's μ changes).
    pub viscosity_ratios: Vec<f64>,
    /// Resolutions (domain.nx).
    pub resolutions: Vec<u32>,
    /// Kernels as `kind:h_ratio`.
    pub kernels: Vec<(String, f64)>,
    /// Backends and precisions.
    pub targets: Vec<BackendId>,
    /// Steps per point.
    pub steps: u64,
    /// A sampled state every this many steps (and at the end).
    pub sample: u64,
    /// Largest |ρ/ρ0 − 1| of a stable state.
    pub density_cap: f64,
    /// Start at rest (no shape velocities, no analytic field): the largest speed is spurious.
    pub at_rest: bool,
    /// Run the points with index ≡ shard.0 (mod shard.1).
    pub shard: (usize, usize),
    /// Stop starting points after this many seconds.
    pub budget_s: Option<f64>,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        Self {
            dt_factors: vec![0.25, 0.5, 1.0, 2.0, 4.0, 8.0],
            density_ratios: vec![10.0, 100.0, 1000.0],
            viscosity_ratios: vec![10.0, 100.0],
            resolutions: vec![],
            kernels: vec![],
            targets: vec![BackendId::default()],
            steps: 100,
            sample: 10,
            density_cap: 0.2,
            at_rest: false,
            shard: (0, 1),
            budget_s: None,
        }
    }
}

/// One point of the map (one row of `records.csv`).
#[derive(Clone, Debug, Serialize)]
pub struct Record {
    /// Scene name.
    pub scene: String,
    /// The case (`base`, `density_ratio=100`, …).
    pub case: String,
    /// `cpu.f64`, `cpu.f32`, `gpu.<variant>`.
    pub target: String,
    /// f32 or f64.
    pub precision: String,
    /// Resolution.
    pub nx: u32,
    /// Fluid particles.
    pub n_fluid: usize,
    /// Kernel and h/Δx.
    pub kernel: String,
    /// ρ_0/ρ_1 (1 for one phase).
    pub density_ratio: f64,
    /// μ_0/μ_1 (1 for one phase or μ_1 = 0).
    pub viscosity_ratio: f64,
    /// dt / tightest limit.
    pub dt_factor: f64,
    /// dt.
    pub dt: f64,
    /// The tightest limit at load and its value.
    pub tightest_limit: String,
    /// Its value.
    pub tightest_limit_value: f64,
    /// Steps asked for.
    pub steps: u64,
    /// Steps done.
    pub steps_done: u64,
    /// Stable over the steps.
    pub stable: bool,
    /// The step where it failed (empty when stable).
    pub fail_step: Option<u64>,
    /// Why it failed (empty when stable).
    pub reason: String,
    /// Largest fluid speed over the sampled states.
    pub max_speed: f64,
    /// |M(t) − M(0)| / M(0), fluid mass (zero unless particles are lost: masses are constant).
    pub mass_drift: f64,
    /// |P(t) − P(0)| / (M c_max), fluid momentum (walls exchange momentum: not zero in a box).
    pub momentum_drift: f64,
    /// Largest |ρ/ρ0 − 1| over the states sampled after the start.
    pub max_density_error: f64,
    /// Wall time per step over the whole point, sampling included (ms).
    pub ms_per_step: f64,
    /// git commit.
    pub commit: String,
}

/// The cases of a sweep: the base, then one axis at a time.
pub fn cases(base: &Scene, o: &StabilityOptions) -> Vec<Case> {
    let mut v = vec![Case { axis: "base".into(), value: String::new(), sets: vec![] }];
    if base.phases.len() == 2 {
        let p0 = &base.phases[0];
        let p1 = &base.phases[1];
        for &r in &o.density_ratios {
            let rho1 = p0.rho0 / r;
            // p_b keeps its ratio to the EOS stiffness B = ρ0c0²/γ (the built-ins use p_b = B).
            let pb1 = p1.p_b * rho1 / p1.rho0;
            v.push(Case {
                axis: "density_ratio".into(),
                value: fmt_num(r),
                sets: vec![format!("phases.1.rho0={rho1:e}"), format!("phases.1.p_b={pb1:e}")],
            });
        }
        for &r in &o.viscosity_ratios {
            v.push(Case {
                axis: "viscosity_ratio".into(),
                value: fmt_num(r),
                sets: vec![format!("phases.1.mu={:e}", p0.mu / r)],
            });
        }
    }
    for &nx in &o.resolutions {
        v.push(Case { axis: "nx".into(), value: nx.to_string(), sets: vec![format!("domain.nx={nx}")] });
    }
    for (k, h) in &o.kernels {
        v.push(Case {
            axis: "kernel".into(),
            value: format!("{k}:{h}"),
            sets: vec![format!("kernel.kind=\"{k}\""), format!("kernel.h_ratio={h}")],
        });
    }
    v
}

fn fmt_num(x: f64) -> String {
    if x == x.round() {
        format!("{x:.0}")
    } else {
        format!("{x}")
    }
}

/// The scene of one point: the case applied, dt = factor × tightest limit, fixed (`warn`), no
/// relaxation; at rest if asked.
pub fn point_scene(
    base: &Scene,
    case: &Case,
    factor: f64,
    at_rest: bool,
) -> Result<(Scene, (&'static str, f64)), String> {
    let mut sets = case.sets.clone();
    sets.push("relax.t=0".into());
    let mut s = apply_overrides(base, &sets).map_err(|e| format!("case {}: {e}", case.label()))?;
    if at_rest {
        s.initial_velocity = None;
        for sh in &mut s.shapes {
            sh.velocity = [0.0, 0.0];
        }
    }
    let tight = dt_policy::limits_at(&s, s.domain.nx).tightest();
    s.time.dt = factor * tight.1;
    s.time.dt_policy = DtPolicy::Warn;
    s.time.dt_nx = 0;
    Ok((s, tight))
}

fn make(target: &BackendId, scene: &Scene, gpu: Option<&Arc<GpuContext>>) -> Result<(Box<dyn Backend>, usize), String> {
    let layout = build_layout(scene).map_err(|e| e.to_string())?;
    let n = layout.n_fluid;
    if let BackendId::Gpu(spec) = target {
        // The map's reasons for a GPU point not run: no adapter (never a new one per point), or
        // the variant's own reason.
        let g = gpu.ok_or("no GPU adapter")?;
        spec.implemented().and_then(|_| spec.support(g))?;
    }
    let mut b = target.build(scene, &layout, gpu)?;
    b.restart_with_velocities(&initial_velocities(scene, &layout, None));
    Ok((b, n))
}

fn totals(fr: &crate::backend::Frame) -> (f64, [f64; 2]) {
    let nf = fr.n_fluid;
    let mut m = 0.0;
    let mut p = [0.0; 2];
    for i in 0..nf {
        m += fr.mass[i];
        p[0] += fr.mass[i] * fr.vel[i][0];
        p[1] += fr.mass[i] * fr.vel[i][1];
    }
    (m, p)
}

/// The step a solver error names (the GPU reports a blow-up at the next check, not at once).
fn error_step(e: &crate::backend::SolverError, k: u64) -> u64 {
    use crate::backend::SolverError::*;
    match e {
        BlowUp { step, .. } | ContactOverflow { step, .. } | NeighbourOverflow { step, .. } => *step,
        Gpu(_) => k,
    }
}

/// Runs one point.
#[allow(clippy::too_many_arguments, reason = "one point of the map names its scene, target, axis and sweep settings")]
pub fn run_point(
    base: &Scene,
    case: &Case,
    factor: f64,
    target: &BackendId,
    o: &StabilityOptions,
    gpu: Option<&Arc<GpuContext>>,
    commit: &str,
) -> Result<Record, String> {
    let (scene, tight) = point_scene(base, case, factor, o.at_rest)?;
    let (mut b, n_fluid) = make(target, &scene, gpu)?;
    let c_max = scene.phases.iter().map(|p| p.c0).fold(0.0, f64::max);
    let fr0 = b.frame();
    let (m0, p0) = totals(&fr0);
    // The start's speed counts; its density does not (a GPU frame before the first step has no
    // evaluated density yet).
    let (mut max_speed, mut max_rho) = (measure(&scene, &fr0).max_speed, 0.0_f64);
    let (mut mass_drift, mut mom_drift) = (0.0_f64, 0.0_f64);
    let mut fail: Option<(u64, String)> = None;
    let start = Instant::now();
    for k in 1..=o.steps {
        if let Err(e) = b.step() {
            fail = Some((error_step(&e, k), e.to_string()));
            break;
        }
        if k % o.sample.max(1) == 0 || k == o.steps {
            let fr = b.frame();
            if let Some(e) = b.take_error() {
                fail = Some((error_step(&e, k), e.to_string()));
                break;
            }
            let row = measure(&scene, &fr);
            let (m, p) = totals(&fr);
            max_speed = max_speed.max(row.max_speed);
            max_rho = max_rho.max(row.max_density_error);
            mass_drift = mass_drift.max((m - m0).abs() / m0);
            mom_drift = mom_drift.max((p[0] - p0[0]).hypot(p[1] - p0[1]) / (m0 * c_max));
            if !(row.max_speed <= c_max) {
                fail = Some((k, format!("supersonic: fluid speed {:.3e} above c_max = {c_max}", row.max_speed)));
            } else if !(row.max_density_error <= o.density_cap) {
                fail =
                    Some((k, format!("density: |ρ/ρ0 − 1| = {:.3e} above {}", row.max_density_error, o.density_cap)));
            }
            if fail.is_some() {
                break;
            }
        }
    }
    let done = b.steps();
    let wall = start.elapsed().as_secs_f64();
    let p = &scene.phases;
    let (dr, vr) = if p.len() == 2 {
        (p[0].rho0 / p[1].rho0, if p[1].mu > 0.0 { p[0].mu / p[1].mu } else { 1.0 })
    } else {
        (1.0, 1.0)
    };
    Ok(Record {
        scene: base.name.clone(),
        case: case.label(),
        target: label(target),
        precision: target.precision().name().into(),
        nx: scene.domain.nx,
        n_fluid,
        kernel: format!("{}:{}", scene.kernel.kind.name(), scene.kernel.h_ratio),
        density_ratio: dr,
        viscosity_ratio: vr,
        dt_factor: factor,
        dt: scene.time.dt,
        tightest_limit: tight.0.into(),
        tightest_limit_value: tight.1,
        steps: o.steps,
        steps_done: done,
        stable: fail.is_none(),
        fail_step: fail.as_ref().map(|f| f.0),
        reason: fail.map(|f| f.1).unwrap_or_default(),
        max_speed,
        mass_drift,
        momentum_drift: mom_drift,
        max_density_error: max_rho,
        ms_per_step: 1e3 * wall / done.max(1) as f64,
        commit: commit.into(),
    })
}

/// The sweep's outcome: the records and the points not run (budget, shard excluded, errors).
#[derive(Clone, Debug, Default)]
pub struct Sweep {
    /// Measured points.
    pub records: Vec<Record>,
    /// `(point, why)` for points of this shard that were not measured.
    pub not_run: Vec<(String, String)>,
}

/// Every point of this shard, in a fixed order: target × case × dt factor.
pub fn sweep(base: &Scene, o: &StabilityOptions, gpu: Option<&Arc<GpuContext>>, quiet: bool) -> Sweep {
    let commit = crate::output::git_commit();
    let start = Instant::now();
    let mut out = Sweep::default();
    let cs = cases(base, o);
    let mut index = 0usize;
    for t in &o.targets {
        for c in &cs {
            for &f in &o.dt_factors {
                let mine = index % o.shard.1 == o.shard.0;
                index += 1;
                if !mine {
                    continue;
                }
                let name = format!("{} {} dt×{f}", label(t), c.label());
                if o.budget_s.is_some_and(|b| start.elapsed().as_secs_f64() > b) {
                    out.not_run.push((name, "budget".into()));
                    continue;
                }
                match run_point(base, c, f, t, o, gpu, &commit) {
                    Ok(r) => {
                        if !quiet {
                            let state = if r.stable {
                                "stable".to_string()
                            } else {
                                format!("unstable at step {}: {}", r.fail_step.unwrap_or(0), r.reason)
                            };
                            eprintln!("{name}: {state} ({:.2} ms/step)", r.ms_per_step);
                        }
                        out.records.push(r);
                    }
                    Err(e) => {
                        if !quiet {
                            eprintln!("{name}: not run: {e}");
                        }
                        out.not_run.push((name, e));
                    }
                }
            }
        }
    }
    out
}

/// The first dt factor at which `records` (one target, one case) are unstable, if any.
pub fn first_unstable(records: &[&Record]) -> Option<f64> {
    let mut r: Vec<&&Record> = records.iter().collect();
    r.sort_by(|a, b| a.dt_factor.total_cmp(&b.dt_factor));
    r.iter().find(|r| !r.stable).map(|r| r.dt_factor)
}
