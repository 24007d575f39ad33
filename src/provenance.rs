//! Where every number comes from: the commit sphlab was built from (baked in by `build.rs`, so
//! it does not depend on the directory the program runs in), and the one envelope every output
//! carries (`summary.json`, `verify`, `study`, `validate`, `analytic --json`): schema version,
//! sphlab version, commit and dirty flag, date, host CPU and threads, the GPU adapter, driver
//! and backend where one was used, and the units of every quantity.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Version of the envelope's layout; bumped when a key changes meaning or goes away.
pub const SCHEMA_VERSION: u32 = 1;

/// The short commit sphlab was built from ("unknown" when built outside a git checkout).
pub const BUILD_COMMIT: &str = env!("SPHLAB_BUILD_COMMIT");

/// True when the build had uncommitted changes to tracked files.
pub fn build_dirty() -> bool {
    env!("SPHLAB_BUILD_DIRTY") == "true"
}

/// The commit as outputs record it: `abc1234567`, or `abc1234567-dirty`.
pub fn commit_label() -> String {
    if build_dirty() {
        format!("{BUILD_COMMIT}-dirty")
    } else {
        BUILD_COMMIT.to_string()
    }
}

/// What `sphlab --version` prints after the name: `0.1.0 (commit abc1234567, dirty)`.
pub fn long_version() -> &'static str {
    static V: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    V.get_or_init(|| {
        format!(
            "{} (commit {}{})",
            env!("CARGO_PKG_VERSION"),
            BUILD_COMMIT,
            if build_dirty() { ", dirty: uncommitted changes" } else { "" }
        )
    })
}

/// The host a measurement ran on.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Host {
    /// CPU model (`/proc/cpuinfo`), or "unknown".
    pub cpu: String,
    /// Logical CPUs of the machine.
    pub cpus: usize,
    /// Worker threads of the CPU backend (`--threads`, default: all logical CPUs).
    pub threads: usize,
    /// Operating system and architecture.
    pub os: String,
}

impl Host {
    /// This machine, with the current rayon pool size as `threads`.
    pub fn current() -> Self {
        Host {
            cpu: cpu_model(),
            cpus: std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1),
            threads: rayon::current_num_threads(),
            os: format!("{}-{}", std::env::consts::OS, std::env::consts::ARCH),
        }
    }
}

/// The GPU an output was produced on.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct GpuInfo {
    /// Adapter name.
    pub adapter: String,
    /// Driver and driver info.
    pub driver: String,
    /// Graphics API backend (Vulkan, Metal, …).
    pub api: String,
    /// Device type (DiscreteGpu, Cpu, …).
    pub device_type: String,
}

impl GpuInfo {
    /// From wgpu's adapter description.
    pub fn from_adapter(info: &wgpu::AdapterInfo) -> Self {
        GpuInfo {
            adapter: info.name.clone(),
            driver: format!("{} {}", info.driver, info.driver_info).trim().to_string(),
            api: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
        }
    }
}

/// The envelope every output carries.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Provenance {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// sphlab's crate version.
    pub sphlab_version: String,
    /// Commit sphlab was built from (baked in at build time).
    pub commit: String,
    /// True when the build had uncommitted changes.
    pub dirty: bool,
    /// UTC date the output was written (ISO 8601).
    pub date: String,
    /// The host.
    pub host: Host,
    /// Backend that produced the numbers (`cpu`, `cpu1`, a GPU variant id, or the command).
    pub backend: String,
    /// The GPU, where one was used.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu: Option<GpuInfo>,
    /// Unit of every quantity the output holds, by its key.
    pub units: BTreeMap<String, String>,
}

impl Provenance {
    /// The envelope for an output of `backend`, with `units` (key → unit).
    pub fn new(backend: impl Into<String>, gpu: Option<GpuInfo>, units: &[(&str, &str)]) -> Self {
        Provenance {
            schema_version: SCHEMA_VERSION,
            sphlab_version: env!("CARGO_PKG_VERSION").to_string(),
            commit: crate::output::git_commit(),
            dirty: build_dirty(),
            date: crate::output::now_utc_iso8601(),
            host: Host::current(),
            backend: backend.into(),
            gpu,
            units: units.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
        }
    }
}

/// A note on the scene units: sphlab is unit-agnostic, quantities are in the scene's own
/// consistent units (SI in the built-in impact scene, nondimensional in the others); 2D masses
/// and energies are per unit depth.
pub const SCENE_UNITS: &str =
    "scene units (L length, T time, M mass per unit depth; SI for `impact`, nondimensional otherwise)";

/// Units of `series.csv` and `summary.json` of a run.
pub const RUN_UNITS: &[(&str, &str)] = &[
    ("units", SCENE_UNITS),
    ("t", "T"),
    ("step", "1"),
    ("dt", "T"),
    ("kinetic_energy", "M L^2 T^-2"),
    ("centroid_x", "L"),
    ("centroid_y", "L"),
    ("mass_phase0", "M"),
    ("mass_phase1", "M"),
    ("max_density_error", "1 (|rho/rho0 - 1|)"),
    ("max_speed", "L T^-1"),
    ("theta_two_point", "deg"),
    ("theta_circle_fit", "deg"),
    ("theta_area", "deg"),
    ("x_tp", "L"),
    ("spread_factor", "1 (D/D0)"),
    ("wave_amplitude", "L"),
    ("max_density_error_x, max_density_error_y, max_speed_x, max_speed_y", "L"),
    ("dt_last", "T"),
    ("t_final", "T"),
    ("wall_time_s", "s (wall clock)"),
    ("ms_per_step", "ms (wall clock)"),
    ("particles x, y / vx, vy / rho / p / mass / h", "L / L T^-1 / M L^-2 / M T^-2 / M / L"),
];

/// Units of `verify` outputs.
pub const VERIFY_UNITS: &[(&str, &str)] =
    &[("units", SCENE_UNITS), ("rel_l2, max_rel", "1 (relative to the CPU f64 reference)"), ("steps", "1")];

/// Units of `study` records.
pub const STUDY_UNITS: &[(&str, &str)] = &[
    (
        "ms_per_step_median, ms_per_step_min, ms_per_step_max, ms_per_step_p10, ms_per_step_p90, ms_per_step_ci_lo, \
         ms_per_step_ci_hi, latency_ms_median, gpu_ms_per_step, stage_sum_ms_per_step",
        "ms",
    ),
    ("load_before, load_after", "1 (1-minute load average)"),
    ("device_bytes, modelled_bytes_per_eval, modelled_bytes_per_step", "B"),
    ("bandwidth_gb_s, achieved_gb_s", "GB/s (10^9 B/s)"),
    ("roofline_fraction", "1 (achieved_gb_s ÷ bandwidth_gb_s)"),
    ("particle_evals_per_s", "1/s"),
    ("ke_rel_error", "1"),
    ("centroid_error_dx", "Δx"),
    ("n, n_fluid, nx, steps, repeats, warmup_steps, cpu_threads, cores, max_n_fits", "1"),
    ("speedup_vs_baseline", "1 (ms/step of the record named in `baseline` ÷ this row's, same run)"),
    ("speedup_vs_cpu_all", "1 (cpu.cells.<precision> ms/step ÷ this row's, same run)"),
    ("speedup_vs_cpu1_cells_f64", "1 (cpu1.cells.f64 ms/step ÷ this row's, same run)"),
];

/// Units of `analytic` outputs.
pub const ANALYTIC_UNITS: &[(&str, &str)] =
    &[("xi, axisym, model_a, model_b, model_c", "1 (D_max/D0)"), ("re, we", "1"), ("theta", "rad")];

/// Units of `validate` reports.
pub const VALIDATE_UNITS: &[(&str, &str)] =
    &[("units", SCENE_UNITS), ("wall_time_s", "s (wall clock)"), ("angles", "deg")];

/// CPU model from `/proc/cpuinfo`, or "unknown".
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}
