//! Typed GPU buffers: [`GpuVec<T>`] (a storage buffer with a length, upload, read back, fill)
//! and [`Uniform<T>`]. `T` is a `bytemuck::Pod` type whose layout matches its WGSL twin.
//!
//! Read back copies into a fresh `MAP_READ` staging buffer, maps it and waits on the device
//! ([`super::staging`]), so it is a synchronisation point; the solver reads back only
//! for checks and output. `fill` writes a sentinel (f32 NaN bits, `u32::MAX`) so a shader that
//! forgets to write an element is caught by the comparison (the stage-by-stage GPU tests).

use super::{GpuContext, GpuError};
use bytemuck::Pod;
use std::marker::PhantomData;

/// Usage of every [`GpuVec`]: storage, copy source/destination.
const STORAGE: wgpu::BufferUsages =
    wgpu::BufferUsages::STORAGE.union(wgpu::BufferUsages::COPY_SRC).union(wgpu::BufferUsages::COPY_DST);

/// Checks `bytes` against the device's storage binding and buffer limits.
fn check_size(ctx: &GpuContext, what: &str, bytes: u64) -> Result<(), GpuError> {
    let limit = ctx.buffer_cap();
    if bytes > limit {
        return Err(GpuError::TooLarge { what: what.to_string(), bytes, limit });
    }
    Ok(())
}

/// A storage buffer of `len` elements of `T`.
pub struct GpuVec<T: Pod> {
    /// The wgpu buffer (at least 4 bytes even when empty, since zero-sized bindings are invalid).
    pub buffer: wgpu::Buffer,
    len: usize,
    _t: PhantomData<T>,
}

impl<T: Pod> GpuVec<T> {
    /// An uninitialised (zeroed by wgpu) buffer of `len` elements.
    pub fn new(ctx: &GpuContext, label: &str, len: usize) -> Result<Self, GpuError> {
        let bytes = (len * size_of::<T>()) as u64;
        check_size(ctx, label, bytes)?;
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.max(4).next_multiple_of(4),
            usage: STORAGE,
            mapped_at_creation: false,
        });
        Ok(Self { buffer, len, _t: PhantomData })
    }

    /// A buffer holding a copy of `data`.
    pub fn from_slice(ctx: &GpuContext, label: &str, data: &[T]) -> Result<Self, GpuError> {
        let v = Self::new(ctx, label, data.len())?;
        v.upload(ctx, data)?;
        Ok(v)
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there are no elements.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Size in bytes of the elements (without the 4-byte minimum).
    pub fn bytes(&self) -> u64 {
        (self.len * size_of::<T>()) as u64
    }

    /// Writes `data` (exactly `len` elements) through the queue.
    pub fn upload(&self, ctx: &GpuContext, data: &[T]) -> Result<(), GpuError> {
        if data.len() != self.len {
            return Err(GpuError::Validation(format!(
                "upload of {} elements into a GpuVec of {}",
                data.len(),
                self.len
            )));
        }
        let bytes: &[u8] = bytemuck::cast_slice(data);
        ctx.traffic.write();
        if !bytes.len().is_multiple_of(4) {
            // write_buffer needs a multiple of 4 bytes: pad the tail.
            let mut padded = bytes.to_vec();
            padded.resize(bytes.len().next_multiple_of(4), 0);
            ctx.queue.write_buffer(&self.buffer, 0, &padded);
        } else if !bytes.is_empty() {
            ctx.queue.write_buffer(&self.buffer, 0, bytes);
        }
        Ok(())
    }

    /// Sets every element to `value` (poisoning with a sentinel before a kernel writes it).
    pub fn fill(&self, ctx: &GpuContext, value: T) -> Result<(), GpuError> {
        self.upload(ctx, &vec![value; self.len])
    }

    /// Copies the buffer back to the host (submits, maps and waits).
    pub fn read_back(&self, ctx: &GpuContext) -> Result<Vec<T>, GpuError> {
        self.read_range(ctx, 0, self.len)
    }

    /// Copies `len` elements from element `start` back to the host (clamped to the buffer; one
    /// submission, one readback: [`super::staging::read_range`]).
    pub fn read_range(&self, ctx: &GpuContext, start: usize, len: usize) -> Result<Vec<T>, GpuError> {
        let start = start.min(self.len);
        let len = len.min(self.len - start);
        let size = size_of::<T>() as u64;
        super::staging::read_range(ctx, &self.buffer, start as u64 * size, len as u64 * size)
    }
}

/// A uniform buffer holding one `T` (physical parameters: no recompilation when they change).
pub struct Uniform<T: Pod> {
    /// The wgpu buffer.
    pub buffer: wgpu::Buffer,
    _t: PhantomData<T>,
}

impl<T: Pod> Uniform<T> {
    /// A uniform buffer initialised to `value` (size rounded up to 16 bytes).
    pub fn new(ctx: &GpuContext, label: &str, value: &T) -> Self {
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (size_of::<T>() as u64).max(16).next_multiple_of(16),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let u = Self { buffer, _t: PhantomData };
        u.write(ctx, value);
        u
    }

    /// Replaces the value (visible to the next submission).
    pub fn write(&self, ctx: &GpuContext, value: &T) {
        let mut bytes = bytemuck::bytes_of(value).to_vec();
        bytes.resize(bytes.len().next_multiple_of(4), 0);
        ctx.traffic.write();
        ctx.queue.write_buffer(&self.buffer, 0, &bytes);
    }
}
