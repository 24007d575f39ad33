//! Headless wgpu device: adapter selection, feature and limit negotiation, the error-scope
//! wrapper that turns a bad shader into an `Err`, and `wait_idle` over the poll API.
//!
//! Every optional feature sphlab can use ([`OPTIONAL_FEATURES`]) is requested when the adapter
//! has it; variants check [`GpuContext::features`] and report "unsupported on this adapter"
//! instead of silently falling back (docs/STUDY.md §2).

use super::GpuError;
use wgpu::{Features, Limits};

/// Optional features requested whenever the adapter offers them.
pub const OPTIONAL_FEATURES: Features = Features::SHADER_F64
    .union(Features::SHADER_FLOAT32_ATOMIC)
    .union(Features::SUBGROUP)
    .union(Features::TIMESTAMP_QUERY)
    .union(Features::TIMESTAMP_QUERY_INSIDE_PASSES);

/// True when a missing GPU must fail instead of skip: `SPHLAB_REQUIRE_GPU=1` or `CI=true`.
pub fn gpu_required() -> bool {
    std::env::var("SPHLAB_REQUIRE_GPU").is_ok_and(|v| v == "1") || std::env::var("CI").is_ok_and(|v| v == "true")
}

/// A headless device and queue with what was negotiated.
pub struct GpuContext {
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name, backend, driver.
    pub adapter_info: wgpu::AdapterInfo,
    /// Features actually enabled on the device.
    pub features: Features,
    /// Limits actually granted to the device.
    pub limits: Limits,
    /// Submissions, readbacks, dispatches and host writes so far (`gpu::counters`).
    pub traffic: super::counters::Traffic,
    /// Pipelines compiled on this device, by variant (built once, reused at every size).
    pub pipelines: super::pipeline_cache::PipelineCache,
}

impl GpuContext {
    /// The most bytes one buffer can hold and bind whole: the smaller of
    /// `max_storage_buffer_binding_size` and `max_buffer_size`.
    pub fn buffer_cap(&self) -> u64 {
        self.limits.max_storage_buffer_binding_size.min(self.limits.max_buffer_size)
    }

    /// This context as an adapter whose per-buffer limits are at most `bytes` (a smaller
    /// device emulated: the memory plan and the list chunks, `gpu::list_chunks`, follow it).
    pub fn with_binding_cap(mut self, bytes: u64) -> Self {
        self.limits.max_storage_buffer_binding_size = self.limits.max_storage_buffer_binding_size.min(bytes);
        self.limits.max_buffer_size = self.limits.max_buffer_size.min(bytes);
        self
    }

    /// Opens the default adapter (high performance preference, any backend wgpu was built with;
    /// `WGPU_BACKEND` and friends are honoured) without a surface.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let features = adapter.features() & OPTIONAL_FEATURES;
        let max = adapter.limits();
        let limits = Limits {
            max_storage_buffer_binding_size: max.max_storage_buffer_binding_size,
            max_storage_buffers_per_shader_stage: max.max_storage_buffers_per_shader_stage,
            max_buffers_and_acceleration_structures_per_shader_stage: max
                .max_buffers_and_acceleration_structures_per_shader_stage,
            max_buffer_size: max.max_buffer_size,
            max_compute_workgroup_storage_size: max.max_compute_workgroup_storage_size,
            max_compute_invocations_per_workgroup: max.max_compute_invocations_per_workgroup,
            max_compute_workgroup_size_x: max.max_compute_workgroup_size_x,
            max_compute_workgroups_per_dimension: max.max_compute_workgroups_per_dimension,
            ..Limits::defaults()
        }
        .or_worse_values_from(&max);
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("sphlab"),
                required_features: features,
                required_limits: limits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(format!("request_device: {e}")))?;
        Ok(Self {
            adapter_info: adapter.get_info(),
            features: device.features(),
            limits: device.limits(),
            traffic: Default::default(),
            device,
            queue,
            pipelines: Default::default(),
        })
    }

    /// One line: "name (backend, device type, driver, driver_info)".
    pub fn describe(&self) -> String {
        let i = &self.adapter_info;
        format!("{} ({:?}, {:?}, {}, {})", i.name, i.backend, i.device_type, i.driver, i.driver_info)
    }

    /// True when the device has every feature in `f`.
    pub fn has(&self, f: Features) -> bool {
        self.features.contains(f)
    }

    /// `Err(MissingFeature)` unless the device has `f` (`name` is its human name).
    pub fn require(&self, f: Features, name: &'static str) -> Result<(), GpuError> {
        if self.has(f) {
            Ok(())
        } else {
            Err(GpuError::MissingFeature(name))
        }
    }

    /// Blocks until all submitted work is done.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(format!("poll: {e}")))
    }

    /// Runs `f` inside a validation error scope: any wgpu validation error becomes `Err`.
    pub fn scoped<R>(&self, f: impl FnOnce(&wgpu::Device) -> R) -> Result<R, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let r = f(&self.device);
        match pollster::block_on(scope.pop()) {
            None => Ok(r),
            Some(e) => Err(GpuError::Validation(e.to_string())),
        }
    }

    /// Builds a compute pipeline (auto layout) from flat WGSL; a bad shader is an `Err`.
    pub fn compute_pipeline(&self, label: &str, wgsl: &str, entry: &str) -> Result<wgpu::ComputePipeline, GpuError> {
        self.scoped(|d| {
            let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
            d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        })
    }

    /// Builds a bind group for group 0 of `pipeline` from buffers bound in order 0, 1, 2, …
    pub fn bind_group(
        &self,
        pipeline: &wgpu::ComputePipeline,
        buffers: &[&wgpu::Buffer],
    ) -> Result<wgpu::BindGroup, GpuError> {
        let entries: Vec<_> = buffers
            .iter()
            .enumerate()
            .map(|(k, b)| wgpu::BindGroupEntry { binding: k as u32, resource: b.as_entire_binding() })
            .collect();
        self.scoped(|d| {
            d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            })
        })
    }

    /// Records and submits one dispatch of `groups` workgroups (x) and waits for it.
    pub fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        groups: u32,
    ) -> Result<(), GpuError> {
        let mut enc = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            pass.dispatch_workgroups(groups, 1, 1);
        }
        self.traffic.dispatch(1);
        self.traffic.submit();
        self.queue.submit([enc.finish()]);
        self.wait_idle()
    }
}
