//! The `sphlab run` driver: builds the scene, relaxes it if asked, applies the initial velocity
//! field, steps a backend and writes `series.csv`, particle snapshots (CSV, optional VTK with a
//! `.pvd` series) and `summary.json`. Before anything big is allocated the scene's resource
//! plan ([`crate::plan`]) is checked against the limits (exit 2). A blow-up keeps every file
//! written so far, writes a final snapshot and a summary naming the step and particle, and maps
//! to exit code 3; an interrupt ([`request_interrupt`], Ctrl-C) stops at the next step with a
//! final snapshot and `status: "interrupted"` (exit 130). A buffer that cannot be allocated
//! after all (diagnostic grid, VTK text) or an output that cannot be written stops the run with
//! the files so far closed and `status: "failed"` plus the reason in `summary.json` (exit 3 for
//! the allocation, naming the buffer and its bytes; exit 1 for the output).

use crate::backend::{Backend, EngineCounters, EnginePerStep, Frame, SolverError};
use crate::backend_id::BackendId;
use crate::diagnostics::{contact_angle, flow};
use crate::fallible::AllocError;
use crate::gpu::bandwidth::EngineTraffic;
use crate::output::{self, PvdWriter, SeriesWriter, Snapshot};
use crate::plan::{Limits, Plan};
use crate::provenance::{GpuInfo, Provenance, RUN_UNITS};
use crate::scene::build::{build_layout, Layout};
use crate::scene::initial::initial_velocities;
use crate::scene::{ContactMode, Scene, SceneError, ShapeKind, Side};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

static INTERRUPT: AtomicBool = AtomicBool::new(false);

/// Asks a running [`run`] to stop after its current step (the Ctrl-C handler calls this).
/// Returns true when an interrupt had already been requested.
pub fn request_interrupt() -> bool {
    INTERRUPT.swap(true, Ordering::SeqCst)
}

/// True once an interrupt was requested.
pub fn interrupt_requested() -> bool {
    INTERRUPT.load(Ordering::SeqCst)
}

/// Errors of a run, with their exit codes.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Bad input (exit 2).
    #[error("{0}")]
    Input(String),
    /// The run blew up (exit 3); outputs so far are kept.
    #[error("{0}")]
    BlowUp(SolverError),
    /// Writing an output failed (exit 1).
    #[error("{0}")]
    Output(output::OutputError),
    /// A buffer could not be allocated mid-run (exit 3); outputs so far are kept.
    #[error(
        "{source}{}; the outputs written before it are kept and summary.json says status \"failed\"",
        .file.as_ref().map_or(String::new(), |f| format!(", writing {}", f.display()))
    )]
    Alloc {
        /// What was being allocated, and how many bytes.
        source: AllocError,
        /// The output file it was for, if any.
        file: Option<PathBuf>,
    },
    /// Stopped by an interrupt (exit 130) after `step` steps; outputs so far are kept.
    #[error("interrupted at step {step} (t = {t:.6e}); a final snapshot and summary.json were written")]
    Interrupted {
        /// Steps taken.
        step: u64,
        /// Time reached.
        t: f64,
    },
}

impl From<output::OutputError> for RunError {
    fn from(e: output::OutputError) -> Self {
        match e {
            output::OutputError::Alloc { path, source } => RunError::Alloc { source, file: Some(path) },
            e => RunError::Output(e),
        }
    }
}

impl From<AllocError> for RunError {
    fn from(source: AllocError) -> Self {
        RunError::Alloc { source, file: None }
    }
}

impl From<SceneError> for RunError {
    fn from(e: SceneError) -> Self {
        RunError::Input(e.to_string())
    }
}

impl RunError {
    /// Process exit code.
    pub fn exit_code(&self) -> i32 {
        match self {
            RunError::Input(_) => 2,
            RunError::BlowUp(_) | RunError::Alloc { .. } => 3,
            RunError::Output(_) => 1,
            RunError::Interrupted { .. } => 130,
        }
    }
}

/// Options of `sphlab run`.
#[derive(Clone, Debug, Serialize)]
pub struct RunOptions {
    /// The backend (`cpu.cells.f64`, a GPU variant id, …).
    pub backend: BackendId,
    /// Overrides the scene's end time.
    pub t_end: Option<f64>,
    /// Run exactly this many steps instead.
    pub steps: Option<u64>,
    /// Output directory.
    pub out: PathBuf,
    /// A particle snapshot at every step that is a multiple of this (0: only the first and the
    /// last); the first (step 0) and the last step always get one.
    pub every: u64,
    /// Also write VTK.
    pub vtk: bool,
    /// No progress bar, no console lines.
    pub quiet: bool,
    /// Particle and memory limits of the resource plan.
    pub limits: Limits,
    /// At most this many steps per `Backend::advance` (one GPU submission and one readback),
    /// cut at output rows, snapshots and the end; 0: [`DEFAULT_STEPS_PER_SUBMIT`].
    pub steps_per_submit: u64,
}

/// Steps per submission when `--steps-per-submit` is 0 (output steps cut batches shorter).
pub const DEFAULT_STEPS_PER_SUBMIT: u64 = 64;
/// Largest accepted `--steps-per-submit` (a submission records ≈ 20 dispatches per step).
pub const MAX_STEPS_PER_SUBMIT: u64 = 4096;

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            backend: BackendId::default(),
            t_end: None,
            steps: None,
            out: PathBuf::from("out"),
            every: 10,
            vtk: false,
            quiet: true,
            limits: Limits::default(),
            steps_per_submit: 0,
        }
    }
}

/// One row of `series.csv` (read back by `validate`).
#[derive(Clone, Debug, Serialize, serde::Deserialize, Default)]
pub struct SeriesRow {
    /// Time.
    pub t: f64,
    /// Step.
    pub step: u64,
    /// Last dt.
    pub dt: f64,
    /// Kinetic energy of the liquid (phase 0).
    pub kinetic_energy: f64,
    /// Liquid centroid x.
    pub centroid_x: f64,
    /// Liquid centroid y.
    pub centroid_y: f64,
    /// Total mass of phase 0.
    pub mass_phase0: f64,
    /// Total mass of phase 1 (0 if absent).
    pub mass_phase1: f64,
    /// max |ρ/ρ0 − 1| over fluid particles.
    pub max_density_error: f64,
    /// Max fluid speed.
    pub max_speed: f64,
    /// The limit that binds at this row's state (`cfl`, `viscous`, `force`, `capillary`): the one
    /// that sets an automatic dt; `fixed` when the scene's dt is fixed.
    #[serde(default)]
    pub dt_limit: String,
    /// dt over the tightest limit at this row's state (≈ 1 for an automatic dt; above 1: a
    /// fixed dt past a limit).
    #[serde(default)]
    pub dt_over_limit: f64,
    /// Contact angle, two-point method (degrees; empty when not measurable).
    pub theta_two_point: Option<f64>,
    /// Contact angle, circle fit.
    pub theta_circle_fit: Option<f64>,
    /// Contact angle, area inversion.
    pub theta_area: Option<f64>,
    /// Contact half-width x_tp.
    pub x_tp: Option<f64>,
    /// Spread factor D/D0.
    pub spread_factor: Option<f64>,
}

/// Measures one series row from a frame (the circle fit empty where its buffers cannot be
/// allocated; [`try_measure`] says so).
pub fn measure(scene: &Scene, fr: &Frame) -> SeriesRow {
    let angles = |pos: &[[f64; 2]], phase: &[u32], dx, y_w, mirrored| {
        Ok::<_, std::convert::Infallible>(contact_angle::measure_all(pos, phase, dx, y_w, mirrored))
    };
    match measure_with(scene, fr, angles) {
        Ok(row) => row,
        Err(never) => match never {},
    }
}

/// [`measure`], or the allocation of the contact-angle diagnostic that failed (its buffers are
/// at most [`contact_angle::max_bytes`] of the fluid particles).
pub fn try_measure(scene: &Scene, fr: &Frame) -> Result<SeriesRow, AllocError> {
    measure_with(scene, fr, contact_angle::try_measure_all)
}

/// One series row, the contact angles from `angles`.
fn measure_with<E>(
    scene: &Scene,
    fr: &Frame,
    angles: impl Fn(&[[f64; 2]], &[u32], f64, f64, bool) -> Result<contact_angle::ContactAngles, E>,
) -> Result<SeriesRow, E> {
    let nf = fr.n_fluid;
    let (mass, pos, vel, phase) = (&fr.mass[..nf], &fr.pos[..nf], &fr.vel[..nf], &fr.phase[..nf]);
    let c = flow::centroid(mass, pos, phase, 0);
    let m = flow::mass_per_phase(mass, phase, scene.phases.len());
    let rho0: Vec<f64> = scene.phases.iter().map(|p| p.rho0).collect();
    let norm = |v: &[f64; 2]| v[0].hypot(v[1]);
    let (v_max, a_max) = (
        vel.iter().map(norm).fold(0.0, f64::max),
        fr.acc.get(..nf).map_or(0.0, |a| a.iter().map(norm).fold(0.0, f64::max)),
    );
    let (limit, tight) = crate::scene::dt_policy::tightest(&crate::scene::dt_policy::state_limits(scene, v_max, a_max));
    let mut row = SeriesRow {
        t: fr.t,
        step: fr.step,
        dt: fr.dt,
        kinetic_energy: flow::kinetic_energy(mass, vel, phase, 0),
        centroid_x: c[0],
        centroid_y: c[1],
        mass_phase0: m[0],
        mass_phase1: m.get(1).copied().unwrap_or(0.0),
        max_density_error: flow::max_density_error(&fr.rho[..nf], &rho0, phase),
        max_speed: v_max,
        dt_limit: if scene.time.dt > 0.0 { "fixed" } else { limit }.into(),
        dt_over_limit: fr.dt / tight,
        ..Default::default()
    };
    if scene.contact.mode != ContactMode::None {
        let dx = scene.domain.dx();
        let y_w = scene.domain.y[0];
        let mirrored = scene.domain.left == Side::Mirror;
        let a = angles(pos, phase, dx, y_w, mirrored)?;
        row.theta_two_point = a.two_point;
        row.theta_circle_fit = a.circle_fit;
        row.theta_area = a.area;
        row.x_tp = contact_angle::contact_half_width(pos, phase, dx, y_w);
        if let (Some(x), Some(r0)) = (row.x_tp, initial_radius(scene)) {
            row.spread_factor = Some(if mirrored { x / r0 } else { x / (2.0 * r0) });
        }
    }
    Ok(row)
}

/// Radius of the first circle of phase 0 (the drop), for D/D0.
pub fn initial_radius(scene: &Scene) -> Option<f64> {
    let liquid = &scene.phases[0].name;
    scene.shapes.iter().find(|s| s.kind == ShapeKind::Circle && &s.phase == liquid).and_then(|s| s.radius)
}

/// What `summary.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// The scene as run (all parameters).
    pub parameters: Scene,
    /// The options.
    pub options: RunOptions,
    /// Active stages in order.
    pub active_stages: Vec<&'static str>,
    /// Fluid particles per phase (by name).
    pub particles_per_phase: Vec<(String, usize)>,
    /// Wall particles.
    pub wall_particles: usize,
    /// Backend name (cpu, cpu1, or variant id).
    pub backend: String,
    /// Precision the backend computes in (f64, f32; a GPU variant's own).
    pub precision: String,
    /// dt of the last step.
    pub dt_last: f64,
    /// Steps taken after t = 0.
    pub steps: u64,
    /// Relaxation steps before t = 0.
    pub relax_steps: u64,
    /// Final time.
    pub t_final: f64,
    /// Wall time of the stepping after t = 0 (s).
    pub wall_time_s: f64,
    /// Wall time per step (ms).
    pub ms_per_step: f64,
    /// "running", "ok", "interrupted", "blow-up: …" or "failed" (an allocation or an output
    /// failed mid-run: [`Summary::error`] says which).
    pub status: String,
    /// Why a `failed` run stopped (the buffer and its bytes, or the output file).
    pub error: Option<String>,
    /// The resource plan the run was admitted with.
    pub plan: Plan,
    /// GPU runs: device bytes, modelled bytes per evaluation, measured bandwidth and the
    /// fraction of the memory roofline (`gpu::bandwidth`).
    pub gpu_engine: Option<EngineTraffic>,
    /// Commit, date, host, GPU and units.
    pub provenance: Provenance,
    /// Stability limits the fixed dt is above at load (`time.dt_policy = "warn"` only), and
    /// while running (from the output rows' measured |v| and |a|).
    pub dt_warnings: Vec<String>,
    /// The largest CFL / viscous numbers and dt over the force limit at the output rows.
    pub stability_numbers: crate::physics::timestep::StabilityNumbers,
    /// What the GPU engine did during the stepping after t = 0 (`None` on the CPU).
    pub engine: Option<EngineReport>,
}

/// The GPU engine's own counts over a run's stepping after t = 0 (`Backend::engine_counters`).
#[derive(Clone, Debug, Serialize)]
pub struct EngineReport {
    /// Largest batch of steps per submission.
    pub steps_per_submit: u64,
    /// Totals of the `advance` calls alone (the stepping).
    pub counters: EngineCounters,
    /// Submits, readbacks, dispatches and host writes per step of the stepping alone.
    pub per_step: EnginePerStep,
    /// Totals including the output frames (series rows and snapshots read every field back).
    pub with_output: EngineCounters,
    /// Per step including the output frames.
    pub per_step_with_output: EnginePerStep,
}

/// Steps of the next batch from `step` at time `t`: at most `k_max`, ending at the next output
/// row (`rows`), snapshot (`snaps`, 0: none) and the end (`steps` if given); a time-driven run
/// leaves its last steps to single steps so it never passes `t_end` (estimating dt as `dt_est`:
/// up to the step before the end with a fixed dt, half the remaining steps with an adaptive one).
#[allow(clippy::too_many_arguments)]
pub fn batch_len(
    k_max: u64,
    step: u64,
    rows: u64,
    snaps: u64,
    steps: Option<u64>,
    t: f64,
    t_end: f64,
    dt_est: Option<(f64, bool)>,
) -> u64 {
    let next = |every: u64| step.checked_div(every).map_or(u64::MAX, |q| (q + 1) * every - step);
    let mut k = k_max.min(next(rows)).min(next(snaps));
    match (steps, dt_est) {
        (Some(n), _) => k = k.min(n.saturating_sub(step)),
        (None, Some((dt, fixed))) if dt > 0.0 => {
            let left = ((t_end - t) / dt).floor().clamp(0.0, 1e12) as u64;
            k = k.min(if fixed { left.saturating_sub(1) } else { left / 2 });
        }
        (None, _) => k = 1,
    }
    k.max(1)
}

/// Builds the backend named in the options.
pub fn make_backend(scene: &Scene, layout: &Layout, opts: &RunOptions) -> Result<Box<dyn Backend>, RunError> {
    make_backend_with_gpu_info(scene, layout, opts, None).map(|(b, _)| b)
}

/// [`make_backend`], also returning the adapter where a GPU was used; with `plan`, the GPU's
/// buffers are checked against the adapter's limits first (exit 2 with the numbers), and the
/// engine's traffic figures come back (the bandwidth probe runs before the solver's buffers
/// exist). A GPU variant this adapter cannot run is an input error (exit 2) with the reason.
pub fn make_backend_with_gpu_info(
    scene: &Scene,
    layout: &Layout,
    opts: &RunOptions,
    plan: Option<&Plan>,
) -> Result<(Box<dyn Backend>, Option<GpuInfo>), RunError> {
    make_gpu_backend(scene, layout, opts, plan).map(|(b, info, _)| (b, info))
}

/// A built backend with the GPU's description and the engine's traffic figures.
pub type GpuBackend = (Box<dyn Backend>, Option<GpuInfo>, Option<EngineTraffic>);

/// [`make_backend_with_gpu_info`] with the engine's traffic figures (GPU runs with a `plan`).
pub fn make_gpu_backend(
    scene: &Scene,
    layout: &Layout,
    opts: &RunOptions,
    plan: Option<&Plan>,
) -> Result<GpuBackend, RunError> {
    let input = |e: String| RunError::Input(format!("--backend {}: {e}", opts.backend));
    let BackendId::Gpu(spec) = opts.backend else {
        return Ok((opts.backend.build(scene, layout, None).map_err(input)?, None, None));
    };
    let ctx = crate::gpu::GpuContext::new().map_err(|e| input(e.to_string()))?;
    spec.support(&ctx).map_err(|e| input(format!("unsupported on this adapter: {e}")))?;
    let mut traffic = None;
    if let Some(p) = plan {
        let lim = crate::gpu::plan::DeviceLimits::of(&ctx, opts.limits.gpu_memory);
        p.check_gpu(&lim).map_err(RunError::Input)?;
        let bw = crate::gpu::bandwidth::measure_bandwidth(&ctx).map_err(|e| input(e.to_string()))?;
        let bytes = p.gpu.as_ref().map_or(0, |g| g.total_bytes);
        traffic = Some(EngineTraffic::new(&spec, scene, layout.pos.len(), layout.n_fluid, bytes, bw));
    }
    let info = GpuInfo::from_adapter(&ctx.adapter_info);
    let b = opts.backend.build(scene, layout, Some(&std::sync::Arc::new(ctx))).map_err(input)?;
    Ok((b, Some(info), traffic))
}

/// The resource plan of `scene` under `opts` (backend and precision), checked against
/// `opts.limits`: an input error with every number when it does not fit.
pub fn plan_for(scene: &Scene, opts: &RunOptions) -> Result<Plan, RunError> {
    let real = if opts.backend.precision() == crate::real::Precision::F32 { 4 } else { 8 };
    let mut plan =
        crate::resources::with_vtk(crate::resources::run_plan(scene, real, opts.backend.kind() == "gpu"), opts.vtk);
    if let BackendId::Gpu(spec) = opts.backend {
        plan = plan.for_variant(&spec);
    }
    plan.check(&opts.limits).map_err(RunError::Input)?;
    Ok(plan)
}

/// The snapshot of a frame, its arrays moved (no copy).
fn snapshot(fr: Frame, h: f64) -> Snapshot {
    Snapshot {
        step: fr.step,
        t: fr.t,
        pos: fr.pos,
        vel: fr.vel,
        rho: fr.rho,
        p: fr.p,
        phase: fr.phase,
        grad_c: fr.grad_c,
        mass: fr.mass,
        h,
    }
}

/// Runs a scene with outputs in `opts.out`. Returns the summary (also written to disk).
///
/// Order: every input is checked (scene fields, options, the resource plan against the limits)
/// before the particles are laid out and before the output directory is created.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<Summary, RunError> {
    scene.validate()?;
    // Whether the scene fits at all comes first (a resolution beyond memory is refused as such,
    // whatever its dt); the dt policy does not change the particle count.
    plan_for(scene, opts)?;
    // The one dt check at load: the scene from here on carries its effective dt.
    let applied = crate::scene::dt_policy::apply(scene)?;
    let scene = &applied.scene;
    for w in &applied.warnings {
        if !opts.quiet {
            eprintln!("warning: time.dt_policy = \"warn\": dt = {:.4e} is above the {w}", scene.time.dt);
        }
    }
    if let Some(t) = opts.t_end {
        if !(t.is_finite() && t > 0.0 && t <= crate::scene::validate::MAX_TIME) {
            return Err(RunError::Input(format!(
                "--t-end: must be a finite number in (0, {:e}], got {t}",
                crate::scene::validate::MAX_TIME
            )));
        }
        if t <= scene.time.dt {
            return Err(RunError::Input(format!("--t-end: must exceed time.dt = {:e}, got {t}", scene.time.dt)));
        }
    }
    if opts.steps == Some(0) {
        return Err(RunError::Input("--steps: must be at least 1".into()));
    }
    if opts.steps_per_submit > MAX_STEPS_PER_SUBMIT {
        return Err(RunError::Input(format!(
            "--steps-per-submit: must be in 0..={MAX_STEPS_PER_SUBMIT} (0: {DEFAULT_STEPS_PER_SUBMIT}), got {}",
            opts.steps_per_submit
        )));
    }
    output::check_out_dir(&opts.out).map_err(|e| RunError::Input(format!("--out: {e}")))?;
    let plan = plan_for(scene, opts)?;
    let layout = build_layout(scene)?;
    let (mut backend, gpu, gpu_engine) = make_gpu_backend(scene, &layout, opts, Some(&plan))?;
    std::fs::create_dir_all(&opts.out)
        .map_err(|e| RunError::Input(format!("--out: cannot create {}: {e}", opts.out.display())))?;
    let model = crate::model::Model::<f64>::new(scene);
    let stages = model.stages.names();
    if !opts.quiet {
        eprintln!(
            "sphlab run {}: {} fluid + {} wall particles, backend {} {}, stages: {}",
            scene.name,
            layout.n_fluid,
            layout.n_wall(),
            backend.name(),
            backend.precision(),
            stages.join(" → ")
        );
    }
    let mut summary = Summary {
        scene: scene.name.clone(),
        parameters: scene.clone(),
        options: opts.clone(),
        active_stages: stages,
        particles_per_phase: scene
            .phases
            .iter()
            .zip(layout.count_per_phase(scene.phases.len()))
            .map(|(p, n)| (p.name.clone(), n))
            .collect(),
        wall_particles: layout.n_wall(),
        backend: opts.backend.to_string(),
        precision: backend.precision().to_string(),
        dt_last: 0.0,
        steps: 0,
        relax_steps: 0,
        t_final: 0.0,
        wall_time_s: 0.0,
        ms_per_step: 0.0,
        status: "running".into(),
        error: None,
        plan,
        gpu_engine,
        provenance: Provenance::new(opts.backend.to_string(), gpu, RUN_UNITS),
        dt_warnings: applied.warnings.clone(),
        stability_numbers: Default::default(),
        engine: None,
    };
    let summary_path = opts.out.join("summary.json");
    output::write_json(&summary_path, &summary)?;
    match step_and_write(scene, opts, &layout, &mut backend, &mut summary, &summary_path) {
        Ok(()) => Ok(summary),
        Err(e) => Err(failed(e, &mut summary, backend.as_ref(), &summary_path)),
    }
}

/// A run stopped by an allocation or output error: `summary.json` says `failed` and why (the
/// series and snapshot files are complete up to the last row and snapshot written). Other
/// errors wrote their own summary.
fn failed(e: RunError, summary: &mut Summary, backend: &dyn Backend, path: &Path) -> RunError {
    if matches!(e, RunError::Alloc { .. } | RunError::Output(_)) {
        summary.status = "failed".into();
        summary.error = Some(e.to_string());
        summary.steps = backend.steps();
        summary.t_final = backend.time();
        let _ = output::write_json(path, &*summary);
    }
    e
}

/// The stepping after the summary of a started run is written: relaxation, the initial
/// velocity field, the steps with their series rows and snapshots, the final summary.
fn step_and_write(
    scene: &Scene,
    opts: &RunOptions,
    layout: &Layout,
    backend: &mut Box<dyn Backend>,
    summary: &mut Summary,
    summary_path: &Path,
) -> Result<(), RunError> {
    let h = scene.h();

    // CFL / viscous numbers at the output rows: the GPU's blow-up messages quote them (the CPU
    // solver records them at every step itself).
    let mut numbers = crate::physics::timestep::StabilityNumbers::default();
    let note = |numbers: &mut crate::physics::timestep::StabilityNumbers, fr: &Frame| -> Result<SeriesRow, RunError> {
        let row = try_measure(scene, fr)?;
        let a = fr.acc.get(..fr.n_fluid).map_or(0.0, |a| a.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max));
        let l = crate::scene::dt_policy::state_limits(scene, row.max_speed, a);
        numbers.record(fr.step, if fr.dt > 0.0 { fr.dt } else { l.min() }, scene.time.cfl, &l);
        Ok(row)
    };
    let started = Instant::now();
    // A failed or interrupted run keeps a final snapshot and a summary saying why it stopped.
    let stop = |summary: &mut Summary,
                backend: &mut Box<dyn Backend>,
                status: String,
                pvd: Option<&mut PvdWriter>|
     -> Result<(), RunError> {
        let fr = backend.frame();
        summary.dt_last = fr.dt;
        let snap = snapshot(fr, h);
        output::write_particles_csv(&opts.out, &snap)?;
        if let Some(p) = pvd {
            p.add_snapshot(&snap)?;
        }
        summary.status = status;
        summary.steps = backend.steps();
        summary.t_final = backend.time();
        summary.ms_per_step = 1e3 * summary.wall_time_s / summary.steps.max(1) as f64;
        output::write_json(summary_path, &*summary)?;
        Ok(())
    };
    // A blow-up's message also quotes the largest CFL and viscous numbers reached before it; the
    // summary keeps the wall time, steps and ms/step of the failed run.
    let fail = |summary: &mut Summary,
                backend: &mut Box<dyn Backend>,
                mut e: SolverError,
                pvd: Option<&mut PvdWriter>,
                numbers: &crate::physics::timestep::StabilityNumbers,
                wall: f64| {
        if let SolverError::BlowUp { what, .. } = &mut e {
            if !what.contains("CFL number") {
                what.push_str(&format!("; at the output rows before it: {}", numbers.describe(scene.time.cfl)));
            }
        }
        summary.stability_numbers = *numbers;
        summary.wall_time_s = wall;
        let _ = stop(summary, backend, format!("blow-up: {e}"), pvd);
        RunError::BlowUp(e)
    };
    let interrupted = |summary: &mut Summary, backend: &mut Box<dyn Backend>, pvd: Option<&mut PvdWriter>| match stop(
        summary,
        backend,
        "interrupted".into(),
        pvd,
    ) {
        Ok(()) => RunError::Interrupted { step: backend.steps(), t: backend.time() },
        Err(e) => e,
    };

    let k_max = if opts.steps_per_submit == 0 { DEFAULT_STEPS_PER_SUBMIT } else { opts.steps_per_submit };
    // Relaxation (in batches of steps, never past its end), then the initial velocity field.
    if let Some(r) = scene.relax.as_ref().filter(|r| r.t > 0.0) {
        let bar = if opts.quiet {
            output::Progress::hidden()
        } else {
            output::Progress::new((r.t / scene.time.dt.max(1e-300)).min(1e12) as u64, "relax")
        };
        let mut dt_est = (scene.time.dt > 0.0).then_some((scene.time.dt, true));
        while backend.time() < r.t * (1.0 - 1e-12) {
            let (step0, t0) = (backend.steps(), backend.time());
            if let Err(e) = backend.advance(batch_len(k_max, step0, 0, 0, None, t0, r.t, dt_est)) {
                let wall = started.elapsed().as_secs_f64();
                return Err(fail(summary, backend, e, None, &numbers, wall));
            }
            if interrupt_requested() {
                summary.relax_steps = backend.steps();
                return Err(interrupted(summary, backend, None));
            }
            let step = backend.steps();
            if scene.time.dt <= 0.0 && step > step0 {
                dt_est = Some(((backend.time() - t0) / (step - step0) as f64, false));
            }
            bar.inc(step - step0);
        }
        bar.finish();
        summary.relax_steps = backend.steps();
        let fr = backend.frame();
        backend.restart_with_velocities(&initial_velocities(scene, layout, Some(&fr)));
    } else if scene.initial_velocity.is_some() {
        backend.restart_with_velocities(&initial_velocities(scene, layout, None));
    }

    let t_end = opts.t_end.unwrap_or(scene.time.t_end);
    let total = opts.steps.unwrap_or_else(|| {
        if scene.time.dt > 0.0 {
            (t_end / scene.time.dt).round().min(1e12) as u64
        } else {
            0
        }
    });
    let bar = if opts.quiet { output::Progress::hidden() } else { output::Progress::new(total, &scene.name) };
    let mut series = SeriesWriter::create(opts.out.join("series.csv"))?;
    let mut pvd = if opts.vtk { Some(PvdWriter::new(&opts.out)) } else { None };
    let write_frame = |fr: Frame, pvd: &mut Option<PvdWriter>| -> Result<(), RunError> {
        let snap = snapshot(fr, h);
        output::write_particles_csv(&opts.out, &snap)?;
        if let Some(p) = pvd.as_mut() {
            p.add_snapshot(&snap)?;
        }
        Ok(())
    };
    let fr = backend.frame();
    series.write(&note(&mut numbers, &fr)?)?;
    write_frame(fr, &mut pvd)?;
    let start = Instant::now();
    let engine0 = backend.engine_counters();
    let mut stepping = EngineCounters::default();
    let done = |b: &dyn Backend| match opts.steps {
        Some(n) => b.steps() >= n,
        None => b.time() >= t_end * (1.0 - 1e-12),
    };
    // dt of the next steps, for the batch length of a time-driven run: the fixed dt, or the mean
    // of the last batch.
    let mut dt_est = (scene.time.dt > 0.0).then_some((scene.time.dt, true));
    while !done(backend.as_ref()) {
        let (step0, t0) = (backend.steps(), backend.time());
        let k = batch_len(k_max, step0, scene.output.every, opts.every, opts.steps, t0, t_end, dt_est);
        let before = backend.engine_counters();
        if let Err(e) = backend.advance(k) {
            let wall = start.elapsed().as_secs_f64();
            return Err(fail(summary, backend, e, pvd.as_mut(), &numbers, wall));
        }
        if let (Some(b), Some(a)) = (before, backend.engine_counters()) {
            stepping = stepping.plus(&a.since(&b));
        }
        let step = backend.steps();
        bar.inc(step - step0);
        if scene.time.dt <= 0.0 && step > step0 {
            dt_est = Some(((backend.time() - t0) / (step - step0) as f64, false));
        }
        let last = done(backend.as_ref());
        let row_due = step.is_multiple_of(scene.output.every) || last;
        let snap_due = last || (opts.every > 0 && step.is_multiple_of(opts.every));
        if row_due || snap_due {
            let fr = backend.frame();
            if let Some(e) = backend.take_error() {
                let wall = start.elapsed().as_secs_f64();
                return Err(fail(summary, backend, e, pvd.as_mut(), &numbers, wall));
            }
            if row_due {
                series.write(&note(&mut numbers, &fr)?)?;
            }
            if snap_due {
                write_frame(fr, &mut pvd)?;
            }
        }
        if interrupt_requested() && !last {
            summary.wall_time_s = start.elapsed().as_secs_f64();
            let fr = backend.frame();
            if !row_due {
                series.write(&try_measure(scene, &fr)?)?;
            }
            series.finish()?;
            return Err(interrupted(summary, backend, pvd.as_mut()));
        }
    }
    bar.finish();
    let wall = start.elapsed().as_secs_f64();
    if let Some(e) = backend.take_error() {
        return Err(fail(summary, backend, e, pvd.as_mut(), &numbers, wall));
    }
    let fr = backend.frame();
    summary.dt_last = fr.dt;
    summary.steps = backend.steps();
    summary.t_final = backend.time();
    summary.wall_time_s = wall;
    summary.ms_per_step = 1e3 * wall / summary.steps.max(1) as f64;
    summary.status = "ok".into();
    summary.stability_numbers = numbers;
    if let Some(g) = summary.gpu_engine.as_mut() {
        g.roofline_fraction = g.fraction(wall / summary.steps.max(1) as f64);
    }
    if let (Some(c0), Some(c1)) = (engine0, backend.engine_counters()) {
        let with_output = c1.since(&c0);
        summary.engine = Some(EngineReport {
            steps_per_submit: k_max,
            counters: stepping,
            per_step: stepping.per_step(),
            with_output,
            per_step_with_output: with_output.per_step(),
        });
    }
    let (c, v, f) = (numbers.cfl_number, numbers.viscous_number, numbers.force_ratio);
    let viscous_max = crate::physics::timestep::VISCOUS_NUMBER_LIMIT;
    if scene.time.dt > 0.0 && (c > scene.time.cfl * (1.0 + 1e-9) || v > viscous_max * (1.0 + 1e-9) || f > 1.0) {
        let w = format!("while running, the fixed dt went past a limit: {}", numbers.describe(scene.time.cfl));
        if !opts.quiet {
            eprintln!("warning: {w}");
        }
        summary.dt_warnings.push(w);
    }
    series.finish()?;
    output::write_json(summary_path, &*summary)?;
    if !opts.quiet {
        eprintln!(
            "done: {} steps to t = {:.6e} in {:.2} s ({:.3} ms/step); outputs in {}",
            summary.steps,
            summary.t_final,
            wall,
            summary.ms_per_step,
            opts.out.display()
        );
        if let Some(g) = &summary.gpu_engine {
            eprintln!("GPU engine (time per step from the wall clock, outputs included): {}", g.describe());
        }
        if let Some(e) = &summary.engine {
            let (p, o) = (e.per_step, e.per_step_with_output);
            eprintln!(
                "engine: {:.4} submits, {:.4} readbacks, {:.1} dispatches, {:.4} host writes per step \
                 ({} steps, at most {} per submit); with the output frames {:.3} submits, {:.3} readbacks per step",
                p.submits,
                p.readbacks,
                p.dispatches,
                p.writes,
                e.counters.steps,
                e.steps_per_submit,
                o.submits,
                o.readbacks
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{batch_len, RunError};
    use crate::fallible::AllocError;
    use crate::output::OutputError;

    #[test]
    fn an_allocation_failure_mid_run_exits_3_naming_the_buffer_and_bytes() {
        let source = AllocError { what: "the VTK text of one data array", bytes: 240_000_256 };
        let e = RunError::from(OutputError::Alloc { path: "out/particles_00000010.vtu".into(), source });
        assert_eq!(e.exit_code(), 3);
        let m = e.to_string();
        assert!(
            m.contains("could not allocate 240000256 bytes (228.88 MiB) for the VTK text of one data array")
                && m.contains("particles_00000010.vtu")
                && m.contains("status \"failed\""),
            "{m}"
        );
        let grid = RunError::from(AllocError { what: "the contact-angle gas grid", bytes: 1 << 30 });
        assert!(grid.exit_code() == 3 && grid.to_string().contains("gas grid"), "{grid}");
        let io = RunError::from(OutputError::Data { path: "x".into(), message: "m".into() });
        assert_eq!(io.exit_code(), 1);
    }

    #[test]
    fn batches_end_at_outputs_and_never_pass_the_end() {
        // Step counts: the next row (every 10), snapshot (every 25) or the last step cuts.
        assert_eq!(batch_len(64, 0, 10, 0, Some(100), 0.0, 1.0, None), 10);
        assert_eq!(batch_len(64, 20, 10, 25, Some(100), 0.0, 1.0, None), 5);
        assert_eq!(batch_len(4, 0, 10, 0, Some(100), 0.0, 1.0, None), 4);
        assert_eq!(batch_len(64, 95, 1000, 0, Some(100), 0.0, 1.0, None), 5);
        // Time-driven, fixed dt 1/8 to t_end 4 (exact in binary): stop one step short, then
        // single steps.
        assert_eq!(batch_len(64, 0, 1000, 0, None, 0.0, 4.0, Some((0.125, true))), 31);
        assert_eq!(batch_len(64, 0, 1000, 0, None, 2.0, 4.0, Some((0.125, true))), 15);
        assert_eq!(batch_len(64, 0, 1000, 0, None, 3.875, 4.0, Some((0.125, true))), 1);
        // Adaptive: half the estimated remainder; no estimate yet: one step.
        assert_eq!(batch_len(64, 0, 1000, 0, None, 2.0, 4.0, Some((0.125, false))), 8);
        assert_eq!(batch_len(64, 0, 1000, 0, None, 0.0, 1.0, None), 1);
    }
}
