//! Preparing a run of `sphlab run`: the checks of every input (scene, options, the resource
//! plan against the limits), the backend (a GPU's adapter checked first), the output folder and
//! the first `summary.json`, before the step loop ([`super::step`]) takes over.

use super::finish::failed;
use super::step::Stepping;
use super::{RunError, RunOptions, Summary, DEFAULT_STEPS_PER_SUBMIT, MAX_STEPS_PER_SUBMIT};
use crate::backend::Backend;
use crate::backend_id::BackendId;
use crate::gpu::bandwidth::EngineTraffic;
use crate::output;
use crate::plan::Plan;
use crate::provenance::{GpuInfo, Provenance, RUN_UNITS};
use crate::scene::build::{build_layout, Layout};
use crate::scene::Scene;

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
    let ctx = match opts.limits.gpu_binding {
        Some(b) => ctx.with_binding_cap(b),
        None => ctx,
    };
    spec.support(&ctx).map_err(|e| input(format!("unsupported on this adapter: {e}")))?;
    let mut traffic = None;
    if let Some(p) = plan {
        let lim = crate::gpu::plan::DeviceLimits::of(&ctx, opts.limits.gpu_memory);
        p.check_gpu(&lim).map_err(RunError::Input)?;
        let bw = crate::gpu::bandwidth::measure_bandwidth(&ctx, crate::gpu::bandwidth::QUICK_PROBE_BYTES)
            .map_err(|e| input(e.to_string()))?;
        let gpu = p.gpu.as_ref().map(|g| crate::gpu::plan::GpuPlan::resolved(&g.spec, g.n, g.cells, &lim));
        let (spec, bytes) = gpu.map_or((spec, 0), |g| (g.spec, g.total_bytes));
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
    check_options(scene, opts)?;
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
    let mut summary = Summary::started(scene, opts, &layout, backend.as_ref(), stages, plan, gpu_engine, gpu);
    summary.dt_warnings = applied.warnings.clone();
    let summary_path = opts.out.join("summary.json");
    output::write_json(&summary_path, &summary)?;
    let stepped = Stepping::new(scene, opts, &mut backend, &mut summary, &summary_path).run(&layout);
    match stepped {
        Ok(()) => Ok(summary),
        Err(e) => Err(failed(e, &mut summary, backend.as_ref(), &summary_path)),
    }
}

/// The options' own checks: the end time, the step count and the batch size.
fn check_options(scene: &Scene, opts: &RunOptions) -> Result<(), RunError> {
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
    Ok(())
}

impl Summary {
    /// The summary of a run about to step: status `running`, nothing measured yet.
    #[allow(clippy::too_many_arguments, reason = "the summary records each of the run's inputs by name")]
    fn started(
        scene: &Scene,
        opts: &RunOptions,
        layout: &Layout,
        backend: &dyn Backend,
        stages: Vec<&'static str>,
        plan: Plan,
        gpu_engine: Option<EngineTraffic>,
        gpu: Option<GpuInfo>,
    ) -> Summary {
        Summary {
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
            ran: backend.name(),
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
            dt_warnings: Vec::new(),
            stability_numbers: Default::default(),
            peak_neighbours: None,
            engine: None,
        }
    }
}
