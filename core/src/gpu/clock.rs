//! The device clock and the one readback per batch of steps.
//!
//! **Clock.** The step counter is `ctl[STEP]` (u32), dt and the time are entries of `vparams`
//! (`vparam::DT`, `vparam::T` plus its rounding error `vparam::T_LO`, in the storage precision).
//! The host writes them only at construction and at a restart ([`write_clock`]); during steps the
//! kernels advance them: `dt_compute` (adaptive dt, by the last workgroup of `reduce_max`) and
//! `clock_tick` (end of each step, by the last workgroup of the fused closing stage) (`kernels-variants/thread/integrate.wgsl`). So k steps are recorded into one
//! command encoder and one submission with no host write in between; the host mirrors step and
//! t by counting (fixed dt) or takes them from the readback (adaptive dt).
//!
//! **Readback.** At the end of a batch the control words (`ctl`, `vctl`) and the clock are
//! copied into one persistent staging buffer inside the same submission ([`ControlReader::record`])
//! and mapped once ([`ControlReader::read`]): one submit and one readback per batch.

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

/// The persistent staging buffer of the control readback.
pub struct ControlReader {
    staging: wgpu::Buffer,
    real: u64,
}

impl ControlReader {
    /// A staging buffer for a solver in precision `T`.
    pub fn new<T: Real>(ctx: &GpuContext) -> Self {
        let real = size_of::<T>() as u64;
        let staging = super::staging::staging_buffer(ctx, "sphlab.control.staging", CLOCK_AT + CLOCK_LEN as u64 * real);
        Self { staging, real }
    }

    /// Records the copies of `ctl`, `vctl` and the clock into the staging buffer (end of a batch).
    pub fn record<T: Real>(&self, enc: &mut wgpu::CommandEncoder, b: &Bufs<T>, vb: &VBufs<T>) {
        enc.copy_buffer_to_buffer(&b.ctl.buffer, 0, &self.staging, 0, CTL_BYTES);
        enc.copy_buffer_to_buffer(&vb.vctl.buffer, 0, &self.staging, CTL_BYTES, VCTL_BYTES);
        let clock = vparam::DT as u64 * self.real;
        enc.copy_buffer_to_buffer(&vb.vparams.buffer, clock, &self.staging, CLOCK_AT, CLOCK_LEN as u64 * self.real);
    }

    /// Maps the staging buffer (after the submission that recorded the copies) and decodes it.
    pub fn read<T: Real>(&self, ctx: &GpuContext) -> Result<Control, GpuError> {
        let bytes: Vec<u8> = super::staging::map_read(ctx, &self.staging, CLOCK_AT + CLOCK_LEN as u64 * self.real)?;
        let words =
            |from: u64, to: u64| -> Vec<u32> { bytemuck::pod_collect_to_vec(&bytes[from as usize..to as usize]) };
        let clock: Vec<T> = bytemuck::pod_collect_to_vec(&bytes[CLOCK_AT as usize..]);
        Ok(Control {
            ctl: words(0, CTL_BYTES),
            vctl: words(CTL_BYTES, CLOCK_AT),
            dt: clock[0].f64(),
            t: clock[1].f64() + clock[2].f64(),
        })
    }
}

/// Sets the clock to `dt` and time `t` (construction and restart only; never between steps).
pub fn write_clock<T: Real>(ctx: &GpuContext, vb: &VBufs<T>, dt: f64, t: f64) {
    let v = [T::c(dt), T::c(t), T::zero()];
    let at = (vparam::DT * size_of::<T>()) as u64;
    ctx.queue.write_buffer(&vb.vparams.buffer, at, bytemuck::cast_slice(&v));
    ctx.traffic.write();
}
