//! Stepping the GPU solver: batches of steps in one submission, the control words read back
//! after each batch (blow-up, neighbour overflow, the device clock) — in a long `advance`, one
//! batch late, with up to `clock::BATCHES_IN_FLIGHT` batches submitted — the run driver's
//! [`Backend`] interface, and stage timing by timestamps.

// The solver's own imports (state, buffers, stage table, errors).
use super::*;

impl<T: Real> GpuSolver<T> {
    /// Takes the control words read back after a batch: the host clock follows the device's
    /// (adaptive dt, or a halted device), and the first failure becomes the error. `latest`:
    /// no batch was submitted after this one (else its clock is not the newest and only a
    /// failure moves the host's).
    fn take_control(&mut self, c: Control, latest: bool) -> Result<(), SolverError> {
        let (bad, over) = (c.ctl[ctl::BAD_STEP], c.ctl[ctl::OVER_STEP]);
        let failed = bad != u32::MAX || over != u32::MAX;
        if (self.model.dt_fixed <= 0.0 && latest) || failed {
            self.step = c.step();
            self.t = c.t;
            if c.dt > 0.0 {
                self.dt = c.dt;
            }
        }
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        if over != u32::MAX && over <= bad {
            self.vb.overflow_in(&self.ctx, c.vctl, over as u64).map_err(|e| self.to_original(e))?;
        }
        if c.ctl[ctl::SCAN_MISS] != u32::MAX {
            return Err(SolverError::Gpu(format!(
                "step {}: the cell counts scanned did not sum to the {} fluid particles; the neighbour lists of that \
                 search are wrong, so the run is stopped (a fused scan that read the counts before every workgroup's \
                 were visible: run the unfused engine to check)",
                c.ctl[ctl::SCAN_MISS],
                self.n_fluid
            )));
        }
        if c.ctl[ctl::CONTACTS_MAX] as usize > MAX_CONTACTS {
            let count = c.ctl[ctl::CONTACTS_MAX] as usize;
            return Err(SolverError::ContactOverflow { step: self.step, count, cap: MAX_CONTACTS });
        }
        if bad != u32::MAX {
            let (device, kind) = ((c.ctl[ctl::BAD] / 2) as usize, c.ctl[ctl::BAD] % 2);
            let particle = self.device_order().map_err(gpu)?.get(device).map_or(device, |&o| o as usize);
            let (pos, vel) = self.read_state().map_err(gpu)?;
            let (p, v) = (pos[particle], vel[particle]);
            let what = if kind == 0 {
                format!(
                    "has a non-finite state: x = ({:.4e}, {:.4e}), v = ({:.4e}, {:.4e})",
                    p.x.f64(),
                    p.y.f64(),
                    v.x.f64(),
                    v.y.f64()
                )
            } else {
                format!("left the domain: x = ({:.4e}, {:.4e})", p.x.f64(), p.y.f64())
            };
            return Err(SolverError::BlowUp { step: bad as u64, t: self.t, particle, what });
        }
        Ok(())
    }

    /// Reads the control words and the clock back (one submit, one readback) and takes them.
    fn check_flags(&mut self) -> Result<(), SolverError> {
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        self.submit(|enc| self.control.record(enc, &self.b, &self.vb, 0)).map_err(gpu)?;
        let c = self.control.read::<T>(&self.ctx).map_err(gpu)?;
        self.take_control(c, true)
    }

    /// `k` steps in ONE submission; the control words and the clock are copied at its end and,
    /// when `read`, mapped (the one readback) and checked.
    fn run_steps(&mut self, k: u64, read: bool) -> Result<(), SolverError> {
        if let Some(e) = self.pending.take() {
            return Err(e);
        }
        if k == 0 {
            return Ok(());
        }
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        let index = self.send_steps(k, read.then_some(0))?;
        if read {
            let c = self.control.take::<T>(&self.ctx, self.control.send(0, index)).map_err(gpu)?;
            self.take_control(c, true)?;
        } else {
            let _ = self.ctx.device.poll(wgpu::PollType::Poll);
        }
        Ok(())
    }

    /// `k` steps in batches of at most `most`, up to [`BATCHES_IN_FLIGHT`] submitted before
    /// the oldest one's control words are read: the device runs batch i + 1 while the host
    /// reads batch i and encodes batch i + 2. A failure found in batch i is reported as at
    /// once (the device halts at the failing step, so the batches after it do nothing); the
    /// others are drained first.
    fn run_batches(&mut self, k: u64, most: u64) -> Result<(), SolverError> {
        if let Some(e) = self.pending.take() {
            return Err(e);
        }
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        let mut flight = std::collections::VecDeque::new();
        let (mut left, mut slot) = (k, 0);
        let mut failure = None;
        while (left > 0 || !flight.is_empty()) && failure.is_none() {
            if left > 0 && flight.len() < BATCHES_IN_FLIGHT {
                let n = left.min(most);
                let index = self.send_steps(n, Some(slot))?;
                flight.push_back(self.control.send(slot, index));
                (left, slot) = (left - n, slot + 1);
                continue;
            }
            let oldest = flight.pop_front().expect("a batch in flight");
            let c = self.control.take::<T>(&self.ctx, oldest).map_err(gpu)?;
            let latest = left == 0 && flight.is_empty();
            failure = self.take_control(c, latest).err();
        }
        for f in flight {
            self.control.take::<T>(&self.ctx, f).map_err(gpu)?;
        }
        failure.map_or(Ok(()), Err)
    }

    /// Records and submits `k` steps (the batch's timestamp pair around them when timing is
    /// on; the control copies into staging slot `slot` when given) and advances the host's
    /// step count (and, with a fixed dt, its clock).
    fn send_steps(&mut self, k: u64, slot: Option<usize>) -> Result<wgpu::SubmissionIndex, SolverError> {
        let gpu = |e: GpuError| SolverError::Gpu(e.to_string());
        let midpoint = self.integrator == Integrator::Midpoint;
        let have_acc = self.have_acc;
        let index = self
            .submit(|enc| {
                // The batch's timestamp pair (timing on): an empty pass before the steps, one after.
                let [open, close] = self.ts.batch().map_or([None, None], |[a, b]| [Some(a), Some(b)]);
                let bracket = |enc: &mut wgpu::CommandEncoder, w| {
                    let label = Some("sphlab.batch");
                    drop(enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label, timestamp_writes: Some(w) }));
                };
                if let Some(w) = open {
                    bracket(enc, w);
                }
                for s in 0..k {
                    self.record_step(enc, midpoint || (s == 0 && !have_acc));
                }
                if let Some(w) = close {
                    bracket(enc, w);
                }
                if let Some(slot) = slot {
                    self.control.record(enc, &self.b, &self.vb, slot);
                }
            })
            .map_err(gpu)?;
        self.have_acc = true;
        self.steps_total += k;
        if self.model.dt_fixed > 0.0 {
            for _ in 0..k {
                self.t += self.model.dt_fixed;
            }
            self.dt = self.model.dt_fixed;
        }
        self.step += k;
        Ok(index)
    }

    /// What was done to the solver's context since the solver was built (`gpu::counters`): the
    /// solver's own work while [`Self::engine_counters_exclusive`].
    pub fn engine_counters(&self) -> EngineCounters {
        EngineCounters { steps: self.steps_total, ..self.ctx.traffic.totals().since(&self.traffic0) }
    }

    /// True while this has been the only solver alive on its context since it was built, so
    /// that [`Self::engine_counters`] counts its work alone.
    pub fn engine_counters_exclusive(&self) -> bool {
        self.claim.exclusive()
    }
}

impl<T: Real> Backend for GpuSolver<T> {
    fn name(&self) -> String {
        self.spec.to_string()
    }
    fn precision(&self) -> &'static str {
        T::NAME
    }
    fn step(&mut self) -> Result<(), SolverError> {
        let adaptive = self.model.dt_fixed <= 0.0;
        let read = adaptive || (self.check_every > 0 && (self.step + 1).is_multiple_of(self.check_every));
        self.run_steps(1, read)
    }
    fn set_steps_per_submit(&mut self, k: u64) {
        self.max_steps_per_submit = k;
    }
    fn advance(&mut self, k: u64) -> Result<(), SolverError> {
        if k == 0 {
            return self.run_steps(0, true);
        }
        let most = if self.max_steps_per_submit == 0 { k } else { self.max_steps_per_submit };
        if !self.batches_in_flight || most >= k {
            let mut left = k;
            while left > 0 {
                let n = left.min(most);
                self.run_steps(n, true)?;
                left -= n;
            }
            return Ok(());
        }
        self.run_batches(k, most)
    }
    fn engine_counters(&self) -> Option<EngineCounters> {
        // Another solver on the context since this one was built: its work would be counted too.
        self.engine_counters_exclusive().then(|| GpuSolver::engine_counters(self))
    }
    fn time(&self) -> f64 {
        self.t
    }
    fn steps(&self) -> u64 {
        self.step
    }
    fn frame(&mut self) -> Frame {
        if self.pending.is_none() {
            self.pending = self.check_flags().err();
        }
        let (pos, vel) = self.read_state().unwrap_or_default();
        let f = self.read_fields().unwrap_or_else(|_| Fields::new(0));
        Frame::from_fields(self.step, self.t, self.dt, self.n_fluid, &pos, &vel, &self.phase, &f)
    }
    fn restart_with_velocities(&mut self, vel: &[[f64; 2]]) {
        if let Ok((_, mut v)) = self.read_state() {
            for (i, x) in vel.iter().enumerate().take(self.n_fluid) {
                v[i] = v2(x);
            }
            if let Ok(orig_of) = self.device_order() {
                let _ = self.b.vel().upload(&self.ctx, &reorder::to_device(&v, 1, &orig_of));
            }
        }
        self.t = 0.0;
        self.step = 0;
        self.have_acc = false;
        let _ = self.reset_ctl();
    }
    fn sync(&mut self) {
        let _ = self.ctx.wait_idle();
    }
    fn take_error(&mut self) -> Option<SolverError> {
        if self.pending.is_none() {
            self.pending = self.check_flags().err();
        }
        self.pending.take()
    }
    fn enable_device_time(&mut self, what: DeviceTiming) -> bool {
        self.enable_timestamps(what)
    }
    fn device_time(&mut self) -> Option<DeviceTimes> {
        self.ts.device_times(&self.ctx, self.step)
    }
}

impl<T: Real> GpuSolver<T> {
    /// Sets what is timed ([`DeviceTiming`]); returns whether timing is on (false for `Off` or
    /// when the device lacks `TIMESTAMP_QUERY`: then nothing is timed and
    /// [`Self::take_stage_times`] returns `None`). Switching on (again) starts from empty sums.
    pub fn enable_timestamps(&mut self, what: DeviceTiming) -> bool {
        self.ts = Timestamps::new(&self.ctx, self.step, what);
        self.ts.is_on()
    }

    /// True while timing (batch or stage) is on.
    pub fn timestamps_enabled(&self) -> bool {
        self.ts.is_on()
    }

    /// Device nanoseconds per stage name (`neighbour_search`, …, `midpoint_predict`, `check`),
    /// summed over every pass recorded since the last call, in order of first appearance;
    /// `None` when timing is off or unavailable (never estimated).
    pub fn take_stage_times(&mut self) -> Result<Option<Vec<(String, f64)>>, GpuError> {
        self.ts.stage_times(&self.ctx, self.step)
    }
}
