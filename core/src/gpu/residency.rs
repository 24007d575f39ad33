//! Host↔device residency of a [`GpuSolver`]'s particle state, for the study's E2 hybrids and E3
//! subdomains (`study::e2_residency`, `study::e3_subdomains`): upload or download one named
//! [`Part`] of the state, returning the bytes moved by that copy call (so the study COUNTS the
//! traffic, never estimates it); a neighbour cell structure built on the host (the GPU `cells`
//! layout: `cell_start`, `sorted`, `cell_of`) and its upload; a list of stages recorded in one
//! submission; a different particle set loaded into a solver built with spare capacity (one
//! subdomain after another on one device); and the device bytes the solver allocated.

use super::buffers::GpuVec;
use super::solver::GpuSolver;
use super::solver_buffers::{cell_of_pos, ctl, sigma_of, sigma_pairs, wall_cells};
use super::{GpuContext, GpuError};
use crate::fields::{Field, Fields};
use crate::model::{COLOUR_WALL, NO_COLOUR};
use crate::real::{Real, Sym2, V2};
use crate::scene::ContactMode;
use crate::stage::Stage;
use bytemuck::Pod;

/// One named part of the particle state that can live on the host, the device or both.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    /// Positions.
    Pos,
    /// Velocities.
    Vel,
    /// A per-evaluation field (contact points excluded).
    Field(Field),
}

/// The GPU `cells` neighbour structure of the fluids built on the host (same grid, same order;
/// the walls' static sort is the solver's own, `solver_buffers::WallCells`).
#[derive(Clone, Debug, Default)]
pub struct HostCells {
    /// Offsets of each cell in `sorted` (cells + 1).
    pub cell_start: Vec<u32>,
    /// Fluid particles by cell, increasing within a cell.
    pub sorted: Vec<u32>,
    /// The cell of each fluid particle.
    pub cell_of: Vec<u32>,
}

/// Writes `data` into the first elements of `v`; the bytes written.
fn write_prefix<P: Pod>(ctx: &GpuContext, v: &GpuVec<P>, data: &[P]) -> Result<u64, GpuError> {
    if data.len() > v.len() {
        return Err(GpuError::Validation(format!("upload of {} elements into a GpuVec of {}", data.len(), v.len())));
    }
    let bytes: &[u8] = bytemuck::cast_slice(data);
    if bytes.len().is_multiple_of(4) {
        if !bytes.is_empty() {
            ctx.queue.write_buffer(&v.buffer, 0, bytes);
        }
    } else {
        let mut padded = bytes.to_vec();
        padded.resize(bytes.len().next_multiple_of(4), 0);
        ctx.queue.write_buffer(&v.buffer, 0, &padded);
    }
    Ok(bytes.len() as u64)
}

/// Reads the first `len` elements of `v` back (a synchronisation point).
fn read_prefix<P: Pod>(ctx: &GpuContext, v: &GpuVec<P>, len: usize) -> Result<Vec<P>, GpuError> {
    v.read_range(ctx, 0, len)
}

impl<T: Real> GpuSolver<T> {
    /// The residency API moves arrays by index: it needs the device in the original particle
    /// order, i.e. cell ordering off (`set_reorder_every(0)` before the first step).
    fn require_original_order(&self) -> Result<(), GpuError> {
        if self.reorder_every() != 0 {
            return Err(GpuError::Unsupported(
                "host<->device residency needs the original particle order: call set_reorder_every(0) first".into(),
            ));
        }
        Ok(())
    }

    /// Particles currently loaded (≤ [`Self::capacity`]).
    pub fn particles(&self) -> usize {
        self.n
    }

    /// Particles the buffers hold.
    pub fn capacity(&self) -> usize {
        self.b.pos().len()
    }

    /// Uploads `part` of the first `rows` particles from host arrays; the bytes written.
    pub fn upload_part(
        &self,
        part: Part,
        rows: usize,
        pos: &[V2<T>],
        vel: &[V2<T>],
        f: &Fields<T>,
    ) -> Result<u64, GpuError> {
        self.require_original_order()?;
        let (ctx, b) = (&*self.ctx, &self.b);
        let r = rows;
        match part {
            Part::Pos => write_prefix(ctx, b.pos(), &pos[..r]),
            Part::Vel => write_prefix(ctx, b.vel(), &vel[..r]),
            Part::Field(field) => match field {
                Field::Sigma => write_prefix(ctx, b.sigma(), &sigma_pairs(&f.sigma[..r])),
                Field::Chi => write_prefix(ctx, &b.chi, &f.chi[..r]),
                Field::Mass => write_prefix(ctx, b.mass(), &f.mass[..r]),
                Field::Colour => write_prefix(ctx, &b.colour, &f.colour[..r]),
                Field::Rho => write_prefix(ctx, b.rho(), &f.rho[..r]),
                Field::P => write_prefix(ctx, &b.p, &f.p[..r]),
                Field::Grad => {
                    let slot = |s: usize| f.grad[..r].iter().map(|g| g[s]).collect::<Vec<V2<T>>>();
                    Ok(write_prefix(ctx, b.grad0(), &slot(0))? + write_prefix(ctx, b.grad1(), &slot(1))?)
                }
                Field::Pi => {
                    let p: Vec<V2<T>> = f.pi[..r].iter().map(|t| V2::new(t.xx, t.xy)).collect();
                    write_prefix(ctx, b.pi(), &p)
                }
                Field::Acc => write_prefix(ctx, &b.acc, &f.acc[..r]),
                Field::Vt => write_prefix(ctx, &b.vt, &f.vt[..r]),
                Field::Contacts => {
                    Err(GpuError::Unsupported("contact points do not move between host and device".into()))
                }
            },
        }
    }

    /// Downloads `part` of the first `rows` particles into host arrays; the bytes read.
    pub fn download_part(
        &self,
        part: Part,
        rows: usize,
        pos: &mut [V2<T>],
        vel: &mut [V2<T>],
        f: &mut Fields<T>,
    ) -> Result<u64, GpuError> {
        let (ctx, b) = (&*self.ctx, &self.b);
        let r = rows;
        fn put<P: Pod>(dst: &mut [P], src: Vec<P>) -> u64 {
            let k = src.len().min(dst.len());
            dst[..k].copy_from_slice(&src[..k]);
            (src.len() * size_of::<P>()) as u64
        }
        Ok(match part {
            Part::Pos => put(&mut pos[..r], read_prefix(ctx, b.pos(), r)?),
            Part::Vel => put(&mut vel[..r], read_prefix(ctx, b.vel(), r)?),
            Part::Field(field) => match field {
                Field::Sigma => {
                    // The bytes moved are the records' (σ, 1/σ²).
                    let records = read_prefix(ctx, b.sigma(), r)?;
                    let bytes = (records.len() * size_of::<V2<T>>()) as u64;
                    put(&mut f.sigma[..r], sigma_of(records));
                    bytes
                }
                Field::Chi => put(&mut f.chi[..r], read_prefix(ctx, &b.chi, r)?),
                Field::Mass => put(&mut f.mass[..r], read_prefix(ctx, b.mass(), r)?),
                Field::Colour => put(&mut f.colour[..r], read_prefix(ctx, &b.colour, r)?),
                Field::Rho => put(&mut f.rho[..r], read_prefix(ctx, b.rho(), r)?),
                Field::P => put(&mut f.p[..r], read_prefix(ctx, &b.p, r)?),
                Field::Grad => {
                    let (g0, g1) = (read_prefix(ctx, b.grad0(), r)?, read_prefix(ctx, b.grad1(), r)?);
                    for (i, (a, c)) in g0.iter().zip(&g1).enumerate() {
                        f.grad[i] = [*a, *c];
                    }
                    ((g0.len() + g1.len()) * size_of::<V2<T>>()) as u64
                }
                Field::Pi => {
                    let p = read_prefix(ctx, b.pi(), r)?;
                    for (i, t) in p.iter().enumerate() {
                        f.pi[i] = Sym2 { xx: t.x, xy: t.y };
                    }
                    (p.len() * size_of::<V2<T>>()) as u64
                }
                Field::Acc => put(&mut f.acc[..r], read_prefix(ctx, &b.acc, r)?),
                Field::Vt => put(&mut f.vt[..r], read_prefix(ctx, &b.vt, r)?),
                Field::Contacts => {
                    return Err(GpuError::Unsupported("contact points do not move between host and device".into()))
                }
            },
        })
    }

    /// The fluids' `cells` structure of `pos` on this solver's grid, built on the host exactly
    /// as the GPU counting sort builds it (`cell_index` clamps into the grid; index order in a
    /// cell).
    pub fn host_cells(&self, pos: &[V2<T>]) -> HostCells {
        let cell_of: Vec<u32> = pos[..self.n_fluid].iter().map(|&p| cell_of_pos(&self.grid, p)).collect();
        let cells = self.grid.cells();
        let mut cell_start = vec![0u32; cells + 1];
        for &c in &cell_of {
            cell_start[c as usize + 1] += 1;
        }
        for c in 0..cells {
            cell_start[c + 1] += cell_start[c];
        }
        let mut cursor = cell_start.clone();
        let mut sorted = vec![0u32; cell_of.len()];
        for (i, &c) in cell_of.iter().enumerate() {
            sorted[cursor[c as usize] as usize] = i as u32;
            cursor[c as usize] += 1;
        }
        HostCells { cell_start, sorted, cell_of }
    }

    /// Uploads a host-built cell structure (instead of running the GPU search); the bytes.
    pub fn upload_cells(&self, c: &HostCells) -> Result<u64, GpuError> {
        let ctx = &*self.ctx;
        Ok(write_prefix(ctx, &self.b.cell_start, &c.cell_start)?
            + write_prefix(ctx, &self.b.sorted, &c.sorted)?
            + write_prefix(ctx, &self.b.cell_of, &c.cell_of)?)
    }

    /// Records `stages` in one submission (not waited for). With `dt` the `Params` uniform is
    /// rewritten first with that dt and `step` (the integrator and check stages read them);
    /// returns the bytes of that uniform write (0 without).
    pub fn run_stages(&mut self, stages: &[Stage], dt: Option<(f64, u64)>) -> Result<u64, GpuError> {
        let mut bytes = 0;
        if let Some((dt, step)) = dt {
            // The device clock (gpu::clock): dt and t for the integrator stages; `check`'s
            // clock_tick advances the device step counter itself.
            let _ = step;
            super::clock::write_clock(&self.ctx, &self.vb, dt, self.t);
            bytes = 3 * size_of::<T>() as u64;
        }
        if !stages.is_empty() {
            self.submit(|enc| {
                for &s in stages {
                    self.record(enc, s);
                }
            })?;
        }
        Ok(bytes)
    }

    /// ṽ = v on the device for the fluid rows (the evaluation's last act without XSPH).
    pub fn vt_from_vel(&self) -> Result<(), GpuError> {
        let bytes = (self.n_fluid * size_of::<V2<T>>()) as u64;
        if bytes == 0 {
            return Ok(());
        }
        self.submit(|enc| enc.copy_buffer_to_buffer(&self.b.vel().buffer, 0, &self.b.vt.buffer, 0, bytes)).map(|_| ())
    }

    /// Loads another particle set (fluids first, `n_fluid` of them, then walls) into a solver
    /// built with at least `pos.len()` particles of capacity: positions, velocities, phases and
    /// the static colours and masses; the step counter and control words restart. The grid stays
    /// the one the solver was built on (build it over the whole domain). Returns the bytes.
    pub fn load_particles(
        &mut self,
        pos: &[V2<T>],
        vel: &[V2<T>],
        phase: &[u32],
        n_fluid: usize,
    ) -> Result<u64, GpuError> {
        let n = pos.len();
        if n > self.capacity() || vel.len() != n || phase.len() != n || n_fluid > n {
            return Err(GpuError::Validation(format!(
                "load_particles: {n} particles ({n_fluid} fluid) into a solver of capacity {}",
                self.capacity()
            )));
        }
        let ctx = &*self.ctx;
        let m = &self.model;
        let wall_colour = if m.contact_mode == ContactMode::A { COLOUR_WALL } else { NO_COLOUR };
        let colour: Vec<i32> = (0..n).map(|i| if i < n_fluid { phase[i] as i32 } else { wall_colour }).collect();
        let mass: Vec<T> =
            (0..n).map(|i| m.phases[if i < n_fluid { phase[i] as usize } else { m.wall_phase }].mass).collect();
        let mut bytes = write_prefix(ctx, self.b.pos(), pos)?
            + write_prefix(ctx, self.b.vel(), vel)?
            + write_prefix(ctx, &self.b.phase, phase)?
            + write_prefix(ctx, &self.b.colour, &colour)?
            + write_prefix(ctx, self.b.mass(), &mass)?;
        // The walls' static sort of this set, in its (original) order.
        let walls = wall_cells(&self.grid, pos, n_fluid);
        self.b.upload_walls(ctx, &walls, self.grid.cells(), n_fluid);
        bytes += 4 * (walls.start.len() + walls.list.len() + walls.cell_of.len()) as u64;
        self.rb.reset_order(ctx)?;
        self.reset_ctl()?;
        bytes += (ctl::LEN * 4 + 3 * size_of::<T>()) as u64;
        self.n = n;
        self.n_fluid = n_fluid;
        self.phase = phase.to_vec();
        let params = super::params::Params::new(&self.model, n, n_fluid, &self.grid);
        self.b.params.write(ctx, &params);
        bytes += size_of_val(&params) as u64;
        self.t = 0.0;
        self.step = 0;
        self.have_acc = false;
        Ok(bytes)
    }

    /// One force evaluation of the loaded particles (every active stage, then ṽ = v without
    /// XSPH), submitted and waited for; a neighbour overflow is an error.
    pub fn evaluate_loaded(&mut self) -> Result<(), GpuError> {
        let stages = self.model.stages.evaluation();
        self.run_stages(&stages, None)?;
        if !self.model.stages.xsph {
            self.vt_from_vel()?;
        }
        self.ctx.wait_idle()?;
        Ok(self.vb.overflow(&self.ctx, self.step)?)
    }

    /// Waits for every submitted command.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.ctx.wait_idle()
    }
}
