//! The resource plan of a run, computed from the scene alone before anything big is allocated:
//! fluid and wall particle counts from the domain, spacing and wall depth, the cell-grid size
//! from the kernel support, and every host buffer the solver sizes by its particles, by part:
//! solver (particle state, fields, layout), neighbours (lists, cell grid) and outputs (the
//! read-back frame); whoever adds buffers of its own (the lab's outputs and diagnostics, the
//! study's reference frames) adds them with [`Plan::with_buffer`], each byte count from the
//! module that allocates the buffer.
//! [`Plan::check`] compares the total with [`Limits`] (`--max-particles`, and the smallest
//! memory limit of [`memory_limits`] and `--max-memory`) and refuses with every number when it
//! does not fit, so a huge resolution or a tiny `h_ratio` is an input error (exit 2), never an
//! allocation failure.
//!
//! Counts are computed in `f64`, so an absurd scene (`domain.y = [0, 1e300]`) gives an absurd
//! but finite plan instead of an overflow. The byte counts are deliberately generous upper
//! estimates of what the run holds at once; the GPU estimates (device buffers of a variant)
//! live in the GPU executor (`gpu::plan`), which plans every device buffer of a variant and checks
//! it against the adapter before any buffer is created.

pub(crate) mod memory_limits;

use crate::gpu::plan as gpu;
use crate::neighbours::cells::CellBox;
use crate::neighbours::INDEX_MASK;
use crate::scene::lattice::Lattice;
use crate::scene::Scene;
pub use memory_limits::{available_memory, fmt_bytes, MemoryLimit};
use serde::Serialize;

/// Fraction of the available memory a run may plan to use by default.
pub const DEFAULT_MEMORY_FRACTION: f64 = memory_limits::AVAILABLE_FRACTION;
/// Default memory limit when the machine's memory cannot be read (8 GiB).
pub const FALLBACK_MEMORY: u64 = 8 << 30;
/// Hard particle limit: a neighbour entry packs the particle index in 28 bits.
pub const HARD_MAX_PARTICLES: u64 = INDEX_MASK as u64;
/// Bytes of a run besides its particles: the program, thread stacks, fixed-size writer buffers.
pub const BASE_BYTES: f64 = 64.0 * 1048576.0;

/// What a run may use.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Limits {
    /// Most particles (fluid + wall).
    pub max_particles: u64,
    /// Most bytes of host memory: the smallest of `memory_limits`.
    pub max_memory: u64,
    /// Which limit `max_memory` is ([`MemoryLimit::source`] of the smallest).
    pub memory_source: &'static str,
    /// Every memory limit found (the machine's and `--max-memory`), with how each was read.
    pub memory_limits: Vec<MemoryLimit>,
    /// Device memory of the GPU (`--gpu-memory`; `None`: [`gpu::DeviceLimits::of`]'s heuristic).
    pub gpu_memory: Option<u64>,
    /// A per-buffer cap below the adapter's own (`--gpu-binding`; `None`: the adapter's), as if
    /// on an adapter with smaller bindings (`GpuContext::with_binding_cap`).
    pub gpu_binding: Option<u64>,
}

impl Default for Limits {
    /// [`HARD_MAX_PARTICLES`] and the smallest memory limit of the machine
    /// ([`memory_limits::machine_limits`]).
    fn default() -> Self {
        Limits::of(HARD_MAX_PARTICLES, memory_limits::machine_limits())
    }
}

impl Limits {
    /// `max_particles` and the smallest of `memory_limits` ([`FALLBACK_MEMORY`] if none).
    pub fn of(max_particles: u64, memory_limits: Vec<MemoryLimit>) -> Self {
        let least = memory_limits.iter().min_by_key(|l| l.bytes);
        let (max_memory, memory_source) =
            least.map_or((FALLBACK_MEMORY, memory_limits::FALLBACK), |l| (l.bytes, l.source));
        Limits { max_particles, max_memory, memory_source, memory_limits, gpu_memory: None, gpu_binding: None }
    }

    /// The defaults with `--max-particles` / `--max-memory` applied (each must be positive;
    /// `max_particles` may not exceed [`HARD_MAX_PARTICLES`]; `--max-memory` counts only where
    /// it is below the machine's limits).
    pub fn with(max_particles: Option<u64>, max_memory: Option<u64>) -> Result<Self, String> {
        let mut particles = HARD_MAX_PARTICLES;
        if let Some(p) = max_particles {
            if p == 0 || p > HARD_MAX_PARTICLES {
                return Err(format!("--max-particles: must lie in [1, {HARD_MAX_PARTICLES}], got {p}"));
            }
            particles = p;
        }
        let mut memory = memory_limits::machine_limits();
        if let Some(m) = max_memory {
            if m < (1 << 20) {
                return Err(format!("--max-memory: must be at least 1M (1048576 bytes), got {m}"));
            }
            memory.push(MemoryLimit {
                source: memory_limits::MAX_MEMORY_FLAG,
                bytes: m,
                detail: "set on the command line".into(),
            });
        }
        Ok(Limits::of(particles, memory))
    }

    /// These limits with `--gpu-memory` (at least 1 MiB) as the GPU's device memory.
    pub fn with_gpu_memory(mut self, gpu_memory: Option<u64>) -> Result<Self, String> {
        if let Some(m) = gpu_memory {
            if m < (1 << 20) {
                return Err(format!("--gpu-memory: must be at least 1M (1048576 bytes), got {m}"));
            }
        }
        self.gpu_memory = gpu_memory;
        Ok(self)
    }

    /// These limits with `--gpu-binding` (at least 64 KiB, one list chunk of the widest slot
    /// arrays) as the GPU's per-buffer cap.
    pub fn with_gpu_binding(mut self, gpu_binding: Option<u64>) -> Result<Self, String> {
        if let Some(b) = gpu_binding {
            if b < (64 << 10) {
                return Err(format!("--gpu-binding: must be at least 64K (65536 bytes), got {b}"));
            }
        }
        self.gpu_binding = gpu_binding;
        Ok(self)
    }

    /// The binding memory limit (the smallest of [`Limits::memory_limits`]).
    pub fn binding(&self) -> Option<&MemoryLimit> {
        self.memory_limits.iter().find(|l| l.source == self.memory_source && l.bytes == self.max_memory)
    }
}

/// Parses a byte size: `123`, `512K`, `64M`, `16G`, `1T` (powers of 1024; a trailing `B` or
/// `iB` is accepted).
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let t = t.strip_suffix("iB").or_else(|| t.strip_suffix('B')).unwrap_or(t);
    let (num, mult) = match t.chars().last() {
        Some('K' | 'k') => (&t[..t.len() - 1], 1u64 << 10),
        Some('M' | 'm') => (&t[..t.len() - 1], 1 << 20),
        Some('G' | 'g') => (&t[..t.len() - 1], 1 << 30),
        Some('T' | 't') => (&t[..t.len() - 1], 1 << 40),
        _ => (t, 1),
    };
    let v: f64 = num.trim().parse().map_err(|_| format!("`{text}` is not a size (e.g. 512M, 16G)"))?;
    let b = v * mult as f64;
    if !(b.is_finite() && (1.0..1.8e19).contains(&b)) {
        return Err(format!("`{text}` is not a size between 1 byte and 16 EiB"));
    }
    Ok(b as u64)
}

/// Bytes per particle of the solver's state and fields, by the size of the working real (4 or
/// 8): position, velocity, their midpoint copies (8 reals), evaluation fields (σ, χ, m, ρ, p,
/// 4 gradient, 3 stress, 2 acceleration, 2 transport velocity: 16 reals), colour and phase.
pub fn solver_bytes_per_particle(real: usize) -> f64 {
    (24 * real + 8) as f64
}

/// Bytes per particle of the f64 layout the solver is built from (position, velocity, phase).
pub const LAYOUT_BYTES_PER_PARTICLE: f64 = 36.0;
/// Bytes per particle of the start-up copies of the fluid's positions and velocities
/// ([`crate::scene::initial::initial_velocities`]).
pub const START_BYTES_PER_PARTICLE: f64 = 32.0;

/// One host buffer (or group of buffers) of the plan.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct HostBuffer {
    /// What it holds.
    pub name: &'static str,
    /// The part of the run that holds it: `solver`, `neighbours`, `outputs`, `diagnostics` or
    /// `copies` (what the study keeps besides the run).
    pub part: &'static str,
    /// Bytes (an upper estimate).
    pub bytes: f64,
}

/// The plan of one scene.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Plan {
    /// Particles across x (domain.nx).
    pub nx: f64,
    /// Rows (domain.y extent / Δx).
    pub ny: f64,
    /// Wall layers behind each wall side.
    pub wall_layers: f64,
    /// Fluid particles.
    pub n_fluid: f64,
    /// Wall particles.
    pub n_wall: f64,
    /// Fluid + wall.
    pub n_total: f64,
    /// Neighbour candidates per particle planned for (the (2κh/Δx + 1)² square around it).
    pub neighbours_per_particle: f64,
    /// Cells of the search grid (cell edge 1.01 κh over the particle box).
    pub cells: f64,
    /// Every host buffer, by part.
    pub host: Vec<HostBuffer>,
    /// Bytes of the `solver` part: particle state, fields, layout, start-up copies.
    pub particle_bytes: f64,
    /// Bytes of the neighbour lists (entries held four times: chunk buffers, the final list,
    /// tracking candidates within the skin).
    pub neighbour_bytes: f64,
    /// Bytes of the cell grid (start, fill and sorted arrays).
    pub cell_bytes: f64,
    /// Bytes of the `outputs` part: the read-back frame, the VTK text.
    pub output_bytes: f64,
    /// Bytes of the `diagnostics` part: the contact-angle grid and interface points.
    pub diagnostic_bytes: f64,
    /// Bytes of the `copies` part (study, validation).
    pub copy_bytes: f64,
    /// Sum of the above and [`BASE_BYTES`].
    pub total_bytes: f64,
    /// GPU: every device buffer of the variant ([`gpu::GpuPlan`]; the default variant until
    /// [`Plan::for_variant`]), `None` on the CPU.
    pub gpu: Option<gpu::GpuPlan>,
}

impl Plan {
    /// The plan of `scene` on the CPU (`real` = 4 or 8 bytes) or, with `gpu`, the default GPU
    /// variant (the host keeps the f64 layout and read-backs; [`Plan::for_variant`] plans
    /// another), with CSV snapshots ([`Plan::with_vtk`] adds the VTK writer). Needs only that the
    /// domain extents and `kernel.h_ratio` are finite and positive (as [`Scene::validate`]
    /// checks); any other value still gives a finite plan.
    pub fn new(scene: &Scene, real: usize, gpu: bool) -> Plan {
        // At least one row, so that a plan exists even for a domain lower than Δx/2.
        let lattice = Lattice::of(scene);
        let lattice = Lattice { ny: lattice.ny.max(1.0), ..lattice };
        let (nx, ny, dx, wall_layers) = (lattice.nx, lattice.ny, lattice.dx, lattice.wall_layers);
        let (wx, wy) = (lattice.columns(), lattice.rows());
        let (n_fluid, n_total) = (lattice.n_fluid(), lattice.n_total());
        let n_wall = n_total - n_fluid;
        let support = scene.support();
        let k = (2.0 * support / dx + 1.0).powi(2);
        let cells = CellBox::<f64>::cells_over(wx * dx, wy * dx, support);
        let host_real = if gpu { 8 } else { real };
        let mut host = vec![
            HostBuffer {
                name: "particle state and fields",
                part: "solver",
                bytes: n_total * solver_bytes_per_particle(host_real),
            },
            HostBuffer { name: "particle layout (f64)", part: "solver", bytes: n_total * LAYOUT_BYTES_PER_PARTICLE },
            HostBuffer { name: "start-up velocity field", part: "solver", bytes: n_fluid * START_BYTES_PER_PARTICLE },
        ];
        if !gpu {
            host.push(HostBuffer {
                name: "neighbour lists",
                part: "neighbours",
                bytes: 4.0 * n_total * (k * 4.0 + 4.0),
            });
            host.push(HostBuffer { name: "cell grid", part: "neighbours", bytes: cells * 8.0 + n_total * 12.0 });
        }
        host.push(HostBuffer {
            name: "read-back frame and snapshot (f64)",
            part: "outputs",
            bytes: n_total * crate::backend::Frame::BYTES_PER_PARTICLE,
        });
        let gpu = gpu.then(|| gpu::GpuPlan::new(&Default::default(), n_total as u64, cells as u64));
        let mut plan = Plan {
            nx,
            ny,
            wall_layers,
            n_fluid,
            n_wall,
            n_total,
            neighbours_per_particle: k,
            cells,
            host,
            particle_bytes: 0.0,
            neighbour_bytes: 0.0,
            cell_bytes: 0.0,
            output_bytes: 0.0,
            diagnostic_bytes: 0.0,
            copy_bytes: 0.0,
            total_bytes: 0.0,
            gpu,
        };
        plan.sum();
        plan
    }

    /// The sums of [`Plan::host`] by part, and the total.
    fn sum(&mut self) {
        let part = |p: &str| self.host.iter().filter(|b| b.part == p).map(|b| b.bytes).sum::<f64>();
        let named = |n: &str| self.host.iter().filter(|b| b.name == n).map(|b| b.bytes).sum::<f64>();
        self.particle_bytes = part("solver");
        self.neighbour_bytes = named("neighbour lists");
        self.cell_bytes = named("cell grid");
        self.output_bytes = part("outputs");
        self.diagnostic_bytes = part("diagnostics");
        self.copy_bytes = part("copies");
        self.total_bytes = BASE_BYTES + self.host.iter().map(|b| b.bytes).sum::<f64>();
    }

    /// The plan with one more host buffer of `bytes` (`part` as in [`HostBuffer::part`]).
    pub fn with_buffer(mut self, name: &'static str, part: &'static str, bytes: f64) -> Plan {
        self.host.push(HostBuffer { name, part, bytes });
        self.sum();
        self
    }

    /// The plan with the device buffers of `spec` (same particles and cells).
    pub fn for_variant(mut self, spec: &crate::gpu::variant::VariantSpec) -> Plan {
        self.gpu = Some(gpu::GpuPlan::new(spec, self.n_total as u64, self.cells as u64));
        self
    }

    /// One line with every number.
    pub fn describe(&self) -> String {
        let mut s = format!(
            "{:.0} fluid + {:.0} wall = {:.0} particles ({:.0} × {:.0} lattice, {:.0} wall layers), \
             {:.3e} cells, ~{:.0} neighbour candidates each; host memory {} ({})",
            self.n_fluid,
            self.n_wall,
            self.n_total,
            self.nx,
            self.ny,
            self.wall_layers,
            self.cells,
            self.neighbours_per_particle,
            fmt_bytes(self.total_bytes),
            self.host.iter().map(|b| format!("{} {}", b.name, fmt_bytes(b.bytes))).collect::<Vec<_>>().join(", ")
        );
        if let Some(g) = &self.gpu {
            s += &format!(
                "; GPU device memory {} for {} (largest buffer `{}` {})",
                fmt_bytes(g.total_bytes as f64),
                g.variant,
                g.largest(u64::MAX).0,
                fmt_bytes(g.largest(u64::MAX).1 as f64)
            );
        }
        s
    }

    /// Ok when the plan fits `limits`; else the message (every number, the binding limit and
    /// how it was found, what to change).
    pub fn check(&self, limits: &Limits) -> Result<(), String> {
        let hint = "lower domain.nx, shrink the domain or lower kernel.h_ratio";
        if !(self.n_total <= limits.max_particles as f64) {
            return Err(format!(
                "resource plan: {:.0} particles exceed the limit of {} (--max-particles); {hint}. Plan: {}",
                self.n_total,
                limits.max_particles,
                self.describe()
            ));
        }
        if !(self.total_bytes <= limits.max_memory as f64) {
            let how = limits.binding().map_or(String::new(), |l| format!(": {}", l.detail));
            return Err(format!(
                "resource plan: {:.0} bytes ({}) of host memory exceed the {} of {} bytes ({}{how}); {hint}. \
                 Plan: {}",
                self.total_bytes,
                fmt_bytes(self.total_bytes),
                limits.memory_source,
                limits.max_memory,
                fmt_bytes(limits.max_memory as f64),
                self.describe()
            ));
        }
        Ok(())
    }

    /// Ok when the device buffers (of [`Plan::for_variant`]) fit `lim`; else the message with
    /// the buffer, the bytes needed and available ([`gpu::GpuPlan::check`]) and this plan.
    pub fn check_gpu(&self, lim: &gpu::DeviceLimits) -> Result<(), String> {
        match &self.gpu {
            Some(g) => g.check(lim).map_err(|e| format!("resource plan: {e}. Plan: {}", self.describe())),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{build::build_layout, builtin::builtin, overrides::apply_overrides};

    #[test]
    fn counts_match_the_layout() {
        for name in crate::scene::builtin::BUILTIN {
            let s = apply_overrides(&builtin(name).unwrap(), &["domain.nx=24".into()]).unwrap();
            let l = build_layout(&s).unwrap();
            let p = Plan::new(&s, 8, false);
            assert_eq!(p.n_fluid as usize, l.n_fluid, "{name}: fluid");
            assert_eq!(p.n_total as usize, l.pos.len(), "{name}: fluid + wall");
        }
    }

    fn limit(source: &'static str, bytes: u64) -> MemoryLimit {
        MemoryLimit { source, bytes, detail: format!("test {source}") }
    }

    #[test]
    fn huge_scenes_are_refused_with_numbers() {
        let s = apply_overrides(&builtin("oscillating-drop").unwrap(), &["domain.nx=5000".into()]).unwrap();
        let l = Limits::of(HARD_MAX_PARTICLES, vec![limit("test", 16 << 30)]);
        let e = Plan::new(&s, 8, false).check(&l).unwrap_err();
        assert!(e.contains("25000000 fluid") && e.contains("GiB"), "{e}");
        let small = apply_overrides(&builtin("oscillating-drop").unwrap(), &["domain.nx=30".into()]).unwrap();
        assert!(Plan::new(&small, 8, false).check(&l).is_ok());
        let l = Limits { max_particles: 100, ..l };
        assert!(Plan::new(&small, 8, false).check(&l).unwrap_err().contains("--max-particles"));
    }

    #[test]
    fn the_smallest_memory_limit_binds_and_is_named() {
        let l = Limits::of(
            HARD_MAX_PARTICLES,
            vec![
                limit(memory_limits::MEM_AVAILABLE, 20 << 30),
                limit(memory_limits::ADDRESS_SPACE, 3 << 30),
                limit(memory_limits::CGROUP, 4 << 30),
            ],
        );
        assert_eq!((l.max_memory, l.memory_source), (3 << 30, memory_limits::ADDRESS_SPACE));
        let s = apply_overrides(&builtin("oscillating-drop").unwrap(), &["domain.nx=1500".into()]).unwrap();
        let e = Plan::new(&s, 8, false).check(&l).unwrap_err();
        assert!(e.contains("address-space limit (RLIMIT_AS) of 3221225472 bytes") && e.contains("test address"), "{e}");
        let small = apply_overrides(&builtin("oscillating-drop").unwrap(), &["domain.nx=30".into()]).unwrap();
        assert!(Plan::new(&small, 8, false).check(&l).is_ok());
        // --max-memory only lowers the machine's limit.
        let l = Limits::with(None, Some(1 << 20)).unwrap();
        assert_eq!((l.max_memory, l.memory_source), (1 << 20, memory_limits::MAX_MEMORY_FLAG));
        let big = Limits::with(None, Some(1 << 60)).unwrap();
        assert_ne!(big.memory_source, memory_limits::MAX_MEMORY_FLAG);
        assert!(big.max_memory < 1 << 60 && big.memory_limits.len() >= 2);
    }

    #[test]
    fn the_core_plans_the_solver_the_neighbours_and_the_frame() {
        let s = apply_overrides(&builtin("sessile-90").unwrap(), &["domain.nx=40".into()]).unwrap();
        let p = Plan::new(&s, 8, false);
        let parts: Vec<&str> = p.host.iter().map(|b| b.part).collect();
        assert_eq!(parts, ["solver", "solver", "solver", "neighbours", "neighbours", "outputs"]);
        assert!(p.output_bytes > 0.0 && p.diagnostic_bytes == 0.0);
        let with = p.clone().with_buffer("probe", "diagnostics", 1e6);
        assert_eq!((with.diagnostic_bytes, with.total_bytes), (1e6, p.total_bytes + 1e6));
        let sum: f64 = p.host.iter().map(|b| b.bytes).sum();
        assert_eq!(p.total_bytes, BASE_BYTES + sum);
    }

    #[test]
    fn byte_sizes_parse() {
        assert_eq!(parse_bytes("512M").unwrap(), 512 << 20);
        assert_eq!(parse_bytes("2GiB").unwrap(), 2 << 30);
        assert_eq!(parse_bytes("1000").unwrap(), 1000);
        assert!(parse_bytes("-1G").is_err() && parse_bytes("lots").is_err() && parse_bytes("1e30T").is_err());
    }
}
