//! Recording a step into a command encoder: the workgroup grid of each kernel domain, the
//! kernels of one stage (the stage table's clears, then one compute pass), an evaluation, a whole
//! step, and one submission of recorded work.

// The solver's own imports (state, buffers, stage table, errors).
use super::*;
use crate::fields::Field;

impl<T: Real> GpuSolver<T> {
    /// The list chunks of the slot arrays (`gpu::list_chunks`: each list kernel is dispatched
    /// once per chunk; 1 while they fit one binding).
    pub fn list_chunks(&self) -> usize {
        self.vb.chunks.len()
    }

    /// The workgroup grid of a kernel over `d`: the groups a 1-D dispatch would need, spread
    /// over x and y (x and z for the block layout, whose y holds the 4 list blocks) when x alone
    /// would pass [`Self::max_groups_per_dim`]; the kernels rebuild the linear index with
    /// `linear_id` / `linear_group_xz` (kernels-variants/common/dispatch.wgsl).
    pub fn groups(&self, d: Domain) -> [u32; 3] {
        self.groups_over(d, self.n)
    }

    /// [`Self::groups`] with the particle domains (`All`, `Block`, `Subgroups`) over `n`
    /// particles (a list chunk's, `gpu::list_chunks`).
    fn groups_over(&self, d: Domain, n: usize) -> [u32; 3] {
        let threads = match d {
            Domain::All => n,
            Domain::Fluid => self.n_fluid,
            Domain::Wall => self.n - self.n_fluid,
            Domain::One | Domain::Group => return [1, 1, 1],
            Domain::ContactAngles => return [u32::from(self.model.young_unbalanced), 1, 1],
            Domain::BlockSums => {
                let many = crate::gpu::plan::scan_blocks(self.grid.cells()) > crate::gpu::plan::SCAN_BLOCK;
                return [u32::from(many), 1, 1];
            }
            Domain::Cells => self.grid.cells(),
            Domain::ScanBlocks => {
                let (gx, gy) = spread(crate::gpu::plan::scan_blocks(self.grid.cells()), self.max_groups_per_dim);
                return [gx, gy, 1];
            }
            Domain::Subgroups => {
                // G lanes per particle at the largest subgroup: a smaller one puts more particles
                // in a workgroup, so this grid covers N at any size the adapter picks.
                let lanes = self.pipes.lanes.min(self.ctx.adapter_info.subgroup_max_size.clamp(1, 64));
                let per_group = 64 / lanes.max(1) as usize;
                let (gx, gy) = spread(n.div_ceil(per_group), self.max_groups_per_dim);
                return [gx, gy, 1];
            }
            Domain::Block => {
                let (gx, gz) = spread(n.div_ceil(32), self.max_groups_per_dim);
                return [gx, (vbufs::NBR_SLOTS / 16) as u32, gz];
            }
        };
        let (gx, gy) = spread(threads.div_ceil(self.spec.workgroup.threads() as usize), self.max_groups_per_dim);
        [gx, gy, 1]
    }

    /// Records the kernels of one stage into `enc` (the unfused path: `verify --per-stage` and
    /// the debug mode of [`Self::set_fused`]).
    pub(in crate::gpu) fn record(&self, enc: &mut wgpu::CommandEncoder, stage: Stage) {
        if let Some(kernels) = self.pipes.stages.get(&stage) {
            self.record_pass(enc, &[stage], kernels);
        }
    }

    /// Records one pass of `stages` (a stage, or a neighbour pass with its fused epilogues,
    /// `stage::passes`) running `kernels`: the table's clears of every stage (when there are
    /// kernels), the block accumulator clear (block kernels), then one compute pass; the reorder
    /// kernels only when the host's cadence says they are due; the search's own cell count (and
    /// its clear) only when no `cell_count` stage has counted the particles where they are, its
    /// scan only when no `cell_scan` stage has scanned those counts, and the merge of the
    /// previous lists instead of the scatter and sort when the counts are fresh and a search has
    /// built the lists of the particles as numbered ([`Self::search_skips`]).
    fn record_pass(&self, enc: &mut wgpu::CommandEncoder, stages: &[Stage], kernels: &Compiled) {
        if kernels.is_empty() {
            return;
        }
        let search = stages[0] == Stage::NeighbourSearch;
        let renumber = search && self.reorder_due();
        let counted = search && self.counts_fresh.replace(false);
        let skips = self.search_skips(search, counted, renumber);
        if stages.contains(&Stage::CellCount) {
            self.counts_fresh.set(true);
        }
        if stages.contains(&Stage::CellScan) {
            self.starts_fresh.set(true);
        }
        if search && self.spec.sorts_cells() {
            self.lists_kept.set(true);
        }
        for clear in stages.iter().flat_map(|s| s.def().clears) {
            if counted && *clear == Clear::CellCounts {
                continue;
            }
            let (buffer, offset, size) = match clear {
                Clear::CellCounts => (&self.b.cell_count.buffer, 0, None),
                Clear::ContactsFound => (&self.b.ctl.buffer, 4 * ctl::CONTACTS_FOUND as u64, Some(4)),
                Clear::Maxima => (&self.b.ctl.buffer, 4 * ctl::VMAX as u64, Some(8)),
            };
            enc.clear_buffer(buffer, offset, size);
        }
        if kernels.iter().any(|(kd, _)| kd.domain == Domain::Block) {
            for b in self.vb.accumulators() {
                enc.clear_buffer(b, 0, None);
            }
        }
        let label = crate::stage::pass_label(stages);
        let dispatches = kernels.iter().any(|(kd, _)| self.groups(kd.domain)[0] > 0);
        let ts = if dispatches { self.ts.writes(&label) } else { None };
        // A renumbering ends the pass after the reorder kernels: the twins swap roles before
        // the rest of the search (the tracking build, the lists) reads the particles.
        let (head, tail) = match kernels.iter().rposition(|(kd, _)| kd.file == reorder::FILE) {
            Some(last) if renumber => kernels.split_at(last + 1),
            _ => (&kernels[..], &kernels[..0]),
        };
        let split = |begin: bool| {
            ts.as_ref().map(|w| wgpu::ComputePassTimestampWrites {
                query_set: w.query_set,
                beginning_of_pass_write_index: if begin { w.beginning_of_pass_write_index } else { None },
                end_of_pass_write_index: if begin { None } else { w.end_of_pass_write_index },
            })
        };
        let (first, last) = if tail.is_empty() { (ts.clone(), None) } else { (split(true), split(false)) };
        self.record_kernels(enc, &label, first, head, &skips, renumber);
        if renumber {
            self.record_renumbered(enc);
        }
        if !tail.is_empty() {
            self.record_kernels(enc, &label, last, tail, &skips, renumber);
        }
    }

    /// One compute pass over `kernels` (the bind groups, then each kernel's dispatch): the
    /// reorder kernels only with a `renumber`ing, none of `skips`.
    fn record_kernels(
        &self,
        enc: &mut wgpu::CommandEncoder,
        label: &str,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
        kernels: &[(crate::gpu::stages::KernelDef, wgpu::ComputePipeline)],
        skips: &[&str],
        renumber: bool,
    ) {
        let desc = wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes };
        let mut pass = enc.begin_compute_pass(&desc);
        pass.set_bind_group(0, &self.bgs[usize::from(self.b.roles_swapped())], &[]);
        pass.set_bind_group(1, &self.vbgs[0], &[]);
        if renumber {
            pass.set_bind_group(2, &self.rbg, &[]);
        }
        let chunked = self.vbgs.len() > 1;
        for (kd, p) in kernels {
            if (kd.file == reorder::FILE && !renumber) || skips.contains(&kd.entry) {
                continue;
            }
            if chunked && crate::gpu::list_chunks::runs_per_chunk(kd) {
                // Once per list chunk, each with its bind group and its particles' grid.
                pass.set_pipeline(p);
                for (g, &(_, len)) in self.vbgs.iter().zip(&self.vb.chunks) {
                    let [gx, gy, gz] = self.groups_over(kd.domain, len);
                    pass.set_bind_group(1, g, &[]);
                    pass.dispatch_workgroups(gx, gy, gz);
                    self.ctx.traffic.dispatch(1);
                }
                pass.set_bind_group(1, &self.vbgs[0], &[]);
                continue;
            }
            let [gx, gy, gz] = self.groups(kd.domain);
            if gx > 0 {
                pass.set_pipeline(p);
                pass.dispatch_workgroups(gx, gy, gz);
                self.ctx.traffic.dispatch(1);
            }
        }
    }

    /// After a renumbering's kernels (search/reorder.wgsl wrote every particle at its slot into
    /// the twins of the persistent arrays, `to_scratch`): the twins swap roles (the next
    /// passes bind the other group 0), phase, the fluids' colour (their phase) and `orig_of`
    /// are copied back from `counts`, and the
    /// arrays now in the roles of ∇C and Π are cleared where no stage of the evaluation
    /// rewrites them (they are read as zero there).
    fn record_renumbered(&self, enc: &mut wgpu::CommandEncoder) {
        self.b.swap_twins();
        let (b, n, counts) = (&self.b, self.n as u64, &self.vb.counts.buffer);
        let copies: [(u64, &wgpu::Buffer, u64, u64); 3] = [
            (0, &b.phase.buffer, 0, n),
            (0, &b.colour.buffer, 0, self.n_fluid as u64),
            (n, &self.rb.buf.buffer, self.rb.orig_at() as u64, n),
        ];
        for (at, dst, to, words) in copies {
            if words > 0 {
                enc.copy_buffer_to_buffer(counts, 4 * at, dst, 4 * to, 4 * words);
                self.ctx.traffic.copy();
            }
        }
        // Zero, unless an evaluation stage writes every particle's value (`stage::TABLE`).
        let stages = || self.passes.iter().flat_map(|(pass, _)| pass);
        let rewritten = |f: Field| stages().any(|s| s.pure_outputs().any(|w| w == f));
        for (g, f) in [(b.grad0(), Field::Grad), (b.grad1(), Field::Grad), (b.pi(), Field::Pi)] {
            if !rewritten(f) {
                enc.clear_buffer(&g.buffer, 0, None);
            }
        }
    }

    /// The search kernels a search pass skips (none for another pass, `counted`: a cell count
    /// stage counted the particles where they are): the count when counted; the scan when a
    /// `cell_scan` stage scanned those counts; the merge of the previous lists unless counted
    /// and the lists kept ([`GpuSolver::lists_kept`]), else the scatter and sort; with a
    /// renumbering, the list kernel its reorder kernel replaces (`gpu::stages::REORDER`).
    fn search_skips(&self, search: bool, counted: bool, renumber: bool) -> Vec<&'static str> {
        let mut skip = Vec::new();
        if !search {
            return skip;
        }
        let scanned = self.starts_fresh.replace(false) && counted;
        if counted {
            skip.push(Stage::CellCount.name());
        }
        if scanned {
            skip.extend(crate::gpu::stages::CELL_SCAN.iter().map(|kd| kd.entry));
        }
        let merge = counted && self.lists_kept.get();
        if merge {
            skip.extend(["cell_scatter", "cell_sort", "reorder_sort"]);
        } else {
            skip.extend([crate::gpu::stages::CELL_MERGE, "reorder_merge"]);
        }
        if renumber {
            skip.push(if merge { crate::gpu::stages::CELL_MERGE } else { "cell_sort" });
        }
        skip
    }

    /// Records one force evaluation: every active stage in the CPU order (fused: the table's
    /// passes, each neighbour pass with its epilogues; unfused while stage timing is on, so
    /// that every stage has its own time), then ṽ.
    pub(super) fn record_evaluate(&self, enc: &mut wgpu::CommandEncoder) {
        self.record_passes(enc, &self.passes);
        if !self.model.stages.xsph {
            let bytes = (self.n_fluid * size_of::<V2<T>>()) as u64;
            if bytes > 0 {
                enc.copy_buffer_to_buffer(&self.b.vel().buffer, 0, &self.b.vt.buffer, 0, bytes);
                self.ctx.traffic.copy();
            }
        }
    }

    /// Records `passes` (fused: each pass as one, its epilogues in its kernels; unfused while
    /// stage timing is on, so that every stage has its own time: stage by stage).
    fn record_passes(&self, enc: &mut wgpu::CommandEncoder, passes: &[(Vec<Stage>, Option<Arc<Compiled>>)]) {
        let fused = self.fused && !self.ts.stages_on();
        for (stages, kernels) in passes {
            match kernels {
                Some(kernels) if fused => self.record_pass(enc, stages, kernels),
                _ => stages.iter().for_each(|s| self.record(enc, *s)),
            }
        }
    }

    /// Records `f` into one command encoder and submits it; returns the submission.
    pub(in crate::gpu) fn submit(
        &self,
        f: impl FnOnce(&mut wgpu::CommandEncoder),
    ) -> Result<wgpu::SubmissionIndex, GpuError> {
        self.ts.before_submit(&self.ctx)?;
        self.ctx.scoped(|d| {
            let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sphlab.step") });
            f(&mut enc);
            let index = self.ctx.queue.submit([enc.finish()]);
            self.ctx.traffic.submit();
            index
        })
    }

    /// One force evaluation at the current state (no integration), waited for; a neighbour
    /// overflow is an error (`GpuError::Solver(NeighbourOverflow)`).
    pub fn evaluate_once(&mut self) -> Result<(), GpuError> {
        self.submit(|enc| self.record_evaluate(enc))?;
        self.ctx.wait_idle()?;
        self.vb.overflow(&self.ctx, self.step).map_err(|e| self.to_original(e))?;
        Ok(())
    }

    /// `e` with the overflowing particle's device index (`VBufs::overflow`) mapped through the
    /// renumbering to its original id.
    pub(in crate::gpu) fn to_original(&self, mut e: SolverError) -> SolverError {
        if let SolverError::NeighbourOverflow { particle: Some(p), .. } = &mut e {
            if let Some(o) = self.device_order().ok().and_then(|order| order.get(*p).copied()) {
                *p = o as usize;
            }
        }
        e
    }

    /// Records one whole step: (first evaluation,) with an adaptive dt `reduce_max` and
    /// `dt_compute`, the integrator's opening stage (with the cell count,
    /// `Stage::opening_passes`), the evaluation, its closing stage with `check` and the cell
    /// count and scan (`Stage::closing_passes`: fused, the check, the clock tick, the count and
    /// the scan run in the closing kernel; unfused, `clock_tick` then `check`, then `cell_count`,
    /// then `cell_scan`, each its own pass).
    /// Reads nothing from the host: dt and the step number come from the device clock.
    pub(super) fn record_step(&self, enc: &mut wgpu::CommandEncoder, first_eval: bool) {
        if first_eval {
            self.record_evaluate(enc);
        }
        if self.model.dt_fixed <= 0.0 {
            self.record(enc, Stage::ReduceMax);
        }
        self.record_passes(enc, &self.opening);
        self.record_evaluate(enc);
        self.record_passes(enc, &self.closing);
    }
}
