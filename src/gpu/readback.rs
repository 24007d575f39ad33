//! Moving data between the host and a [`GpuSolver`]: reading the fields and the state back,
//! and the per-stage check of `sphlab verify` (upload CPU-produced inputs, run ONE stage with its
//! outputs poisoned, read everything back), and the neighbour structures for their exact check.

use super::solver::GpuSolver;
use super::solver_buffers::ctl;
use super::variant::SearchVariant;
use super::variant_buffers::NBR_SLOTS;
use super::GpuError;
use crate::fields::{ContactPoint, Field, Fields};
use crate::model::MAX_CONTACTS;
use crate::real::{Real, Sym2, V2};
use crate::stage::Stage;

/// The GPU neighbour structures after an evaluation.
#[derive(Clone, Debug)]
pub struct NeighbourView {
    /// Offsets of each cell in `sorted` (n_cells + 1; empty for the `direct` search).
    pub cell_start: Vec<u32>,
    /// Particles by cell, increasing within a cell.
    pub sorted: Vec<u32>,
    /// Each particle's explicit list, packed `j | code << 28`, sorted (list variants only).
    pub lists: Option<Vec<Vec<u32>>>,
}

impl<T: Real> GpuSolver<T> {
    /// Uploads CPU-produced inputs, runs the neighbour search and ONE stage, and reads every
    /// field back. The stage's pure outputs (the stage table's) are poisoned first (NaN), so an
    /// element the kernel forgets to write shows up in the comparison.
    pub fn run_stage_from(
        &mut self,
        pos: &[V2<T>],
        vel: &[V2<T>],
        f: &Fields<T>,
        stage: Stage,
    ) -> Result<Fields<T>, GpuError> {
        let ctx = &*self.ctx;
        let b = &self.b;
        b.pos.upload(ctx, pos)?;
        b.vel.upload(ctx, vel)?;
        b.sigma.upload(ctx, &f.sigma)?;
        b.chi.upload(ctx, &f.chi)?;
        b.mass.upload(ctx, &f.mass)?;
        b.colour.upload(ctx, &f.colour)?;
        b.rho.upload(ctx, &f.rho)?;
        b.p.upload(ctx, &f.p)?;
        let grad: Vec<V2<T>> = f.grad.iter().flat_map(|g| [g[0], g[1]]).collect();
        b.grad.upload(ctx, &grad)?;
        b.pi.upload(ctx, &f.pi.iter().map(|t| V2::new(t.xx, t.xy)).collect::<Vec<_>>())?;
        b.acc.upload(ctx, &f.acc)?;
        b.vt.upload(ctx, &f.vt)?;
        self.upload_contacts(&f.contacts)?;
        let nan = T::nan();
        let nan2 = V2::new(nan, nan);
        for field in stage.pure_outputs() {
            match field {
                Field::Sigma => b.sigma.fill(ctx, nan)?,
                Field::Chi => b.chi.fill(ctx, nan)?,
                Field::Mass => b.mass.fill(ctx, nan)?,
                Field::Rho => b.rho.fill(ctx, nan)?,
                Field::P => b.p.fill(ctx, nan)?,
                Field::Grad => b.grad.fill(ctx, nan2)?,
                Field::Pi => b.pi.fill(ctx, nan2)?,
                Field::Acc => b.acc.fill(ctx, nan2)?,
                Field::Vt => b.vt.fill(ctx, nan2)?,
                Field::Contacts => b.contacts.fill(ctx, nan)?,
                Field::Colour => b.colour.fill(ctx, -1)?,
            }
        }
        if !self.pipes.stages.contains_key(&stage) {
            return Err(GpuError::Unsupported(format!("{}: no stage `{stage}`", self.spec)));
        }
        self.vb.invalidate(ctx)?;
        self.submit(|enc| {
            self.record(enc, Stage::NeighbourSearch);
            if stage != Stage::NeighbourSearch {
                self.record(enc, stage);
            }
        })?;
        self.ctx.wait_idle()?;
        self.vb.overflow(&self.ctx, self.step)?;
        self.read_fields()
    }

    fn upload_contacts(&self, cps: &[ContactPoint<T>]) -> Result<(), GpuError> {
        let mut c = vec![T::zero(); 4 * MAX_CONTACTS];
        for (k, cp) in cps.iter().take(MAX_CONTACTS).enumerate() {
            c[4 * k..4 * k + 3].copy_from_slice(&[cp.r.x, cp.r.y, cp.s]);
        }
        self.b.contacts.upload(&self.ctx, &c)?;
        let mut w = self.b.ctl.read_back(&self.ctx)?;
        w[ctl::CONTACTS] = cps.len().min(MAX_CONTACTS) as u32;
        w[ctl::CONTACTS_FOUND] = cps.len() as u32;
        self.b.ctl.upload(&self.ctx, &w)
    }

    /// Reads every per-evaluation field back (positions and velocities separately).
    pub fn read_fields(&self) -> Result<Fields<T>, GpuError> {
        let ctx = &*self.ctx;
        let b = &self.b;
        let w = b.ctl.read_back(ctx)?;
        let raw = b.contacts.read_back(ctx)?;
        let kept = (w[ctl::CONTACTS] as usize).min(MAX_CONTACTS);
        let grad = b.grad.read_back(ctx)?;
        Ok(Fields {
            sigma: b.sigma.read_back(ctx)?,
            chi: b.chi.read_back(ctx)?,
            mass: b.mass.read_back(ctx)?,
            colour: b.colour.read_back(ctx)?,
            rho: b.rho.read_back(ctx)?,
            p: b.p.read_back(ctx)?,
            grad: grad.chunks(2).map(|g| [g[0], g[1]]).collect(),
            pi: b.pi.read_back(ctx)?.iter().map(|t| Sym2 { xx: t.x, xy: t.y }).collect(),
            acc: b.acc.read_back(ctx)?,
            vt: b.vt.read_back(ctx)?,
            contacts: (0..kept)
                .map(|k| ContactPoint { r: V2::new(raw[4 * k], raw[4 * k + 1]), s: raw[4 * k + 2] })
                .collect(),
            contact_overflow: (w[ctl::CONTACTS_FOUND] as usize).saturating_sub(MAX_CONTACTS),
        })
    }

    /// The neighbour structures of the last evaluation (for the exact comparison with the CPU).
    pub fn read_neighbours(&self) -> Result<NeighbourView, GpuError> {
        let ctx = &*self.ctx;
        let (cell_start, sorted) = if self.spec.search == SearchVariant::Direct {
            (Vec::new(), Vec::new())
        } else {
            (self.b.cell_start.read_back(ctx)?, self.b.sorted.read_back(ctx)?)
        };
        let lists = if self.spec.has_lists() {
            let (counts, nbr) = (self.vb.counts.read_back(ctx)?, self.vb.nbr.read_back(ctx)?);
            let list = |i: usize| {
                let mut l = nbr[i * NBR_SLOTS..i * NBR_SLOTS + (counts[i] as usize).min(NBR_SLOTS)].to_vec();
                l.sort_unstable();
                l
            };
            Some((0..self.n).map(list).collect())
        } else {
            None
        };
        Ok(NeighbourView { cell_start, sorted, lists })
    }

    /// Positions and velocities.
    pub fn read_state(&self) -> Result<(Vec<V2<T>>, Vec<V2<T>>), GpuError> {
        Ok((self.b.pos.read_back(&self.ctx)?, self.b.vel.read_back(&self.ctx)?))
    }
}
