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

/// A mapping under way: `map_async` was called on a staging buffer whose filling submission is
/// queued; [`map_finish`] waits for that submission alone and reads the bytes.
pub struct Mapping {
    rx: std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
    bytes: u64,
}

/// Starts mapping the first `bytes` of `staging` (the submission that fills it must already be
/// queued); nothing waits here, so more work can be submitted before [`map_finish`].
pub fn map_start(staging: &wgpu::Buffer, bytes: u64) -> Mapping {
    let (tx, rx) = std::sync::mpsc::channel();
    if bytes > 0 {
        let mapped = bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        staging.slice(..mapped).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
    }
    Mapping { rx, bytes }
}

/// Waits until `until` is done (`None`: everything submitted), reads the mapping's bytes as
/// elements of `P` and unmaps `staging` again: one readback.
pub fn map_finish<P: Pod>(
    ctx: &GpuContext,
    staging: &wgpu::Buffer,
    m: Mapping,
    until: Option<wgpu::SubmissionIndex>,
) -> Result<Vec<P>, GpuError> {
    if m.bytes == 0 {
        return Ok(Vec::new());
    }
    let mapped = m.bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
    ctx.device
        .poll(wgpu::PollType::Wait { submission_index: until, timeout: None })
        .map_err(|e| GpuError::Readback(format!("poll: {e}")))?;
    ctx.traffic.readback();
    m.rx.recv()
        .map_err(|e| GpuError::Readback(format!("map callback dropped: {e}")))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let out = {
        let view = staging.slice(..mapped).get_mapped_range().map_err(|e| GpuError::Readback(e.to_string()))?;
        bytemuck::pod_collect_to_vec(&view[..m.bytes as usize])
    };
    staging.unmap();
    Ok(out)
}

/// Maps the first `bytes` of `staging` (the submission that fills it must already be queued),
/// waits for the device, and returns them as elements of `P`; the buffer is unmapped again.
pub fn map_read<P: Pod>(ctx: &GpuContext, staging: &wgpu::Buffer, bytes: u64) -> Result<Vec<P>, GpuError> {
    map_finish(ctx, staging, map_start(staging, bytes), None)
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
