//! `sphlab info`: the machine: build commit, CPU and threads, memory, every GPU adapter with its
//! features and limits, and what the solver's device was granted.

use super::common::{gpu_context, print_json, with_provenance};
use sphlab::error::Error;
use sphlab::gpu::plan::DeviceLimits;
use sphlab::plan::{self, Limits};
use sphlab::provenance::{self, GpuInfo, Provenance};

/// Every adapter wgpu finds, with the features and limits sphlab cares about.
fn adapters_json() -> Vec<serde_json::Value> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    adapters
        .iter()
        .map(|ad| {
            let l = ad.limits();
            let features: Vec<&str> = ad.features().iter_names().map(|(n, _)| n).collect();
            serde_json::json!({
                "adapter": GpuInfo::from_adapter(&ad.get_info()),
                "features": features,
                "limits": {
                    "max_buffer_size": l.max_buffer_size,
                    "max_storage_buffer_binding_size": l.max_storage_buffer_binding_size,
                    "max_storage_buffers_per_shader_stage": l.max_storage_buffers_per_shader_stage,
                    "max_compute_workgroup_storage_size": l.max_compute_workgroup_storage_size,
                    "max_compute_invocations_per_workgroup": l.max_compute_invocations_per_workgroup,
                    "max_compute_workgroup_size_x": l.max_compute_workgroup_size_x,
                    "max_compute_workgroups_per_dimension": l.max_compute_workgroups_per_dimension,
                },
            })
        })
        .collect()
}

/// The report, as text or JSON.
pub fn run(json: bool) -> Result<(), Error> {
    let prov = Provenance::new("info", None, &[]);
    let limits = Limits::default();
    let adapters = adapters_json();
    // What the solver's device was granted (the adapter's own limits, requested in full) and
    // the device memory its memory plan assumes.
    let device = gpu_context().ok().map(|c| (c.describe(), DeviceLimits::of(&c, None)));
    let doc = with_provenance(
        serde_json::json!({
            "memory_available_bytes": plan::available_memory(),
            "default_limits": limits,
            "adapters": adapters,
            "device": device.as_ref().map(|(name, l)| serde_json::json!({"adapter": name, "limits": l})),
        }),
        &prov,
    );
    if json {
        print_json(&doc);
        return Ok(());
    }
    println!("sphlab {}", provenance::long_version());
    println!(
        "host: {} ({} logical CPUs, {} worker threads, {})",
        prov.host.cpu, prov.host.cpus, prov.host.threads, prov.host.os
    );
    println!(
        "memory: {} available; default limits: {} particles, {} ({})",
        plan::available_memory().map_or("unknown".into(), |b| plan::fmt_bytes(b as f64)),
        limits.max_particles,
        plan::fmt_bytes(limits.max_memory as f64),
        limits.memory_source
    );
    if adapters.is_empty() {
        println!("GPU adapters: none");
    }
    for a in &adapters {
        let ad = &a["adapter"];
        println!(
            "adapter: {} ({}, {}, driver {})",
            ad["adapter"].as_str().unwrap_or(""),
            ad["api"].as_str().unwrap_or(""),
            ad["device_type"].as_str().unwrap_or(""),
            ad["driver"].as_str().unwrap_or("")
        );
        let f: Vec<&str> =
            a["features"].as_array().map(|v| v.iter().filter_map(|x| x.as_str()).collect()).unwrap_or_default();
        println!("  features: {}", if f.is_empty() { "-".into() } else { f.join(" ") });
        if let Some(l) = a["limits"].as_object() {
            for (k, v) in l {
                println!("  {k}: {v}");
            }
        }
    }
    if let Some((name, l)) = &device {
        println!(
            "solver device: {name}: granted max_buffer_size {}, max_storage_buffer_binding_size {}, \
             max_compute_workgroups_per_dimension {}; device memory {} ({})",
            l.max_buffer_size,
            l.max_binding_size,
            l.max_groups_per_dim,
            l.memory.map_or("unknown".into(), |m| plan::fmt_bytes(m as f64)),
            l.memory_source
        );
    }
    Ok(())
}
