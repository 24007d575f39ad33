//! E3 (thesis §6.2, §6.5, Fig. 6.9): the domain split into subdomains of at most `budget`
//! particles, each made self-contained with halo (ghost) particles, sent to the device one after
//! another, solved there and its results gathered. Subdomains are strips along x of equal
//! particle count (fluid and wall particles alike); the halo of a strip is every other particle
//! whose position or boundary image (mirror or periodic, `Images::image_pos`) lies within
//! [`HALO_SUPPORTS`] kernel supports (+ Δx) of the strip: the acceleration of an owned particle
//! needs Π, p and σ of its neighbours, Π needs ∇C of theirs, ∇C needs σ one support further,
//! and σ the positions one more, so three supports make the owned results exact.
//!
//! Per force evaluation the host splits the current positions, and for each subdomain uploads
//! positions, velocities, phases, colours and masses (`GpuSolver::load_particles`, into ONE
//! solver of spare capacity: one subdomain on the device at a time, as in the thesis), runs the
//! evaluation and downloads the acceleration and ṽ of the owned fluid particles; the host
//! integrates (the reference's integrator stages) and checks. Bytes are counted at the copy
//! calls. Device memory is that solver's allocation; the GPU busy fraction is device time
//! (timestamps of every stage pass, where the adapter has them) over wall time. Each split is
//! verified against the unsplit GPU run of the same variant after a few steps with
//! `verify::compare_fields` (the one tolerance table).

use super::e23::gpu_err;
use crate::backend::{Backend, DeviceTiming};
use crate::cpu::{boundary_axis, CpuSolver};
use crate::fields::{Field, Fields};
use crate::gpu::residency::Part;
use crate::gpu::solver::GpuSolver;
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::model::Images;
use crate::real::V2;
use crate::scene::build::Layout;
use crate::scene::Scene;
use crate::stage::Stage;
use std::sync::Arc;
use std::time::Instant;

/// Halo width in kernel supports (the dependency depth of one evaluation).
pub const HALO_SUPPORTS: f32 = 3.0;

/// One of the thesis's three configurations of Fig. 6.9 and the sphlab variant that runs it.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    /// The thesis's symbol.
    pub symbol: &'static str,
    /// What it is.
    pub label: &'static str,
    /// The variant id.
    pub variant: &'static str,
}

/// ○ atomics + cached, ∆ no atomics + recomputed, □ atomics + reductions + recomputed; all on
/// the `cells` search (stateless, so a reloaded subdomain needs nothing from its last visit) in
/// f32, the block mappings with the portable compare-and-swap float atomics.
pub const CONFIGS: [Config; 3] = [
    Config { symbol: "○", label: "atomics + cached", variant: "cells.block-atomic.cas.cached.f32" },
    Config { symbol: "∆", label: "no atomics + recomputed", variant: "cells.thread.recomputed.f32" },
    Config {
        symbol: "□", label: "atomics + reductions + recomputed", variant: "cells.block-tree.cas.recomputed.f32"
    },
];

/// One subdomain: global indices, fluids first (owned, then halo), then walls (owned, then halo).
#[derive(Clone, Debug, Default)]
pub struct Sub {
    /// Local → global index.
    pub global: Vec<usize>,
    /// Fluid particles (owned + halo).
    pub n_fluid: usize,
    /// Owned fluid particles (the first rows).
    pub owned_fluid: usize,
    /// Owned wall particles (rows `n_fluid..n_fluid + owned_wall`).
    pub owned_wall: usize,
}

impl Sub {
    /// Halo particles.
    pub fn halo(&self) -> usize {
        self.global.len() - self.owned_fluid - self.owned_wall
    }
    /// (local, global) of every owned particle.
    pub fn owned(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.owned_fluid).chain(self.n_fluid..self.n_fluid + self.owned_wall).map(|l| (l, self.global[l]))
    }
}

/// Splits `pos` (the first `n_fluid` fluid) into strips along x of at most `budget` particles
/// each, with the halo of width `width` (boundary images included).
pub fn split(pos: &[V2<f32>], n_fluid: usize, images: &Images<f32>, budget: usize, width: f32) -> Vec<Sub> {
    let n = pos.len();
    let k = n.div_ceil(budget.max(1)).max(1);
    let per = n.div_ceil(k);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| pos[a].x.total_cmp(&pos[b].x).then(a.cmp(&b)));
    let codes = images.codes();
    let mut owner = vec![0usize; n];
    for (r, &i) in order.iter().enumerate() {
        owner[i] = r / per;
    }
    (0..k)
        .map(|s| {
            let chunk = &order[(s * per).min(n)..((s + 1) * per).min(n)];
            let (lo, hi) =
                chunk.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &i| (a.min(pos[i].x), b.max(pos[i].x)));
            let near = |j: usize| {
                codes.iter().any(|&c| {
                    let x = images.image_pos(c, pos[j]).x;
                    (lo - x).max(x - hi) <= width
                })
            };
            let halo: Vec<usize> = (0..n).filter(|&j| owner[j] != s && near(j)).collect();
            let mut own: Vec<usize> = chunk.to_vec();
            own.sort_unstable();
            let of = |v: &[usize], fluid: bool| -> Vec<usize> {
                v.iter().copied().filter(|&i| (i < n_fluid) == fluid).collect()
            };
            let (of_, hf, ow, hw) = (of(&own, true), of(&halo, true), of(&own, false), of(&halo, false));
            let mut sub =
                Sub { n_fluid: of_.len() + hf.len(), owned_fluid: of_.len(), owned_wall: ow.len(), ..Sub::default() };
            sub.global = [of_, hf, ow, hw].concat();
            sub
        })
        .collect()
}

/// The split solver of one configuration and budget.
pub struct SplitSolver {
    /// Host state: positions, velocities, the gathered acceleration and ṽ (and every field of
    /// the last evaluation with [`Self::gather_all`]).
    pub host: CpuSolver<f32>,
    gpu: GpuSolver<f32>,
    budget: usize,
    width: f32,
    lf: Fields<f32>,
    lpos: Vec<V2<f32>>,
    lvel: Vec<V2<f32>>,
    have_acc: bool,
    /// Gather every field of the owned particles at each evaluation (verification).
    pub gather_all: bool,
    /// Bytes host → device, device → host.
    pub h2d: u64,
    /// Device → host.
    pub d2h: u64,
    /// Halo particles summed over evaluations.
    pub halo_sum: u64,
    /// Evaluations.
    pub evals: u64,
    /// Subdomains of the last split.
    pub subdomains: usize,
}

impl SplitSolver {
    /// A split run of `spec` on `scene` with `budget` particles per subdomain.
    pub fn new(
        ctx: &Arc<GpuContext>,
        scene: &Scene,
        layout: &Layout,
        spec: VariantSpec,
        budget: usize,
        vel0: &[[f64; 2]],
    ) -> Result<Self, String> {
        let host = super::e23::host_solver(scene, layout, vel0, "E3")?;
        if host.model.stages.contact_line {
            return Err("E3: the contact line spans subdomains (scenes with contact points are not split)".into());
        }
        let width = HALO_SUPPORTS * host.model.support() + host.model.dx;
        let subs = split(&host.pos, host.n_fluid, &host.model.images, budget, width);
        let largest = subs.iter().map(|s| s.global.len()).max().unwrap_or(0);
        let capacity = (largest + largest / 4 + 64).min(layout.pos.len());
        // The solver's grid spans the whole domain: the first two particles sit at its corners.
        let n = layout.pos.len();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &layout.pos {
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
        let mut cap = Layout {
            pos: (0..capacity).map(|k| layout.pos[k % n]).collect(),
            vel: vec![[0.0; 2]; capacity],
            phase: (0..capacity).map(|k| layout.phase[k % n]).collect(),
            n_fluid: capacity.min(layout.n_fluid),
            dx: layout.dx,
        };
        cap.phase.iter_mut().take(cap.n_fluid).for_each(|p| *p = layout.phase[0]);
        cap.phase.iter_mut().skip(cap.n_fluid).for_each(|p| *p = crate::scene::build::WALL);
        cap.pos[0] = lo;
        cap.pos[capacity.min(2) - 1] = hi;
        let mut gpu = GpuSolver::<f32>::new(ctx.clone(), scene, &cap, spec).map_err(gpu_err)?;
        // Subdomains are loaded and gathered by index: keep the original particle order.
        gpu.set_reorder_every(0).map_err(gpu_err)?;
        Ok(Self {
            host,
            gpu,
            budget,
            width,
            lf: Fields::new(capacity),
            lpos: vec![V2::zero(); capacity],
            lvel: vec![V2::zero(); capacity],
            have_acc: false,
            gather_all: false,
            h2d: 0,
            d2h: 0,
            halo_sum: 0,
            evals: 0,
            subdomains: subs.len(),
        })
    }

    /// Device bytes of the one subdomain solver.
    pub fn device_bytes(&self) -> u64 {
        self.gpu.device_bytes()
    }

    /// Switches GPU timestamps on; false when the adapter has none.
    pub fn enable_timestamps(&mut self) -> bool {
        self.gpu.enable_timestamps(DeviceTiming::Stages)
    }

    /// Device ms since the last call (timestamps), `None` without them.
    pub fn take_device_ms(&mut self) -> Result<Option<f64>, String> {
        let t = self.gpu.take_stage_times().map_err(gpu_err)?;
        Ok(t.map(|v| v.iter().map(|s| s.1).sum::<f64>() * 1e-6))
    }

    /// One force evaluation over every subdomain at the host's current state.
    fn evaluate(&mut self) -> Result<(), String> {
        let h = &mut self.host;
        let subs = split(&h.pos, h.n_fluid, &h.model.images, self.budget, self.width);
        self.subdomains = subs.len();
        self.evals += 1;
        for s in &subs {
            self.halo_sum += s.halo() as u64;
            let pos: Vec<V2<f32>> = s.global.iter().map(|&g| h.pos[g]).collect();
            let vel: Vec<V2<f32>> = s.global.iter().map(|&g| h.vel[g]).collect();
            let phase: Vec<u32> = s.global.iter().map(|&g| h.phase[g]).collect();
            self.h2d += self.gpu.load_particles(&pos, &vel, &phase, s.n_fluid).map_err(gpu_err)?;
            self.gpu.evaluate_loaded().map_err(gpu_err)?;
            let parts: Vec<Part> = if self.gather_all {
                Field::ALL.iter().filter(|f| **f != Field::Contacts).map(|f| Part::Field(*f)).collect()
            } else {
                vec![Part::Field(Field::Acc), Part::Field(Field::Vt)]
            };
            let rows = if self.gather_all { s.global.len() } else { s.owned_fluid };
            for p in parts {
                self.d2h +=
                    self.gpu.download_part(p, rows, &mut self.lpos, &mut self.lvel, &mut self.lf).map_err(gpu_err)?;
            }
            let (f, lf) = (&mut h.f, &self.lf);
            for (l, g) in s.owned() {
                if g < h.n_fluid {
                    f.acc[g] = lf.acc[l];
                    f.vt[g] = lf.vt[l];
                }
                if self.gather_all {
                    f.sigma[g] = lf.sigma[l];
                    f.chi[g] = lf.chi[l];
                    f.mass[g] = lf.mass[l];
                    f.colour[g] = lf.colour[l];
                    f.rho[g] = lf.rho[l];
                    f.p[g] = lf.p[l];
                    f.grad[g] = lf.grad[l];
                    f.pi[g] = lf.pi[l];
                }
            }
        }
        Ok(())
    }

    /// One step: the scene's integrator on the host around the split evaluations.
    pub fn step(&mut self) -> Result<(), String> {
        let integrator = self.host.integrator;
        if integrator == crate::scene::Integrator::Midpoint || !self.have_acc {
            self.evaluate()?;
        }
        let dt = self.host.model.dt_fixed as f32;
        let (pre, post) = Stage::step_pair(integrator);
        let (r0, v0) = (self.host.pos.clone(), self.host.vel.clone());
        for (k, stage) in [pre, post].into_iter().enumerate() {
            if k == 1 {
                self.evaluate()?;
            }
            let h = &mut self.host;
            match stage {
                Stage::MidpointPredict => h.midpoint_predict(dt),
                Stage::MidpointCorrect => h.midpoint_correct(&r0, &v0, dt),
                Stage::VerletDrift => h.verlet_drift(dt),
                Stage::VerletKick => h.verlet_kick(dt),
                other => return Err(format!("{other} is not an integrator stage")),
            }
            let im = h.model.images;
            let (lo, hi) = (h.model.lo, h.model.hi);
            for i in 0..h.n_fluid {
                let (p, v) = (&mut h.pos[i], &mut h.vel[i]);
                boundary_axis(&im.x, lo.x, hi.x, &mut p.x, &mut v.x);
                boundary_axis(&im.y, lo.y, hi.y, &mut p.y, &mut v.y);
            }
        }
        self.have_acc = true;
        let h = &mut self.host;
        h.step += 1;
        h.t += h.model.dt_fixed;
        h.check().map_err(|e| e.to_string())
    }
}

/// What one split (or unsplit) run measured.
#[derive(Clone, Debug)]
pub struct SplitTiming {
    /// Sorted wall ms per step.
    pub ms: Vec<f64>,
    /// Total wall ms of the timed steps.
    pub wall_ms: f64,
    /// Total device ms (timestamps), when the adapter has them.
    pub device_ms: Option<f64>,
    /// Bytes host → device per step.
    pub h2d_per_step: f64,
    /// Bytes device → host per step.
    pub d2h_per_step: f64,
    /// Halo particles per evaluation (summed over subdomains).
    pub halo: f64,
    /// Subdomains.
    pub subdomains: usize,
    /// Device bytes allocated.
    pub device_bytes: u64,
}

/// Times `steps` split steps after one warm-up step.
pub fn time_split(s: &mut SplitSolver, steps: u64) -> Result<SplitTiming, String> {
    s.step()?;
    let timed = s.enable_timestamps();
    s.take_device_ms()?;
    let (h2d, d2h, halo, evals) = (s.h2d, s.d2h, s.halo_sum, s.evals);
    let (mut ms, mut dev) = (Vec::new(), 0.0);
    for _ in 0..steps {
        let t = Instant::now();
        s.step()?;
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        dev += s.take_device_ms()?.unwrap_or(0.0);
    }
    let wall_ms = ms.iter().sum();
    ms.sort_by(f64::total_cmp);
    let st = steps.max(1) as f64;
    Ok(SplitTiming {
        ms,
        wall_ms,
        device_ms: timed.then_some(dev),
        h2d_per_step: (s.h2d - h2d) as f64 / st,
        d2h_per_step: (s.d2h - d2h) as f64 / st,
        halo: (s.halo_sum - halo) as f64 / (s.evals - evals).max(1) as f64,
        subdomains: s.subdomains,
        device_bytes: s.device_bytes(),
    })
}

/// Times `steps` steps of the unsplit GPU solver (everything resident) after one warm-up step.
pub fn time_unsplit(g: &mut GpuSolver<f32>, steps: u64) -> Result<SplitTiming, String> {
    g.step().map_err(gpu_err)?;
    g.sync();
    let timed = g.enable_timestamps(DeviceTiming::Stages);
    let (mut ms, mut dev) = (Vec::new(), 0.0);
    for _ in 0..steps {
        let t = Instant::now();
        g.step().map_err(gpu_err)?;
        g.sync();
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        if let Some(v) = g.take_stage_times().map_err(gpu_err)? {
            dev += v.iter().map(|s| s.1).sum::<f64>() * 1e-6;
        }
    }
    if let Some(e) = g.take_error() {
        return Err(gpu_err(e));
    }
    let wall_ms = ms.iter().sum();
    ms.sort_by(f64::total_cmp);
    Ok(SplitTiming {
        ms,
        wall_ms,
        device_ms: timed.then_some(dev),
        h2d_per_step: 0.0,
        d2h_per_step: 0.0,
        halo: 0.0,
        subdomains: 1,
        device_bytes: g.device_bytes(),
    })
}

/// Verifies a split run against the unsplit GPU run of the same variant after `steps` steps:
/// every field of the last evaluation (owned rows gathered from their subdomains) through
/// `verify::compare_fields`. `Ok(summary)` when every check passes, `Err(failed)` otherwise.
pub fn verify_split(
    ctx: &Arc<GpuContext>,
    scene: &Scene,
    layout: &Layout,
    spec: VariantSpec,
    budget: usize,
    vel0: &[[f64; 2]],
    steps: u64,
) -> Result<String, String> {
    let mut s = SplitSolver::new(ctx, scene, layout, spec, budget, vel0)?;
    s.gather_all = true;
    let mut g = GpuSolver::<f32>::new(ctx.clone(), scene, layout, spec).map_err(gpu_err)?;
    g.restart_with_velocities(vel0);
    for _ in 0..steps.max(1) {
        s.step()?;
        g.step().map_err(gpu_err)?;
    }
    if let Some(e) = g.take_error() {
        return Err(format!("unsplit: {e}"));
    }
    let gf = g.read_fields().map_err(gpu_err)?;
    let checks = crate::verify::compare_fields("field", "", &s.host.f, &gf, &s.host.model, s.host.n_fluid, None);
    super::e23::verdict(&checks)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::AxisMap;

    #[test]
    fn strips_partition_the_particles_within_budget_and_the_halo_holds_every_near_particle() {
        let pos: Vec<V2<f32>> = (0..400).map(|k| V2::new((k % 20) as f32 * 0.05, (k / 20) as f32 * 0.05)).collect();
        let images = Images { x: [Some(AxisMap::Mirror(0.0)), None], y: [None, None] };
        let (budget, width) = (90, 0.12);
        let subs = split(&pos, 300, &images, budget, width);
        let mut seen = vec![0; pos.len()];
        for s in &subs {
            assert!(s.owned_fluid + s.owned_wall <= budget);
            assert!(s.global[..s.n_fluid].iter().all(|&g| g < 300) && s.global[s.n_fluid..].iter().all(|&g| g >= 300));
            let owned: Vec<usize> = s.owned().map(|(_, g)| g).collect();
            owned.iter().for_each(|&g| seen[g] += 1);
            for j in 0..pos.len() {
                let near = owned.iter().any(|&i| {
                    let (a, b) = (pos[i].x, pos[j].x);
                    (a - b).abs() <= width || (a + b).abs() <= width // b's mirror image at −b
                });
                assert_eq!(near, s.global.contains(&j), "particle {j}");
            }
        }
        assert!(seen.iter().all(|&c| c == 1), "every particle owned exactly once");
        assert_eq!(subs.len(), 400usize.div_ceil(budget));
    }
}
