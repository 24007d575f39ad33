//! Moving data between the host and a [`GpuSolver`]: reading the fields and the state back,
//! and the per-stage check of `sphlab verify` (upload CPU-produced inputs, run ONE stage with its
//! outputs poisoned, read everything back), and the neighbour structures for their exact check.
//! Everything crosses in the original particle order (`gpu::reorder` maps to and from the
//! device's cell order).

use super::mask_lists::{decode, uses_masks, MaskBuffers};
use super::pooled_lists::{pooled_slot, SlotLayout};
use super::reorder::{to_device, to_original};
use super::solver::GpuSolver;
use super::solver_buffers::{ctl, sigma_of, sigma_pairs};
use super::variant::SumLayout;
use super::variant_buffers::NBR_SLOTS;
use super::GpuError;
use crate::fields::{ContactPoint, Field, Fields};
use crate::model::{CONTACT_WORDS, MAX_CONTACTS};
use crate::neighbours::INDEX_MASK as PACK_MASK;
use crate::physics::contact::line_force_per_weight;
use crate::real::{Real, Sym2, V2};
use crate::stage::Stage;
use std::cmp::Ordering;

/// Positions and velocities in particle order.
pub type PosVel<T> = (Vec<V2<T>>, Vec<V2<T>>);

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
        let o = self.device_order()?;
        b.pos().upload(ctx, &to_device(pos, 1, &o))?;
        self.counts_fresh.set(false);
        self.lists_kept.set(false);
        b.vel().upload(ctx, &to_device(vel, 1, &o))?;
        b.sigma().upload(ctx, &to_device(&sigma_pairs(&f.sigma), 1, &o))?;
        b.chi.upload(ctx, &to_device(&f.chi, 1, &o))?;
        b.mass().upload(ctx, &to_device(&f.mass, 1, &o))?;
        b.colour.upload(ctx, &to_device(&f.colour, 1, &o))?;
        b.rho().upload(ctx, &to_device(&f.rho, 1, &o))?;
        b.p.upload(ctx, &to_device(&f.p, 1, &o))?;
        for (s, slot) in [b.grad0(), b.grad1()].into_iter().enumerate() {
            let g: Vec<V2<T>> = f.grad.iter().map(|g| g[s]).collect();
            slot.upload(ctx, &to_device(&g, 1, &o))?;
        }
        let pi: Vec<V2<T>> = f.pi.iter().map(|t| V2::new(t.xx, t.xy)).collect();
        b.pi().upload(ctx, &to_device(&pi, 1, &o))?;
        b.acc.upload(ctx, &to_device(&f.acc, 1, &o))?;
        b.vt.upload(ctx, &to_device(&f.vt, 1, &o))?;
        self.upload_contacts(f, &pos[..self.n_fluid])?;
        let nan = T::nan();
        let nan2 = V2::new(nan, nan);
        for field in stage.pure_outputs() {
            match field {
                Field::Sigma => b.sigma().fill(ctx, nan2)?,
                Field::Chi => b.chi.fill(ctx, nan)?,
                Field::Mass => b.mass().fill(ctx, nan)?,
                Field::Rho => b.rho().fill(ctx, nan)?,
                Field::P => b.p.fill(ctx, nan)?,
                Field::Grad => {
                    b.grad0().fill(ctx, nan2)?;
                    b.grad1().fill(ctx, nan2)?
                }
                Field::Pi => b.pi().fill(ctx, nan2)?,
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
        // No renumbering here: the uploaded per-evaluation inputs (σ, p, ∇C, …) do not move
        // (the slots hold their particles through `sorted`, not in physical order).
        let every = std::mem::replace(&mut self.reorder_every, 0);
        self.vb.set_physical(&self.ctx, false);
        let done = self.submit(|enc| {
            self.record(enc, Stage::NeighbourSearch);
            if stage != Stage::NeighbourSearch {
                self.record(enc, stage);
            }
        });
        self.reorder_every = every;
        self.vb.set_physical(&self.ctx, self.physical_order());
        done?;
        self.ctx.wait_idle()?;
        self.vb.overflow(&self.ctx, self.step).map_err(|e| self.to_original(e))?;
        self.read_fields()
    }

    /// Uploads `f`'s contact points: x, y, s, the cos θ_d measured there and, with the
    /// unbalanced Young force, the point's line force per unit weight over the `fluid` positions
    /// (what `contact_angle` writes on the device).
    fn upload_contacts(&self, f: &Fields<T>, fluid: &[V2<T>]) -> Result<(), GpuError> {
        let cps = &f.contacts;
        let mut c = vec![T::zero(); CONTACT_WORDS * MAX_CONTACTS];
        for (k, cp) in cps.iter().take(MAX_CONTACTS).enumerate() {
            let cos = f.contact_cos.get(k).copied();
            let per_weight = if self.model.young_unbalanced {
                line_force_per_weight(&self.model, cp, cos, fluid)
            } else {
                T::zero()
            };
            let words = [cp.r.x, cp.r.y, cp.s, cos.unwrap_or(T::zero()), per_weight];
            c[CONTACT_WORDS * k..CONTACT_WORDS * (k + 1)].copy_from_slice(&words);
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
        let kept = (w[ctl::CONTACTS_FOUND] as usize).min(MAX_CONTACTS);
        let (contacts, contact_cos) = sorted_contacts(
            (0..kept)
                .map(|k| {
                    let c = &raw[CONTACT_WORDS * k..CONTACT_WORDS * (k + 1)];
                    (ContactPoint { r: V2::new(c[0], c[1]), s: c[2] }, c[3])
                })
                .collect(),
        );
        // The measured angles only where the scene measures them (the CPU's fields have none else).
        let contact_cos = if self.model.young_unbalanced { contact_cos } else { Vec::new() };
        let o = self.device_order()?;
        let (g0, g1) = (to_original(b.grad0().read_back(ctx)?, 1, &o), to_original(b.grad1().read_back(ctx)?, 1, &o));
        Ok(Fields {
            sigma: to_original(sigma_of(b.sigma().read_back(ctx)?), 1, &o),
            chi: to_original(b.chi.read_back(ctx)?, 1, &o),
            mass: to_original(b.mass().read_back(ctx)?, 1, &o),
            colour: to_original(b.colour.read_back(ctx)?, 1, &o),
            rho: to_original(b.rho().read_back(ctx)?, 1, &o),
            p: to_original(b.p.read_back(ctx)?, 1, &o),
            grad: g0.into_iter().zip(g1).map(|(a, c)| [a, c]).collect(),
            pi: to_original(b.pi().read_back(ctx)?, 1, &o).iter().map(|t| Sym2 { xx: t.x, xy: t.y }).collect(),
            pi_iso: Vec::new(),
            acc: to_original(b.acc.read_back(ctx)?, 1, &o),
            vt: to_original(b.vt.read_back(ctx)?, 1, &o),
            contacts,
            contact_overflow: (w[ctl::CONTACTS_FOUND] as usize).saturating_sub(MAX_CONTACTS),
            contact_cos,
            shift: Vec::new(),
            shift_dv: Vec::new(),
        })
    }

    /// Fills the fluids' cell lists of the next search (`sorted[0..n_fluid)`: not the walls'
    /// static lists, nor the previous lists kept after them for the merge) with an index no
    /// particle has, so a slot the next search does not write fails every comparison (tests).
    pub fn poison_cell_lists(&self) -> Result<(), GpuError> {
        let poison = vec![u32::MAX; self.n_fluid];
        self.ctx.traffic.write();
        self.ctx.queue.write_buffer(&self.b.sorted.buffer, 0, bytemuck::cast_slice(&poison));
        Ok(())
    }

    /// Runs the stage table's `cell_scan` as a pass of its own on `counts` (one per cell, with
    /// the per-block sums the count kernels keep after them computed here) and returns the cell
    /// starts it wrote with the control word [`ctl::SCAN_MISS`]: the scan and its check that the
    /// counts sum to the particle count, on counts a test chooses (tests).
    pub fn scan_counts(&self, counts: &[u32]) -> Result<(Vec<u32>, u32), GpuError> {
        let cells = self.grid.cells();
        assert_eq!(counts.len(), cells, "one count per cell");
        let block = crate::gpu::plan::SCAN_BLOCK;
        let mut words = counts.to_vec();
        words.extend(counts.chunks(block).map(|c| c.iter().sum::<u32>()));
        self.ctx.traffic.write();
        self.ctx.queue.write_buffer(&self.b.cell_count.buffer, 0, bytemuck::cast_slice(&words));
        self.reset_ctl()?;
        self.submit(|enc| self.record(enc, Stage::CellScan))?;
        self.ctx.wait_idle()?;
        let starts = self.b.cell_start.read_range(&self.ctx, 0, cells + 1)?;
        Ok((starts, self.b.ctl.read_back(&self.ctx)?[ctl::SCAN_MISS]))
    }

    /// The neighbour structures of the last evaluation (for the exact comparison with the CPU),
    /// in original indices: `sorted` re-sorted within each cell, each list under its particle's
    /// original index, whatever the device order and list layout (slot- or particle-major).
    pub fn read_neighbours(&self) -> Result<NeighbourView, GpuError> {
        let ctx = &*self.ctx;
        let o = self.device_order()?;
        // (An index no particle has, e.g. a poisoned slot, reads as u32::MAX.)
        let orig = |e: u32| o.get((e & PACK_MASK) as usize).map_or(u32::MAX, |&d| d | (e & !PACK_MASK));
        let starts = if self.spec.sorts_cells() { self.b.cell_start.read_back(ctx)? } else { Vec::new() };
        let slots = if self.spec.sorts_cells() { self.b.sorted.read_range(ctx, 0, self.n)? } else { Vec::new() };
        let (cell_start, sorted) = if !self.spec.sorts_cells() {
            (Vec::new(), Vec::new())
        } else {
            // Each cell's fluid slots, then its wall slots, as one list per cell.
            let cells = self.grid.cells();
            let (fluid, wall) = (&starts[..cells + 1], &starts[2 * (cells + 1)..3 * (cells + 1)]);
            let mut start = vec![0u32];
            let mut sorted = Vec::with_capacity(self.n);
            for c in 0..cells {
                for (a, e) in [(fluid[c], fluid[c + 1]), (wall[c], wall[c + 1])] {
                    sorted.extend(slots[(a as usize).min(self.n)..(e as usize).min(self.n)].iter().map(|&j| orig(j)));
                }
                let k = start[c] as usize;
                sorted[k..].sort_unstable();
                start.push(sorted.len() as u32);
            }
            (start, sorted)
        };
        let lists = if self.spec.has_lists() && uses_masks(&self.spec) {
            let (pos, ref_pos) = (self.b.pos().read_back(ctx)?, self.vb.ref_pos.read_back(ctx)?);
            // The slots as the kernels read them (`slot_at`): s itself in physical order.
            let sorted: Vec<u32> = if self.physical_order() { (0..self.n as u32).collect() } else { slots };
            let (nbr, cand, cand_hi) =
                (self.vb.nbr[0].read_back(ctx)?, self.vb.cand.read_back(ctx)?, self.vb.cand_hi.read_back(ctx)?);
            let bufs = MaskBuffers {
                pos: &pos,
                ref_pos: &ref_pos,
                cell_start: &starts,
                sorted: &sorted,
                nbr: &nbr,
                cand: &cand,
                cand_hi: &cand_hi,
            };
            let device = decode(&self.spec, &self.grid, &self.model.images, &bufs);
            let mut lists = vec![Vec::new(); self.n];
            for (d, &orig_i) in o.iter().enumerate() {
                let mut l: Vec<u32> = device[d].iter().map(|&e| orig(e)).collect();
                l.sort_unstable();
                lists[orig_i as usize] = l;
            }
            Some(lists)
        } else if self.spec.has_lists() {
            let counts = self.vb.counts.read_back(ctx)?;
            let slot_major = self.spec.mapping.layout() == SumLayout::Thread;
            let mut lists = vec![Vec::new(); self.n];
            // Each list chunk's slots (`gpu::list_chunks`), indexed within the chunk.
            for (buf, &(base, len)) in self.vb.nbr.iter().zip(&self.vb.chunks) {
                let nbr = buf.read_back(ctx)?;
                let pooled = self.spec.slots == SlotLayout::Pooled;
                let slot = |l: usize, k: usize| match (pooled, slot_major) {
                    (true, _) => pooled_slot(&nbr, l, k),
                    (false, true) => k * len + l,
                    (false, false) => l * NBR_SLOTS + k,
                };
                for l in 0..len {
                    let d = base + l;
                    let mut list: Vec<u32> =
                        (0..(counts[d] as usize).min(NBR_SLOTS)).map(|k| orig(nbr[slot(l, k)])).collect();
                    list.sort_unstable();
                    lists[o[d] as usize] = list;
                }
            }
            Some(lists)
        } else {
            None
        };
        Ok(NeighbourView { cell_start, sorted, lists })
    }

    /// Positions and velocities.
    pub fn read_state(&self) -> Result<PosVel<T>, GpuError> {
        let o = self.device_order()?;
        let (pos, vel) = (self.b.pos().read_back(&self.ctx)?, self.b.vel().read_back(&self.ctx)?);
        Ok((to_original(pos, 1, &o), to_original(vel, 1, &o)))
    }
}

/// Contact points in the CPU's (x, s) order (the device keeps them in the order found), each
/// with its measured cos θ_d.
fn sorted_contacts<T: Real>(mut c: Vec<(ContactPoint<T>, T)>) -> (Vec<ContactPoint<T>>, Vec<T>) {
    c.sort_by(|(a, _), (b, _)| {
        a.r.x.partial_cmp(&b.r.x).unwrap_or(Ordering::Equal).then(a.s.partial_cmp(&b.s).unwrap_or(Ordering::Equal))
    });
    c.into_iter().unzip()
}
