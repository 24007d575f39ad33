//! E2 (thesis Fig. 6.8): runtime as routines move to the GPU one group at a time. A [`Hybrid`]
//! names the stage groups ([`GROUPS`], from the stage table) that run on the GPU; the rest run on
//! the CPU (one thread, f32, the reference's own stage functions). Each part of the state
//! ([`Part`]: positions, velocities, every field of the table) is tracked as valid on the host,
//! the device or both; before a stage runs on one side, each input it reads (the table's
//! `reads`, positions, velocities for the force and integrator stages, the field itself for a
//! partial write) that is valid only on the other side is copied, and the bytes are COUNTED at
//! the copy call (`GpuSolver::upload_part` / `download_part` / `upload_cells` / the `Params`
//! write of the integrator). A CPU neighbour search hands the GPU stages the `cells` structure
//! built on the host (`GpuSolver::host_cells`); a GPU search needs every evaluation stage on the
//! GPU (the CPU stages would need the lists back). Consecutive GPU stages go in one submission;
//! every step ends with a device sync. Each hybrid is verified after a few steps against the CPU
//! f32 reference with `verify::compare_fields` (the one tolerance table).

use super::e23::gpu_err;
use crate::backend::{Backend, SolverError};
use crate::cpu::stages::{evaluation_fn, Ctx};
use crate::cpu::{boundary_axis, CpuSolver};
use crate::exec::Exec;
use crate::fields::{Field, Fields};
use crate::gpu::residency::Part;
use crate::gpu::solver::GpuSolver;
use crate::gpu::variant::{KernelValues, SumLayout, VariantSpec};
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::real::V2;
use crate::scene::build::Layout;
use crate::scene::{Integrator, Scene};
use crate::stage::{Stage, Write};
use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

/// The stage groups that move together, in the order the thesis's flowchart runs them.
pub const GROUPS: [&str; 5] = ["search", "density", "surface", "forces", "integration"];

/// The group of a stage.
pub fn group_of(stage: Stage) -> &'static str {
    match stage {
        Stage::NeighbourSearch => "search",
        Stage::NumberDensity
        | Stage::ContactLine
        | Stage::WallTyping
        | Stage::EquationOfState
        | Stage::WallPressure => "density",
        Stage::ColourGradient | Stage::NormalCorrection | Stage::SurfaceStress => "surface",
        Stage::Acceleration | Stage::Xsph => "forces",
        Stage::MidpointPredict
        | Stage::MidpointCorrect
        | Stage::VerletDrift
        | Stage::VerletKick
        | Stage::Check
        | Stage::CellCount
        | Stage::CellScan
        | Stage::ReduceMax => "integration",
    }
}

/// A named residency: the groups on the GPU.
#[derive(Clone, Copy, Debug)]
pub struct Hybrid {
    /// Name (the record's variant is `hybrid.<name>`).
    pub name: &'static str,
    /// Groups on the GPU; the others run on the CPU.
    pub gpu: &'static [&'static str],
}

/// From all-CPU to all-GPU, one group moved at a time (forces first, the search only once every
/// evaluation stage is on the GPU, the integration last).
pub const HYBRIDS: [Hybrid; 6] = [
    Hybrid { name: "cpu-all", gpu: &[] },
    Hybrid { name: "gpu-forces", gpu: &["forces"] },
    Hybrid { name: "gpu-surface-forces", gpu: &["surface", "forces"] },
    Hybrid { name: "gpu-density-surface-forces", gpu: &["density", "surface", "forces"] },
    Hybrid { name: "gpu-evaluation", gpu: &["search", "density", "surface", "forces"] },
    Hybrid { name: "gpu-all", gpu: &["search", "density", "surface", "forces", "integration"] },
];

impl Hybrid {
    /// True when `stage` runs on the GPU.
    pub fn on_gpu(&self, stage: Stage) -> bool {
        self.gpu.contains(&group_of(stage))
    }
    /// The CPU groups, `+`-joined (`-` for none).
    pub fn cpu_groups(&self) -> String {
        let v: Vec<&str> = GROUPS.iter().copied().filter(|g| !self.gpu.contains(g)).collect();
        if v.is_empty() {
            "-".into()
        } else {
            v.join("+")
        }
    }
}

/// Where a part of the state is valid.
#[derive(Clone, Copy, Debug, Default)]
struct Valid {
    host: bool,
    dev: bool,
}

/// Bytes moved so far.
#[derive(Clone, Copy, Debug, Default)]
pub struct Traffic {
    /// Host → device.
    pub h2d: u64,
    /// Device → host.
    pub d2h: u64,
}

/// One hybrid solver: the CPU reference's state and stage functions, a GPU solver, and where
/// each part of the state is valid.
pub struct HybridSolver {
    hybrid: Hybrid,
    /// Host state (the CPU stages run on it).
    pub cpu: CpuSolver<f32>,
    gpu: GpuSolver<f32>,
    valid: HashMap<Part, Valid>,
    pending: Vec<Stage>,
    r0: Vec<V2<f32>>,
    v0: Vec<V2<f32>>,
    have_acc: bool,
    /// Bytes moved so far.
    pub traffic: Traffic,
}

impl HybridSolver {
    /// A hybrid on `scene` with the GPU variant `spec` (f32, `cells` search without explicit
    /// lists when the search stays on the CPU).
    pub fn new(
        ctx: &Arc<GpuContext>,
        scene: &Scene,
        layout: &Layout,
        spec: VariantSpec,
        hybrid: Hybrid,
        vel0: &[[f64; 2]],
    ) -> Result<Self, String> {
        let cpu = super::e23::host_solver(scene, layout, vel0, "E2 hybrids")?;
        let st = cpu.model.stages;
        if st.contact_line && hybrid.gpu.len() != GROUPS.len() && !hybrid.gpu.is_empty() {
            return Err(format!("{}: contact points do not move between host and device", hybrid.name));
        }
        let eval = st.evaluation();
        if hybrid.on_gpu(Stage::NeighbourSearch) && eval.iter().any(|s| !hybrid.on_gpu(*s)) {
            return Err(format!("{}: a GPU search needs every evaluation stage on the GPU", hybrid.name));
        }
        let cpu_search_for_gpu = !hybrid.on_gpu(Stage::NeighbourSearch) && eval.iter().any(|s| hybrid.on_gpu(*s));
        if cpu_search_for_gpu
            && (spec.search != SearchKind::Cells
                || spec.mapping.layout() != SumLayout::Thread
                || spec.kernel_values != KernelValues::Recomputed)
        {
            return Err(format!(
                "{}: a CPU search feeds the GPU the `cells` structure: variant {spec} needs its own lists; use cells.thread.recomputed.f32",
                hybrid.name
            ));
        }
        let mut gpu = GpuSolver::<f32>::new(ctx.clone(), scene, layout, spec).map_err(gpu_err)?;
        // Host and device arrays are exchanged by index: keep the original particle order.
        gpu.set_reorder_every(0).map_err(gpu_err)?;
        gpu.restart_with_velocities(vel0);
        let mut valid = HashMap::new();
        let both = Valid { host: true, dev: true };
        valid.insert(Part::Pos, both);
        valid.insert(Part::Vel, both);
        valid.insert(Part::Field(Field::Mass), both);
        valid.insert(Part::Field(Field::Colour), both);
        Ok(Self {
            hybrid,
            cpu,
            gpu,
            valid,
            pending: Vec::new(),
            r0: Vec::new(),
            v0: Vec::new(),
            have_acc: false,
            traffic: Traffic::default(),
        })
    }

    /// The hybrid.
    pub fn hybrid(&self) -> Hybrid {
        self.hybrid
    }

    fn flush(&mut self) -> Result<(), String> {
        if !self.pending.is_empty() {
            let stages = std::mem::take(&mut self.pending);
            let dt = stages
                .iter()
                .any(|s| group_of(*s) == "integration")
                .then_some((self.cpu.model.dt_fixed, self.cpu.step + 1));
            self.traffic.h2d += self.gpu.run_stages(&stages, dt).map_err(gpu_err)?;
        }
        Ok(())
    }

    /// Makes `part` valid on the GPU side (`gpu`) or the host, copying if needed.
    fn ensure(&mut self, part: Part, gpu: bool) -> Result<(), String> {
        let v = self.valid.get(&part).copied().unwrap_or_default();
        if (gpu && v.dev) || (!gpu && v.host) || !(v.host || v.dev) {
            return Ok(());
        }
        self.flush()?;
        let n = self.cpu.pos.len();
        let c = &mut self.cpu;
        if gpu {
            self.traffic.h2d += self.gpu.upload_part(part, n, &c.pos, &c.vel, &c.f).map_err(gpu_err)?;
        } else {
            self.traffic.d2h += self.gpu.download_part(part, n, &mut c.pos, &mut c.vel, &mut c.f).map_err(gpu_err)?;
        }
        self.valid.insert(part, Valid { host: true, dev: true });
        Ok(())
    }

    fn written(&mut self, part: Part, gpu: bool) {
        self.valid.insert(part, Valid { host: !gpu, dev: gpu });
    }

    /// Inputs and outputs of a stage as parts of the state.
    fn io(stage: Stage) -> (Vec<Part>, Vec<Part>) {
        let d = stage.def();
        let mut reads: Vec<Part> = d.reads.iter().map(|f| Part::Field(*f)).collect();
        let mut writes: Vec<Part> = Vec::new();
        for w in d.writes {
            if let Write::Part(f) = w {
                reads.push(Part::Field(*f));
            }
            writes.push(Part::Field(w.field()));
        }
        reads.push(Part::Pos);
        match group_of(stage) {
            "forces" => reads.push(Part::Vel),
            "integration" => {
                reads.push(Part::Vel);
                if stage != Stage::Check {
                    writes.extend([Part::Pos, Part::Vel]);
                }
                if stage == Stage::VerletKick {
                    reads.push(Part::Field(Field::Vt));
                }
            }
            _ => {}
        }
        reads.retain(|p| *p != Part::Field(Field::Contacts));
        writes.retain(|p| *p != Part::Field(Field::Contacts));
        (reads, writes)
    }

    /// Runs one stage on its side.
    fn run(&mut self, stage: Stage) -> Result<(), String> {
        let gpu = self.hybrid.on_gpu(stage);
        let (reads, writes) = Self::io(stage);
        for p in reads {
            self.ensure(p, gpu)?;
        }
        if stage == Stage::NeighbourSearch {
            let eval = self.cpu.model.stages.evaluation();
            if gpu {
                self.pending.push(stage);
            } else {
                let c = &mut self.cpu;
                if eval.iter().any(|s| !self.hybrid.on_gpu(*s)) {
                    c.nbrs = c.search.update(c.exec, &c.model.images, &c.pos, c.model.support());
                }
                if eval.iter().any(|s| self.hybrid.on_gpu(*s)) {
                    let cells = self.gpu.host_cells(&self.cpu.pos);
                    self.flush()?;
                    self.traffic.h2d += self.gpu.upload_cells(&cells).map_err(gpu_err)?;
                }
            }
        } else if gpu {
            self.pending.push(stage);
        } else {
            self.flush()?;
            self.run_cpu(stage)?;
        }
        for p in writes {
            self.written(p, gpu);
        }
        Ok(())
    }

    fn run_cpu(&mut self, stage: Stage) -> Result<(), String> {
        let c = &mut self.cpu;
        let dt = c.model.dt_fixed as f32;
        if let Some(f) = evaluation_fn::<f32>(stage) {
            let mut fields = std::mem::take(&mut c.f);
            let ctx = Ctx {
                m: &c.model,
                pos: &c.pos,
                vel: &c.vel,
                phase: &c.phase,
                n_fluid: c.n_fluid,
                nbrs: &c.nbrs,
                exec: c.exec,
            };
            f(&ctx, &mut fields);
            c.f = fields;
            return Ok(());
        }
        match stage {
            Stage::MidpointPredict => {
                (self.r0, self.v0) = (c.pos.clone(), c.vel.clone());
                c.midpoint_predict(dt);
            }
            Stage::MidpointCorrect => c.midpoint_correct(&self.r0, &self.v0, dt),
            Stage::VerletDrift => c.verlet_drift(dt),
            Stage::VerletKick => c.verlet_kick(dt),
            Stage::Check => return c.check().map_err(|e| e.to_string()),
            other => return Err(format!("{other}: not a CPU stage of a hybrid")),
        }
        apply_boundaries(c);
        Ok(())
    }

    /// One force evaluation: every active stage on its side, then ṽ = v without XSPH.
    fn evaluate(&mut self) -> Result<(), String> {
        for stage in self.cpu.model.stages.evaluation() {
            self.run(stage)?;
        }
        if !self.cpu.model.stages.xsph {
            let gpu = self.hybrid.on_gpu(Stage::Acceleration);
            self.ensure(Part::Vel, gpu)?;
            if gpu {
                self.flush()?;
                self.gpu.vt_from_vel().map_err(gpu_err)?;
            } else {
                let nf = self.cpu.n_fluid;
                let c = &mut self.cpu;
                c.f.vt[..nf].copy_from_slice(&c.vel[..nf]);
            }
            self.written(Part::Field(Field::Vt), gpu);
        }
        Ok(())
    }

    /// One time step (the scene's integrator, as `CpuSolver::advance`), ended by a device sync.
    pub fn step(&mut self) -> Result<(), String> {
        let integrator = self.cpu.integrator;
        if integrator == Integrator::Midpoint || !self.have_acc {
            self.evaluate()?;
        }
        let (pre, post) = Stage::step_pair(integrator);
        self.run(pre)?;
        self.evaluate()?;
        self.run(post)?;
        self.run(Stage::Check)?;
        self.flush()?;
        self.gpu.wait().map_err(gpu_err)?;
        self.have_acc = true;
        let c = &mut self.cpu;
        c.step += 1;
        c.t += c.model.dt_fixed;
        Ok(())
    }

    /// Ends a run: the GPU's blow-up / overflow flags (when a GPU stage ran), then every part of
    /// the state gathered on the host (not counted as traffic); the host fields and state.
    pub fn gather(&mut self) -> Result<(), String> {
        self.flush()?;
        if !self.hybrid.gpu.is_empty() {
            if let Some(e) = self.gpu.take_error() {
                return Err(match e {
                    SolverError::BlowUp { .. } => format!("GPU: {e}"),
                    other => gpu_err(other),
                });
            }
        }
        let parts: Vec<Part> = self.valid.iter().filter(|(_, v)| v.dev && !v.host).map(|(p, _)| *p).collect();
        let saved = self.traffic;
        for p in parts {
            self.ensure(p, false)?;
        }
        self.traffic = saved;
        Ok(())
    }

    /// The host fields (after [`Self::gather`]).
    pub fn fields(&self) -> &Fields<f32> {
        &self.cpu.f
    }
}

/// Mirror and periodic sides on the host (as the CPU reference's step).
fn apply_boundaries(c: &mut CpuSolver<f32>) {
    let im = c.model.images;
    let (lo, hi) = (c.model.lo, c.model.hi);
    for i in 0..c.n_fluid {
        let (p, v) = (&mut c.pos[i], &mut c.vel[i]);
        boundary_axis(&im.x, lo.x, hi.x, &mut p.x, &mut v.x);
        boundary_axis(&im.y, lo.y, hi.y, &mut p.y, &mut v.y);
    }
}

/// What one hybrid measured.
#[derive(Clone, Debug)]
pub struct HybridTiming {
    /// Sorted wall ms per step.
    pub ms: Vec<f64>,
    /// Bytes moved per step, host → device.
    pub h2d_per_step: f64,
    /// Bytes moved per step, device → host.
    pub d2h_per_step: f64,
}

/// Times `steps` steps of a hybrid after `warmup` steps.
pub fn time_hybrid(h: &mut HybridSolver, warmup: u64, steps: u64) -> Result<HybridTiming, String> {
    for _ in 0..warmup {
        h.step()?;
    }
    let before = h.traffic;
    let mut ms = Vec::new();
    for _ in 0..steps {
        let t = Instant::now();
        h.step()?;
        ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    h.gather()?;
    ms.sort_by(f64::total_cmp);
    let s = steps.max(1) as f64;
    Ok(HybridTiming {
        ms,
        h2d_per_step: (h.traffic.h2d - before.h2d) as f64 / s,
        d2h_per_step: (h.traffic.d2h - before.d2h) as f64 / s,
    })
}

/// Verifies a hybrid after `steps` steps against the CPU f32 reference (all cores, cells):
/// every field of the last evaluation through `verify::compare_fields`. `Ok(worst check)` when
/// every check passes (`name max_rel`), `Err(failed checks)` otherwise.
pub fn verify_hybrid(
    ctx: &Arc<GpuContext>,
    scene: &Scene,
    layout: &Layout,
    spec: VariantSpec,
    hybrid: Hybrid,
    vel0: &[[f64; 2]],
    steps: u64,
) -> Result<String, String> {
    let mut h = HybridSolver::new(ctx, scene, layout, spec, hybrid, vel0)?;
    let mut r = CpuSolver::<f32>::new(scene, layout, Exec::Parallel, SearchKind::Cells);
    r.restart_with_velocities(vel0);
    for _ in 0..steps {
        h.step()?;
        r.advance().map_err(|e| format!("CPU reference: {e}"))?;
    }
    h.gather()?;
    let checks = crate::verify::compare_fields("field", "", h.fields(), &r.f, &r.model, r.n_fluid, None);
    super::e23::verdict(&checks)
}
