//! The device clock and the one readback per batch of steps.
//!
//! **Clock.** The step counter is `ctl[STEP]` (u32), dt and the time are entries of `vparams`
//! (`vparam::DT`, `vparam::T` plus its rounding error `vparam::T_LO`, in the storage precision).
//! The host writes them only at construction and at a restart ([`write_clock`]); during steps the
//! kernels advance them: the opening integrator stage (adaptive dt, from `reduce_max`'s maxima) and
//! `clock_tick` (end of each step, by the last workgroup of the fused closing stage) (`kernels-variants/thread/integrate.wgsl`). So k steps are recorded into one
//! command encoder and one submission with no host write in between; the host mirrors step and
//! t by counting (fixed dt) or takes them from the readback (adaptive dt).
//!
//! **Readback.** At the end of a batch the control words (`ctl`, `vctl`) and the clock are
//! copied into a persistent staging buffer inside the same submission ([`ControlReader::record`])
//! and mapped once ([`ControlReader::read`]): one submit and one readback per batch. The reader
//! keeps a ring of [`BATCHES_IN_FLIGHT`] such buffers, so that a long `advance` can submit the
//! next batches before the oldest one's words are read ([`ControlReader::send`],
//! [`ControlReader::take`]): the device is never idle while the host encodes.

use super::solver_buffers::{ctl, Bufs};
use super::variant_buffers::{vctl, vparam, VBufs};
use super::{GpuContext, GpuError};
use crate::real::Real;

/// Bytes of the `ctl` words, of the `vctl` words, and where the clock starts in the staging buffer.
const CTL_BYTES: u64 = 4 * ctl::LEN as u64;
const VCTL_BYTES: u64 = 4 * vctl::LEN as u64;
const CLOCK_AT: u64 = CTL_BYTES + VCTL_BYTES;
/// Clock entries copied: dt, t, t_lo.
const CLOCK_LEN: usize = 3;

/// The control words and the clock at the end of a batch.
#[derive(Clone, Debug)]
pub struct Control {
    /// `ctl` words (`solver_buffers::ctl`).
    pub ctl: Vec<u32>,
    /// `vctl` words (`variant_buffers::vctl`).
    pub vctl: Vec<u32>,
    /// dt of the last step.
    pub dt: f64,
    /// Time after the last step (t + t_lo).
    pub t: f64,
}

impl Control {
    /// Steps completed on the device.
    pub fn step(&self) -> u64 {
        self.ctl[ctl::STEP] as u64
    }
}

/// Batches a long `advance` keeps submitted before it reads the oldest one's control words.
pub const BATCHES_IN_FLIGHT: usize = 3;

/// The ring of persistent staging buffers of the control readback.
pub struct ControlReader {
    staging: Vec<wgpu::Buffer>,
    real: u64,
}

/// A batch whose control words are on their way back: its staging slot, the mapping started
/// right after its submission, and that submission.
pub struct InFlight {
    slot: usize,
    mapping: super::staging::Mapping,
    index: wgpu::SubmissionIndex,
}

impl ControlReader {
    /// [`BATCHES_IN_FLIGHT`] staging buffers for a solver in precision `T`.
    pub fn new<T: Real>(ctx: &GpuContext) -> Self {
        let real = size_of::<T>() as u64;
        let bytes = CLOCK_AT + CLOCK_LEN as u64 * real;
        let staging = (0..BATCHES_IN_FLIGHT)
            .map(|_| super::staging::staging_buffer(ctx, "sphlab.control.staging", bytes))
            .collect();
        Self { staging, real }
    }

    fn bytes(&self) -> u64 {
        CLOCK_AT + CLOCK_LEN as u64 * self.real
    }

    /// Records the copies of `ctl`, `vctl` and the clock into staging slot `slot` (end of a
    /// batch; slot 0 for a batch read at once).
    pub fn record<T: Real>(&self, enc: &mut wgpu::CommandEncoder, b: &Bufs<T>, vb: &VBufs<T>, slot: usize) {
        let staging = &self.staging[slot % self.staging.len()];
        enc.copy_buffer_to_buffer(&b.ctl.buffer, 0, staging, 0, CTL_BYTES);
        enc.copy_buffer_to_buffer(&vb.vctl.buffer, 0, staging, CTL_BYTES, VCTL_BYTES);
        let clock = vparam::DT as u64 * self.real;
        enc.copy_buffer_to_buffer(&vb.vparams.buffer, clock, staging, CLOCK_AT, CLOCK_LEN as u64 * self.real);
    }

    /// Starts mapping slot `slot` right after `index`, the submission that recorded its copies.
    pub fn send(&self, slot: usize, index: wgpu::SubmissionIndex) -> InFlight {
        let slot = slot % self.staging.len();
        InFlight { slot, mapping: super::staging::map_start(&self.staging[slot], self.bytes()), index }
    }

    /// Waits for an in-flight batch's submission alone and decodes its words.
    pub fn take<T: Real>(&self, ctx: &GpuContext, f: InFlight) -> Result<Control, GpuError> {
        let staging = &self.staging[f.slot];
        let bytes: Vec<u8> = super::staging::map_finish(ctx, staging, f.mapping, Some(f.index))?;
        Ok(self.decode::<T>(&bytes))
    }

    /// Maps slot 0 (after the submission that recorded the copies) and decodes it.
    pub fn read<T: Real>(&self, ctx: &GpuContext) -> Result<Control, GpuError> {
        let bytes: Vec<u8> = super::staging::map_read(ctx, &self.staging[0], self.bytes())?;
        Ok(self.decode::<T>(&bytes))
    }

    fn decode<T: Real>(&self, bytes: &[u8]) -> Control {
        let words =
            |from: u64, to: u64| -> Vec<u32> { bytemuck::pod_collect_to_vec(&bytes[from as usize..to as usize]) };
        let clock: Vec<T> = bytemuck::pod_collect_to_vec(&bytes[CLOCK_AT as usize..]);
        Control {
            ctl: words(0, CTL_BYTES),
            vctl: words(CTL_BYTES, CLOCK_AT),
            dt: clock[0].f64(),
            t: clock[1].f64() + clock[2].f64(),
        }
    }
}

/// Sets the clock to `dt` and time `t` (construction and restart only; never between steps).
pub fn write_clock<T: Real>(ctx: &GpuContext, vb: &VBufs<T>, dt: f64, t: f64) {
    let v = [T::c(dt), T::c(t), T::zero()];
    let at = (vparam::DT * size_of::<T>()) as u64;
    ctx.queue.write_buffer(&vb.vparams.buffer, at, bytemuck::cast_slice(&v));
    ctx.traffic.write();
}
