//! Reading device memory on the host, written once: a `MAP_READ` staging buffer filled by a copy
//! in a submission, mapped, waited for (a synchronisation point), read and unmapped. Every
//! readback goes through here — typed buffers ([`super::GpuVec::read_range`], which the
//! residency prefixes use), the bandwidth probe's and the stage timers' ticks, the control
//! words — so each is counted once, as one readback, in the context's [`super::counters`].

use super::{GpuContext, GpuError};
use bytemuck::Pod;

/// A `MAP_READ | COPY_DST` buffer of `bytes` (rounded up to the copy alignment, at least 4).
pub fn staging_buffer(ctx: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Maps the first `bytes` of `staging` (the submission that fills it must already be queued),
/// waits for the device, and returns them as elements of `P`; the buffer is unmapped again.
pub fn map_read<P: Pod>(ctx: &GpuContext, staging: &wgpu::Buffer, bytes: u64) -> Result<Vec<P>, GpuError> {
    if bytes == 0 {
        return Ok(Vec::new());
    }
    let mapped = bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
    let (tx, rx) = std::sync::mpsc::channel();
    staging.slice(..mapped).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.wait_idle()?;
    ctx.traffic.readback();
    rx.recv()
        .map_err(|e| GpuError::Readback(format!("map callback dropped: {e}")))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let out = {
        let view = staging.slice(..mapped).get_mapped_range().map_err(|e| GpuError::Readback(e.to_string()))?;
        bytemuck::pod_collect_to_vec(&view[..bytes as usize])
    };
    staging.unmap();
    Ok(out)
}

/// Bytes `offset..offset + bytes` of `src` (a `COPY_SRC` buffer; `offset` a multiple of 4) as
/// elements of `P`, through a fresh staging buffer: one submission, one readback.
pub fn read_range<P: Pod>(ctx: &GpuContext, src: &wgpu::Buffer, offset: u64, bytes: u64) -> Result<Vec<P>, GpuError> {
    if bytes == 0 {
        return Ok(Vec::new());
    }
    let size = bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
    let staging = staging_buffer(ctx, "sphlab.readback", size);
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(src, offset, &staging, 0, size);
    ctx.queue.submit([enc.finish()]);
    ctx.traffic.submit();
    map_read(ctx, &staging, bytes)
}
