//! `sphlab study`: the thesis's Chapter 6 timing study (STUDY.md §4) and beyond, as records in
//! the format of STUDY.md §5 (`records.csv`, one row per backend × size) plus `summary.md` and
//! SVG plots.
//!
//! * **E1** (Fig. 6.3): neighbour search {direct, cells, tracking} × {CPU one thread, GPU} at
//!   2,025 fluid particles (the oscillating-drop box at nx = 45).
//! * **E4** (§6.5 headline): every GPU variant against the single-thread CPU NNPS (cells) at
//!   10,000 fluid particles (nx = 100): the speedup (thesis: 120× on a 2012 GPU).
//! * **scaling**: time per step against N for the CPU (one thread, all threads) and the GPU
//!   variants, log-log.
//!
//! Each backend runs the same scene from the same state: warm-up steps, then `steps` timed steps
//! (each followed by a device sync, so GPU time is wall clock of finished work); median, p10 and
//! p90 per step; where the adapter has timestamp queries, also the device time of every stage
//! pass (`gpu::timing`): `gpu_ms_per_step` (median) and `stage_times.csv`. The error columns
//! compare the backend's state after the timed steps with the CPU f64 one-thread run of the
//! same steps (kinetic energy, centroid). Absolute GPU times mean something only on a real GPU; on lavapipe (a CPU emulation of Vulkan) read ratios and
//! correctness only. E2 (residency hybrids, Fig. 6.8) and E3 (subdomain budgets, Fig. 6.9) run
//! from [`e23`]; the thesis-style figures come from [`thesis_figs`]. Every
//! backend is named by its [`BackendId`] (`cpu1.cells.f64`, `cells.thread.recomputed.f32`, …),
//! the same id the CLI, the bench and `records.csv` use; the outputs are written by [`report`].

pub mod e23;
pub mod e2_residency;
pub mod e3_subdomains;
pub mod report;
pub mod thesis_figs;

use crate::backend::{Backend, BackendId, Frame};
use crate::exec::Exec;
use crate::gpu::variant::{Precision, SearchVariant, VariantSpec};
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::run::{initial_velocities, measure};
use crate::scene::build::{build_layout, Layout};
use crate::scene::{builtin::builtin, overrides::apply_overrides, Scene};
use serde::Serialize;
use std::sync::Arc;
use std::time::Instant;

/// Largest particle count at which the O(N²) `direct` GPU variants run by default.
pub const DIRECT_MAX_N: usize = 3000;

/// One benchmark record (STUDY.md §5).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Record {
    /// Experiment (e1, e4, scaling).
    pub experiment: String,
    /// Backend id (`cpu1.cells.f64`, `cells.thread.recomputed.f32`, …; [`BackendId`]).
    pub variant: String,
    /// Scene name.
    pub scene: String,
    /// Particles across the box.
    pub nx: u32,
    /// Total particles (fluid + wall).
    pub n: usize,
    /// Fluid particles.
    pub n_fluid: usize,
    /// Timed steps.
    pub steps: u64,
    /// cpu, cpu1 or gpu.
    pub backend: String,
    /// Adapter name (or "CPU").
    pub adapter: String,
    /// Driver and driver info.
    pub driver: String,
    /// Device type.
    pub device_type: String,
    /// CPU model.
    pub cpu_model: String,
    /// CPU threads used.
    pub cpu_threads: usize,
    /// f32 or f64.
    pub precision: String,
    /// Median wall time per step (ms).
    pub ms_per_step_median: f64,
    /// 10th percentile.
    pub ms_per_step_p10: f64,
    /// 90th percentile.
    pub ms_per_step_p90: f64,
    /// `wall`, or `wall+timestamps` when the backend also reported GPU timestamps.
    pub timing: String,
    /// Median device time per step (ms) from GPU timestamps (empty without them).
    pub gpu_ms_per_step: Option<f64>,
    /// Particle-evaluations per second: N × force evaluations per step ÷ seconds per step.
    pub particle_evals_per_s: f64,
    /// Relative kinetic-energy difference from the CPU f64 reference after the same steps.
    pub ke_rel_error: f64,
    /// Centroid difference from the reference, in Δx.
    pub centroid_error_dx: f64,
    /// git commit.
    pub commit: String,
    /// UTC date.
    pub date: String,
    /// Mean device ms per step of each stage over the timed steps (GPU timestamps; written to
    /// `stage_times.csv`, not to `records.csv`).
    #[serde(skip)]
    pub stage_ms: Vec<(String, f64)>,
    /// E2: the stage groups on the CPU (`+`-joined, `-` for none); empty otherwise.
    pub residency_cpu: String,
    /// E2/E3: host → device bytes per step, counted at the copy calls.
    pub bytes_h2d_per_step: Option<f64>,
    /// E2/E3: device → host bytes per step, counted at the copy calls.
    pub bytes_d2h_per_step: Option<f64>,
    /// E3: particles per subdomain (empty: the unsplit run).
    pub budget: Option<usize>,
    /// E3: subdomains.
    pub subdomains: Option<usize>,
    /// E3: halo particles per force evaluation, summed over the subdomains.
    pub halo_particles: Option<f64>,
    /// E3: device bytes allocated by the (subdomain) solver.
    pub device_bytes: Option<u64>,
    /// E3: GPU busy fraction, device time (timestamps) ÷ wall time.
    pub gpu_busy: Option<f64>,
    /// E2: the GPU variant of the hybrids; E3: the thesis's configuration (○ ∆ □).
    pub config: String,
    /// E2/E3: verification verdict (against the CPU reference / the unsplit run).
    pub verified: String,
}

/// What to run.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// Experiments: e1, e4, scaling.
    pub experiments: Vec<String>,
    /// Scaling sizes (nx).
    pub sizes: Vec<u32>,
    /// Timed steps per backend.
    pub steps: u64,
    /// GPU variants (empty: every supported one).
    pub variants: Vec<VariantSpec>,
    /// Output directory.
    pub out: std::path::PathBuf,
    /// E2 and E3 settings.
    pub e23: e23::E23Options,
}

/// The study scene at resolution nx: the oscillating drop without relaxation, its dt (1e-4 at
/// nx = 30) rescaled by `time.dt_policy = "scale"` (∝ Δx while the CFL limit binds, to nx ≈ 120).
pub fn study_scene(nx: u32) -> Scene {
    let sets = [format!("domain.nx={nx}"), "relax.t=0".into(), "time.dt_policy=scale".into()];
    let scene = apply_overrides(&builtin("oscillating-drop").expect("built-in"), &sets).expect("valid study scene");
    crate::scene::dt_policy::apply(&scene).expect("the scaled dt is within the limits").scene
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// What [`time_backend`] measured.
struct Timed {
    /// Sorted wall ms per step.
    ms: Vec<f64>,
    /// Sorted device ms per step (GPU timestamps; empty without them).
    device_ms: Vec<f64>,
    /// Mean device ms per step of each stage.
    stage_ms: Vec<(String, f64)>,
    /// The state after the timed steps.
    frame: Frame,
}

/// Times `steps` steps (after 2 warm-up steps): wall clock around each step and its device
/// sync; GPU timestamps too where the backend has them, read after the wall measurement.
fn time_backend(b: &mut dyn Backend, steps: u64) -> Result<Timed, String> {
    let device = b.enable_device_time(true);
    for _ in 0..2 {
        b.step().map_err(|e| e.to_string())?;
    }
    b.sync();
    let _ = b.device_time();
    let (mut ms, mut device_ms, mut stage_ms) = (Vec::new(), Vec::new(), Vec::<(String, f64)>::new());
    for _ in 0..steps {
        let t = Instant::now();
        b.step().map_err(|e| e.to_string())?;
        b.sync();
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        if let Some(d) = device.then(|| b.device_time()).flatten() {
            device_ms.push(d.total_ms);
            for (stage, x) in d.stages {
                match stage_ms.iter_mut().find(|(s, _)| *s == stage) {
                    Some(e) => e.1 += x / steps as f64,
                    None => stage_ms.push((stage, x / steps as f64)),
                }
            }
        }
    }
    b.enable_device_time(false);
    ms.sort_by(f64::total_cmp);
    device_ms.sort_by(f64::total_cmp);
    Ok(Timed { ms, device_ms, stage_ms, frame: b.frame() })
}

struct Ctx<'a> {
    scene: Scene,
    layout: Layout,
    vel0: Vec<[f64; 2]>,
    reference: Option<Frame>,
    gpu: Option<&'a Arc<GpuContext>>,
    commit: String,
    date: String,
    cpu_model: String,
}

impl Ctx<'_> {
    fn record(&mut self, experiment: &str, id: BackendId, steps: u64, threads: usize) -> Result<Record, String> {
        let mut b = id.build(&self.scene, &self.layout, self.gpu)?;
        b.restart_with_velocities(&self.vel0);
        let Timed { ms, device_ms, stage_ms, frame } = time_backend(b.as_mut(), steps)?;
        let (ke_err, c_err) = match &self.reference {
            Some(r) => {
                let (a, c) = (measure(&self.scene, &frame), measure(&self.scene, r));
                let dx = self.scene.domain.dx();
                (
                    (a.kinetic_energy - c.kinetic_energy).abs() / c.kinetic_energy.abs().max(1e-300),
                    ((a.centroid_x - c.centroid_x).hypot(a.centroid_y - c.centroid_y)) / dx,
                )
            }
            None => (0.0, 0.0),
        };
        let median = percentile(&ms, 0.5);
        let evals = if self.scene.time.integrator == crate::scene::Integrator::Midpoint { 2.0 } else { 1.0 };
        let (adapter, driver, device_type) = match (id, self.gpu) {
            (BackendId::Gpu(_), Some(g)) => {
                let i = &g.adapter_info;
                (i.name.clone(), format!("{} {}", i.driver, i.driver_info), format!("{:?}", i.device_type))
            }
            _ => ("CPU".into(), "-".into(), "Cpu".into()),
        };
        Ok(Record {
            experiment: experiment.into(),
            variant: id.to_string(),
            scene: self.scene.name.clone(),
            nx: self.scene.domain.nx,
            n: self.layout.pos.len(),
            n_fluid: self.layout.n_fluid,
            steps,
            backend: id.kind().into(),
            adapter,
            driver,
            device_type,
            cpu_model: self.cpu_model.clone(),
            cpu_threads: threads,
            precision: id.precision().name().into(),
            ms_per_step_median: median,
            ms_per_step_p10: percentile(&ms, 0.1),
            ms_per_step_p90: percentile(&ms, 0.9),
            timing: if device_ms.is_empty() { "wall" } else { "wall+timestamps" }.into(),
            gpu_ms_per_step: (!device_ms.is_empty()).then(|| percentile(&device_ms, 0.5)),
            particle_evals_per_s: self.layout.pos.len() as f64 * evals / (median * 1e-3),
            ke_rel_error: ke_err,
            centroid_error_dx: c_err,
            commit: self.commit.clone(),
            date: self.date.clone(),
            stage_ms,
            ..Record::default()
        })
    }
}

/// Runs one experiment at one size; appends records (and prints a line per record).
fn run_size(
    experiment: &str,
    nx: u32,
    opts: &StudyOptions,
    gpu: Option<&Arc<GpuContext>>,
    cpu_searches: &[SearchKind],
    all_threads: bool,
    out: &mut Vec<Record>,
) -> Result<(), String> {
    let scene = study_scene(nx);
    let layout = build_layout(&scene).map_err(|e| e.to_string())?;
    let vel0 = initial_velocities(&scene, &layout, None);
    let mut c = Ctx {
        scene,
        layout,
        vel0,
        reference: None,
        gpu,
        commit: crate::output::git_commit(),
        date: crate::output::now_utc_iso8601(),
        cpu_model: crate::provenance::cpu_model(),
    };
    // The reference: CPU f64, one thread, cells.
    let reference = BackendId::Cpu { exec: Exec::Serial, search: SearchKind::Cells, precision: Precision::F64 };
    let mut r = reference.build(&c.scene, &c.layout, None)?;
    r.restart_with_velocities(&c.vel0);
    c.reference = Some(time_backend(r.as_mut(), opts.steps)?.frame);
    let push = |rec: Result<Record, String>, id: BackendId, out: &mut Vec<Record>| match rec {
        Ok(r) => {
            eprintln!("{experiment} nx={nx} {:<44} {:>10.3} ms/step", r.variant, r.ms_per_step_median);
            out.push(r);
        }
        Err(e) => eprintln!("{experiment} nx={nx} {id}: skipped: {e}"),
    };
    for &search in cpu_searches {
        let id = BackendId::Cpu { exec: Exec::Serial, search, precision: Precision::F64 };
        push(c.record(experiment, id, opts.steps, 1), id, out);
    }
    if all_threads {
        for precision in [Precision::F64, Precision::F32] {
            let id = BackendId::Cpu { exec: Exec::Parallel, search: SearchKind::Cells, precision };
            push(c.record(experiment, id, opts.steps, rayon::current_num_threads()), id, out);
        }
    }
    if gpu.is_some() {
        let specs: Vec<VariantSpec> = if opts.variants.is_empty() { VariantSpec::all() } else { opts.variants.clone() };
        for spec in specs {
            // E1 compares the searches: the default variant of each.
            if experiment == "e1" && spec != (VariantSpec { search: spec.search, ..VariantSpec::default() }) {
                continue;
            }
            let id = BackendId::Gpu(spec);
            if spec.search == SearchVariant::Direct && c.layout.pos.len() > DIRECT_MAX_N && opts.variants.is_empty() {
                eprintln!("{experiment} nx={nx} {id}: skipped: direct search is O(N²); only run up to {DIRECT_MAX_N} particles unless named in --variants");
                continue;
            }
            push(c.record(experiment, id, opts.steps, 1), id, out);
        }
    }
    Ok(())
}

/// Runs the selected experiments and writes `records.csv`, `summary.md` and plots.
pub fn run_study(opts: &StudyOptions) -> Result<Vec<Record>, String> {
    let gpu = GpuContext::new().map(Arc::new).map_err(|e| eprintln!("study: no GPU adapter ({e}); CPU only")).ok();
    let mut recs = Vec::new();
    let all = [SearchKind::Direct, SearchKind::Cells, SearchKind::Tracking];
    for e in &opts.experiments {
        match e.as_str() {
            "e1" => run_size("e1", 45, opts, gpu.as_ref(), &all, false, &mut recs)?,
            "e4" => run_size("e4", 100, opts, gpu.as_ref(), &[SearchKind::Cells], true, &mut recs)?,
            "scaling" => {
                for &nx in &opts.sizes {
                    run_size("scaling", nx, opts, gpu.as_ref(), &[SearchKind::Cells], true, &mut recs)?;
                }
            }
            "e2" | "e3" => match gpu.as_ref() {
                Some(g) if e == "e2" => e23::run_e2(&opts.e23, opts.steps, g, &mut recs)?,
                Some(g) => e23::run_e3(&opts.e23, g, &mut recs)?,
                None => eprintln!("{e}: skipped: it needs a GPU adapter"),
            },
            other => return Err(format!("--experiments: unknown experiment `{other}` (e1, e2, e3, e4, scaling)")),
        }
    }
    report::write(&opts.out, &recs, gpu.as_ref().map(|g| g.describe()))?;
    Ok(recs)
}
