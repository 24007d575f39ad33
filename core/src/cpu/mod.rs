//! The CPU reference solver: the physics truth every GPU variant is judged against. Runs the
//! stages of the stage table ([`crate::stage`]; functions in [`stages`]) in the order of docs/PHYSICS.md §12, in `f64` or `f32`, on all cores or one
//! thread, with any of the three neighbour searches (identical results).

pub mod contact_angle;
pub mod line_force;
pub mod momentum;
pub mod stages;

use crate::backend::{Backend, Frame, SolverError};
use crate::exec::Exec;
use crate::fields::Fields;
use crate::model::{AxisMap, Model, MAX_CONTACTS};
use crate::neighbours::{NeighbourList, Search, SearchKind};
use crate::physics::integrate::*;
use crate::physics::timestep::{DtLimits, StabilityNumbers};
use crate::real::{Real, V2};
use crate::scene::build::Layout;
use crate::scene::{Integrator, Scene};
use crate::stage::Stage;
use stages::{assign_colours, evaluation_fn, Ctx};
use std::time::{Duration, Instant};

/// Wall-clock time spent per stage (for profiles; not a benchmark).
#[derive(Clone, Debug, Default)]
pub struct StageClock {
    /// (stage name, accumulated time).
    pub totals: Vec<(&'static str, Duration)>,
}

impl StageClock {
    fn add(&mut self, name: &'static str, d: Duration) {
        if let Some(e) = self.totals.iter_mut().find(|e| e.0 == name) {
            e.1 += d;
        } else {
            self.totals.push((name, d));
        }
    }
}

/// The CPU solver.
pub struct CpuSolver<T: Real> {
    /// Constants.
    pub model: Model<T>,
    /// Execution mode.
    pub exec: Exec,
    /// Neighbour search.
    pub search: Search<T>,
    /// Positions (fluids first).
    pub pos: Vec<V2<T>>,
    /// Velocities.
    pub vel: Vec<V2<T>>,
    /// Fluid phase or WALL.
    pub phase: Vec<u32>,
    /// Number of fluid particles.
    pub n_fluid: usize,
    /// Fields of the last evaluation.
    pub f: Fields<T>,
    /// Neighbour lists of the last evaluation.
    pub nbrs: NeighbourList,
    /// The most neighbours one particle had in one evaluation so far (`Backend::peak_neighbours`).
    pub peak_neighbours: usize,
    /// Time.
    pub t: f64,
    /// Steps.
    pub step: u64,
    /// Last dt.
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Per-stage wall clock (when `profile` is on).
    pub clock: StageClock,
    /// Record per-stage times.
    pub profile: bool,
    /// The largest CFL / viscous numbers reached at the start of every step so far.
    pub numbers: StabilityNumbers,
    /// The limit that bound the last dt (`fixed` for a fixed dt).
    pub dt_bound: &'static str,
    /// Verlet: the half-step velocities v_{n+½} of the drift, kept for the closing kick while
    /// `vel` holds the predicted v_n + dt·a_n that the evaluation sees (the GPU keeps them in
    /// `state0[n..]`). Empty with the midpoint integrator.
    pub vhalf: Vec<V2<T>>,
    have_acc: bool,
    evaluated: bool,
}

impl<T: Real> CpuSolver<T> {
    /// A solver for a validated scene and its layout.
    pub fn new(scene: &Scene, layout: &Layout, exec: Exec, search: SearchKind) -> Self {
        let model = Model::<T>::new(scene);
        let n = layout.pos.len();
        let dt_fixed = model.dt_fixed;
        let mut s = Self {
            model,
            exec,
            search: Search::new(search),
            pos: layout.pos.iter().map(|p| V2::from_f64(p[0], p[1])).collect(),
            vel: layout.vel.iter().map(|v| V2::from_f64(v[0], v[1])).collect(),
            phase: layout.phase.clone(),
            n_fluid: layout.n_fluid,
            f: Fields::new(n),
            nbrs: NeighbourList::default(),
            peak_neighbours: 0,
            t: 0.0,
            step: 0,
            dt: dt_fixed,
            integrator: scene.time.integrator,
            clock: StageClock::default(),
            profile: false,
            numbers: StabilityNumbers::default(),
            dt_bound: "fixed",
            vhalf: match scene.time.integrator {
                Integrator::Verlet | Integrator::VerletPec => vec![V2::from_f64(0.0, 0.0); layout.n_fluid],
                Integrator::Midpoint => Vec::new(),
            },
            have_acc: false,
            evaluated: false,
        };
        let mut f = std::mem::take(&mut s.f);
        assign_colours(&s.ctx(), &mut f);
        s.f = f;
        s
    }

    /// The read-only view the stage functions take (also for tools that re-walk the pairs).
    pub fn ctx(&self) -> Ctx<'_, T> {
        Ctx {
            m: &self.model,
            pos: &self.pos,
            vel: &self.vel,
            phase: &self.phase,
            n_fluid: self.n_fluid,
            nbrs: &self.nbrs,
            exec: self.exec,
        }
    }

    /// One force evaluation at the current positions and velocities: every active stage of
    /// the stage table, in order.
    pub fn evaluate(&mut self) -> Result<(), SolverError> {
        let profile = self.profile;
        let mut clock = std::mem::take(&mut self.clock);
        let r = self.run_evaluation(|stage, _, d| {
            if profile {
                clock.add(stage.name(), d);
            }
        });
        self.clock = clock;
        r
    }

    /// One force evaluation that also returns the fields after every stage, in order (for the
    /// per-stage GPU check: stage k's inputs are the fields after stage k − 1).
    pub fn evaluate_stagewise(&mut self) -> Result<Vec<(Stage, Fields<T>)>, SolverError> {
        let mut out = Vec::new();
        self.run_evaluation(|stage, f, _| out.push((stage, f.clone())))?;
        Ok(out)
    }

    /// Runs the active evaluation stages; `after(stage, fields, time)` sees each one's result.
    /// Without XSPH, ṽ = v afterwards.
    fn run_evaluation(&mut self, mut after: impl FnMut(Stage, &Fields<T>, Duration)) -> Result<(), SolverError> {
        self.evaluated = true;
        let mut f = std::mem::take(&mut self.f);
        for stage in self.model.stages.evaluation() {
            let t = Instant::now();
            match evaluation_fn::<T>(stage) {
                Some(run) => run(&self.ctx(), &mut f),
                None => {
                    self.nbrs = self.search.update(self.exec, &self.model.images, &self.pos, self.model.support());
                    self.peak_neighbours = self.peak_neighbours.max(self.nbrs.max_count());
                }
            }
            after(stage, &f, t.elapsed());
        }
        if !self.model.stages.xsph {
            f.vt[..self.n_fluid].copy_from_slice(&self.vel[..self.n_fluid]);
        }
        let overflow = f.contact_overflow;
        self.f = f;
        if overflow > 0 {
            return Err(SolverError::ContactOverflow {
                step: self.step,
                count: MAX_CONTACTS + overflow,
                cap: MAX_CONTACTS,
            });
        }
        Ok(())
    }

    /// `reduce_max`: max |v| and max |a| over the fluid particles.
    pub fn reduce_max(&self) -> (f64, f64) {
        let nf = self.n_fluid;
        let vmax = self.vel[..nf].iter().map(|v| v.norm().f64()).fold(0.0, f64::max);
        let amax = self.f.acc[..nf].iter().map(|a| a.norm().f64()).fold(0.0, f64::max);
        (vmax, amax)
    }

    /// The dt of the next step: fixed, or the minimum of the limits at the current state.
    pub fn next_dt(&self) -> f64 {
        if self.model.dt_fixed > 0.0 {
            return self.model.dt_fixed;
        }
        self.limits_now().min()
    }

    /// The stability limits at the current state (|v|, |a| of the last evaluation).
    pub fn limits_now(&self) -> DtLimits {
        let (vmax, amax) = self.reduce_max();
        let m = &self.model;
        DtLimits::compute(m.kernel.h.f64(), m.cfl, m.c_max, vmax, m.nu_max, amax, m.rho_mean, m.sigma_max)
    }

    /// The dt of the step about to be taken, checked against the limits at the current state
    /// (recorded in [`Self::numbers`]; [`Self::dt_bound`] names the limit an automatic dt took).
    fn step_dt(&mut self) -> f64 {
        let lim = self.limits_now();
        let dt = if self.model.dt_fixed > 0.0 {
            self.dt_bound = "fixed";
            self.model.dt_fixed
        } else {
            let (name, v) = crate::scene::dt_policy::tightest(&lim);
            self.dt_bound = name;
            v
        };
        self.numbers.record(self.step + 1, dt, self.model.cfl, &lim);
        dt
    }

    /// Mirror and periodic sides: reflect or wrap fluid particles that crossed them (and their
    /// Verlet half-step velocity with the same reflection).
    fn apply_boundaries(&mut self) {
        let im = self.model.images;
        let (lo, hi) = (self.model.lo, self.model.hi);
        for i in 0..self.n_fluid {
            let mut q = self.pos[i];
            if let Some(vh) = self.vhalf.get_mut(i) {
                boundary_axis(&im.x, lo.x, hi.x, &mut q.x, &mut vh.x);
                boundary_axis(&im.y, lo.y, hi.y, &mut q.y, &mut vh.y);
            }
            let (p, v) = (&mut self.pos[i], &mut self.vel[i]);
            boundary_axis(&im.x, lo.x, hi.x, &mut p.x, &mut v.x);
            boundary_axis(&im.y, lo.y, hi.y, &mut p.y, &mut v.y);
        }
    }

    /// Checks for NaN and for particles outside the box (by more than Δx/2).
    pub fn check(&self) -> Result<(), SolverError> {
        let m = &self.model;
        let tol = T::c(0.5) * m.dx;
        for i in 0..self.n_fluid {
            let (p, v) = (self.pos[i], self.vel[i]);
            let what = if !p.is_finite() || !v.is_finite() || !self.f.acc[i].is_finite() {
                Some(format!(
                    "has a non-finite state: x = ({:.4e}, {:.4e}), v = ({:.4e}, {:.4e})",
                    p.x.f64(),
                    p.y.f64(),
                    v.x.f64(),
                    v.y.f64()
                ))
            } else if p.x < m.lo.x - tol || p.x > m.hi.x + tol || p.y < m.lo.y - tol || p.y > m.hi.y + tol {
                Some(format!("left the domain: x = ({:.4e}, {:.4e})", p.x.f64(), p.y.f64()))
            } else {
                None
            };
            if let Some(what) = what {
                let what = format!("{what}; {}", self.numbers.describe(m.cfl));
                return Err(SolverError::BlowUp { step: self.step, t: self.t, particle: i, what });
            }
        }
        Ok(())
    }

    fn fluid_update(&mut self, f: impl Fn(usize, V2<T>, V2<T>) -> (V2<T>, V2<T>)) {
        for i in 0..self.n_fluid {
            let (p, v) = f(i, self.pos[i], self.vel[i]);
            self.pos[i] = p;
            self.vel[i] = v;
        }
    }

    /// The advection velocity of the evaluation for a step of `dt`: ṽ (v or XSPH), plus
    /// (dt/2)·a_b with the transport-velocity formulation (Adami, Hu & Adams 2013, eq. 10),
    /// whose (dt/2)·a_b is kept for the next evaluation's artificial stress ([`Fields::shift_dv`]).
    fn advection(&mut self, dt: T) -> Vec<V2<T>> {
        let half = T::c(0.5) * dt;
        self.f.shift_dv = self.f.shift.iter().map(|a| *a * half).collect();
        let mut vt = self.f.vt.clone();
        for (v, d) in vt.iter_mut().zip(&self.f.shift_dv) {
            *v += *d;
        }
        vt
    }

    /// `midpoint_predict`: half step from the evaluation at the start of the step.
    pub fn midpoint_predict(&mut self, dt: T) {
        let (vt, acc) = (self.advection(dt), self.f.acc.clone());
        self.fluid_update(|i, r, v| integrate_predict(r, v, vt[i], acc[i], dt));
    }

    /// `midpoint_correct`: the full step from the start state `(r0, v0)` with the midpoint
    /// evaluation.
    pub fn midpoint_correct(&mut self, r0: &[V2<T>], v0: &[V2<T>], dt: T) {
        let (vt, acc) = (self.advection(dt), self.f.acc.clone());
        self.fluid_update(|i, _, _| integrate_correct(r0[i], v0[i], vt[i], acc[i], dt));
    }

    /// `verlet_drift`: opening half kick v_{n+½} = v_n + (dt/2) a_n (kept in [`Self::vhalf`]),
    /// the drift with v_{n+½} plus the evaluation's XSPH correction ṽ − v, and the predicted
    /// velocity v_n + dt·a_n in `vel` for the evaluation at the new positions. With the
    /// evaluation at v_{n+½} instead (kept as [`Integrator::VerletPec`]), the viscous force of
    /// the closing kick lags by O(dt): first order with viscosity (1.007 measured).
    pub fn verlet_drift(&mut self, dt: T) {
        self.vhalf.resize(self.n_fluid, V2::from_f64(0.0, 0.0));
        let predicted = self.integrator == Integrator::Verlet;
        let vt = self.advection(dt);
        let acc = &self.f.acc;
        for i in 0..self.n_fluid {
            let v0 = self.vel[i];
            let vh = integrate_kick(v0, acc[i], dt);
            self.pos[i] = integrate_drift(self.pos[i], vh + (vt[i] - v0), dt);
            self.vel[i] = if predicted { integrate_kick(vh, acc[i], dt) } else { vh };
            self.vhalf[i] = vh;
        }
    }

    /// `verlet_kick`: closing half kick v_{n+1} = v_{n+½} + (dt/2) a_{n+1}. The transport
    /// velocity follows it (ṽ += v_{n+1} − v_predicted), so that ṽ − v keeps the XSPH correction
    /// of the evaluation and the next drift moves with v_{n+½} + (ṽ − v).
    pub fn verlet_kick(&mut self, dt: T) {
        for i in 0..self.n_fluid {
            let v = integrate_kick(self.vhalf[i], self.f.acc[i], dt);
            self.f.vt[i] = self.f.vt[i] + (v - self.vel[i]);
            self.vel[i] = v;
        }
    }

    /// One time step of the scene's integrator: (first evaluation,) the integrator's opening
    /// stage, boundaries, the evaluation, its closing stage, boundaries, `check`.
    pub fn advance(&mut self) -> Result<(), SolverError> {
        if self.integrator == Integrator::Midpoint || !self.have_acc {
            self.evaluate()?;
        }
        let dt = self.step_dt();
        let dtt = T::c(dt);
        let (open, close) = Stage::step_pair(self.integrator);
        let (r0, v0) = if close == Stage::MidpointCorrect {
            (self.pos.clone(), self.vel.clone())
        } else {
            (Vec::new(), Vec::new())
        };
        for (k, stage) in [open, close].into_iter().enumerate() {
            if k == 1 {
                self.apply_boundaries();
                self.evaluate()?;
            }
            match stage {
                Stage::MidpointPredict => self.midpoint_predict(dtt),
                Stage::MidpointCorrect => self.midpoint_correct(&r0, &v0, dtt),
                Stage::VerletDrift => self.verlet_drift(dtt),
                Stage::VerletKick => self.verlet_kick(dtt),
                other => unreachable!("{other} is not an integrator stage"),
            }
        }
        self.have_acc = true;
        self.dt = dt;
        self.apply_boundaries();
        self.step += 1;
        self.t += self.dt;
        self.check()
    }
}

/// Reflects (mirror) or wraps (periodic) one coordinate across the box sides (twin of WGSL
/// `boundary_axis` in shaders/geometry.wgsl, same name).
#[inline(always)]
pub fn boundary_axis<T: Real>(maps: &[Option<AxisMap<T>>; 2], lo: T, hi: T, x: &mut T, v: &mut T) {
    match maps[0] {
        Some(AxisMap::Mirror(p)) if *x < p => {
            *x = p + p - *x;
            *v = -*v;
        }
        Some(AxisMap::Shift(s)) if *x < lo => *x -= s,
        _ => {}
    }
    match maps[1] {
        Some(AxisMap::Mirror(p)) if *x > p => {
            *x = p + p - *x;
            *v = -*v;
        }
        Some(AxisMap::Shift(s)) if *x >= hi => *x -= s,
        _ => {}
    }
}

impl<T: Real> Backend for CpuSolver<T> {
    fn name(&self) -> String {
        self.exec.name().to_string()
    }
    fn precision(&self) -> &'static str {
        T::NAME
    }
    fn step(&mut self) -> Result<(), SolverError> {
        self.advance()
    }
    fn time(&self) -> f64 {
        self.t
    }
    fn steps(&self) -> u64 {
        self.step
    }
    fn peak_neighbours(&self) -> Option<usize> {
        Some(self.peak_neighbours)
    }
    fn frame(&mut self) -> Frame {
        if !self.evaluated {
            // The fields of the initial state, so that the t = 0 row is measured, not zeros.
            let _ = self.evaluate();
        }
        Frame::from_fields(self.step, self.t, self.dt, self.n_fluid, &self.pos, &self.vel, &self.phase, &self.f)
    }
    fn restart_with_velocities(&mut self, vel: &[[f64; 2]]) {
        for (i, v) in vel.iter().enumerate().take(self.n_fluid) {
            self.vel[i] = V2::from_f64(v[0], v[1]);
        }
        self.t = 0.0;
        self.step = 0;
        self.numbers = StabilityNumbers::default();
        self.have_acc = false;
        self.evaluated = false;
    }
}
