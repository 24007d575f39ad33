//! The adapter side of the GPU preset: which adapters it accepts, how it names and describes
//! one, the sizes that fit it, the variants it supports, and the provenance of a loan.

use super::{archive, parts, PresetOptions};
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::provenance::{GpuInfo, Provenance};
use std::fmt::Write;
use std::path::Path;

/// A directory name from an adapter name (`NVIDIA H200` → `nvidia-h200`).
pub fn adapter_slug(name: &str) -> String {
    let s: String =
        name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '-' }).collect();
    let s = s.split('-').filter(|p| !p.is_empty()).collect::<Vec<_>>().join("-");
    if s.is_empty() {
        "adapter".into()
    } else {
        s
    }
}

/// The scaling resolutions whose host plan and GPU buffers fit this adapter.
pub fn fitting_sizes(ctx: &GpuContext) -> Vec<u32> {
    let device = crate::gpu::plan::DeviceLimits::of(ctx, None);
    let limits = crate::plan::Limits::default();
    parts::SCALING_NX
        .iter()
        .copied()
        .filter(|&nx| {
            let Ok(scene) = crate::study::study_scene_with(nx, &[]) else { return false };
            crate::resources::run_plan(&scene, 8, false).check(&limits).is_ok()
                && crate::resources::run_plan(&scene, 4, true).check_gpu(&device).is_ok()
        })
        .collect()
}

/// Adapter, driver and the limits that bound the sizes.
pub fn describe_adapter(ctx: &GpuContext) -> String {
    let i = &ctx.adapter_info;
    let l = &ctx.limits;
    format!(
        "adapter: {} ({:?}, {:?}); driver: {} {}\nlimits: max_buffer_size {}, max_storage_buffer_binding_size {}, \
         max_compute_workgroups_per_dimension {}; features: {:?}",
        i.name,
        i.backend,
        i.device_type,
        i.driver,
        i.driver_info,
        l.max_buffer_size,
        l.max_storage_buffer_binding_size,
        l.max_compute_workgroups_per_dimension,
        ctx.features
    )
}

/// `Err` (exit 2, naming adapter and backend) unless the adapter is a GPU on Vulkan, Metal or
/// DX12; a CPU adapter passes with `allow_cpu`.
pub fn check_adapter(info: &wgpu::AdapterInfo, allow_cpu: bool) -> Result<(), String> {
    let named = format!("the adapter `{}` (backend {:?}, device type {:?})", info.name, info.backend, info.device_type);
    if !matches!(info.backend, wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12) {
        return Err(format!(
            "--preset gpu: {named} is not on Vulkan, Metal or DX12; set WGPU_BACKEND=vulkan (scripts/gpu-report.sh does)"
        ));
    }
    if info.device_type == wgpu::DeviceType::Cpu && !allow_cpu {
        return Err(format!(
            "--preset gpu: {named} is a CPU adapter (e.g. lavapipe), not a GPU; its times are not GPU times. Pass \
             --allow-cpu-adapter to rehearse the preset on it"
        ));
    }
    Ok(())
}

/// `variants.csv`: every variant and whether this adapter runs it.
pub(super) fn variants_csv(ctx: &GpuContext) -> String {
    let mut csv = String::from("variant,status\n");
    for v in VariantSpec::all() {
        let st = v
            .support(ctx)
            .map_or_else(|e| format!("\"unsupported: {}\"", e.replace('"', "'")), |()| "supported".into());
        let _ = writeln!(csv, "{v},{st}");
    }
    csv
}

/// `provenance.json`: the common envelope plus backend, limits, budget, scale and binary hash.
pub(super) fn provenance(
    ctx: &GpuContext,
    exe: &Path,
    o: &PresetOptions,
    scale: &str,
) -> Result<serde_json::Value, String> {
    let prov = Provenance::new(
        "study --preset gpu",
        Some(GpuInfo::from_adapter(&ctx.adapter_info)),
        crate::provenance::STUDY_UNITS,
    );
    let mut v = serde_json::to_value(&prov).map_err(|e| e.to_string())?;
    let l = &ctx.limits;
    v["adapter_backend"] = format!("{:?}", ctx.adapter_info.backend).into();
    v["limits"] = serde_json::json!({
        "max_buffer_size": l.max_buffer_size,
        "max_storage_buffer_binding_size": l.max_storage_buffer_binding_size,
        "max_compute_workgroups_per_dimension": l.max_compute_workgroups_per_dimension,
        "max_compute_invocations_per_workgroup": l.max_compute_invocations_per_workgroup,
        "max_compute_workgroup_storage_size": l.max_compute_workgroup_storage_size,
    });
    v["features"] = format!("{:?}", ctx.features).into();
    v["binary"] = exe.display().to_string().into();
    v["binary_sha256"] = archive::sha256_of(exe)?.into();
    v["budget_s"] = o.budget_s.into();
    v["scale"] = scale.into();
    Ok(v)
}
