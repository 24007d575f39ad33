//! `sphlab variants`: every GPU variant with what it needs and whether this adapter runs it, or
//! with `--memory N` the GPU memory plan of every variant at N particles.

use super::common::{gpu_context, print_json, with_provenance};
use clap::Args;
use sphlab::error::Error;
use sphlab::gpu::plan::{bytes_per_particle, max_particles, DeviceLimits, GpuPlan};
use sphlab::gpu::variant::{VariantSpec, SUBGROUP_LANES};
use sphlab::plan::{fmt_bytes, parse_bytes, HARD_MAX_PARTICLES};
use sphlab::provenance::{GpuInfo, Provenance};
use sphlab::scene::{builtin, overrides::apply_overrides};

#[derive(Args)]
pub struct VariantsArgs {
    /// JSON output.
    #[arg(long)]
    json: bool,
    /// The GPU memory plan instead: bytes per particle of every variant, its total for N
    /// particles, and the largest N on this adapter and on a stated 140 GB adapter with
    /// 2 GiB bindings.
    #[arg(long, value_name = "N")]
    memory: Option<u64>,
    /// Device memory of this adapter for the plan (default: host memory on a CPU adapter).
    #[arg(long, value_parser = parse_bytes)]
    gpu_memory: Option<u64>,
}

/// The variant list, or the memory plan with `--memory`.
pub fn run(a: VariantsArgs) -> Result<(), Error> {
    match a.memory {
        Some(n) => memory(n, a.gpu_memory, a.json),
        None => {
            list(a.json);
            Ok(())
        }
    }
}

/// Every variant: its id, the features it needs, and whether this adapter runs it.
fn list(json: bool) {
    let ctx = gpu_context();
    let mut rows = Vec::new();
    for v in VariantSpec::all() {
        let status = match &ctx {
            Err(_) => "unknown: no adapter".to_string(),
            Ok(c) => match v.support(c) {
                Ok(()) => "supported".to_string(),
                Err(e) => format!("unsupported: {e}"),
            },
        };
        let needs: Vec<&str> = v.features().into_iter().map(|(_, name)| name).collect();
        rows.push((v.to_string(), needs, status));
    }
    if json {
        let gpu = ctx.as_ref().ok().map(|c| GpuInfo::from_adapter(&c.adapter_info));
        let variants: Vec<serde_json::Value> = rows
            .iter()
            .map(|(id, needs, status)| serde_json::json!({"id": id, "needs": needs, "status": status}))
            .collect();
        let doc = serde_json::json!({
            "adapter_error": ctx.as_ref().err(),
            "variants": variants,
        });
        print_json(&with_provenance(doc, &Provenance::new("variants", gpu, &[])));
        return;
    }
    match &ctx {
        Ok(c) => {
            let (lo, hi) = (c.adapter_info.subgroup_min_size, c.adapter_info.subgroup_max_size);
            println!("adapter: {}", c.describe());
            println!("subgroups: {lo}..{hi} lanes (the subgroup mapping: min({SUBGROUP_LANES}, S) lanes per particle)");
        }
        Err(e) => println!("adapter: none ({e})"),
    }
    for (id, needs, status) in rows {
        let needs = if needs.is_empty() { "-".to_string() } else { needs.join("+") };
        println!("{id:<44} needs {needs:<34} {status}");
    }
}

/// `--memory N`: the GPU memory plan of every variant (`plan::gpu`), cells per particle as in
/// `oscillating-drop` at nx = 300; at N in the list format the stated adapter gets (`lists`:
/// slots or masks where the format is a choice; `slots`: full or pooled, the slot layout of
/// the cached variants, `gpu::pooled_lists`; `chunks`: the list chunks its slot arrays take
/// there, `gpu::list_chunks`), the largest N of each adapter in the format chosen there.
fn memory(n: u64, gpu_memory: Option<u64>, json: bool) -> Result<(), Error> {
    if n == 0 || n > HARD_MAX_PARTICLES {
        return Err(Error::input(format!("--memory: N must lie in [1, {HARD_MAX_PARTICLES}], got {n}")));
    }
    let scene = apply_overrides(&builtin::builtin("oscillating-drop").expect("built-in"), &["domain.nx=300".into()])
        .expect("valid override");
    let p = sphlab::resources::run_plan(&scene, 4, true);
    let cpp = p.cells / p.n_total;
    let ctx = gpu_context();
    let here = ctx.as_ref().ok().map(|c| DeviceLimits::of(c, gpu_memory));
    let big = DeviceLimits::stated(140_000_000_000, 2 << 30, "stated: 140 GB device memory, 2 GiB per buffer");
    let mut rows = Vec::new();
    for v in VariantSpec::all() {
        // At N on the stated adapter, in the list format the plan chooses there.
        let plan = GpuPlan::resolved(&v, n, (n as f64 * cpp).ceil() as u64, &big);
        let fits = here.as_ref().map(|l| GpuPlan::new(&v, n, plan.cells).check(l));
        rows.push(serde_json::json!({
            "id": v.to_string(),
            "lists": plan.spec.lists.suffix(),
            "slots": plan.spec.slots.suffix(),
            "bytes_per_particle": bytes_per_particle(&plan.spec, cpp),
            "total_bytes": plan.total_bytes,
            "largest_buffer": plan.largest(big.buffer_cap()).0,
            "largest_buffer_bytes": plan.largest(big.buffer_cap()).1,
            "list_chunks": plan.list_chunks(big.buffer_cap()),
            "fits_here": fits.as_ref().map(|r| r.is_ok()),
            "refusal_here": fits.and_then(|r| r.err()),
            "max_n_here": here.as_ref().map(|l| max_particles(&v, cpp, l, HARD_MAX_PARTICLES)),
            "max_n_stated": max_particles(&v, cpp, &big, HARD_MAX_PARTICLES),
        }));
    }
    if json {
        let doc = serde_json::json!({
            "n": n, "cells_per_particle": cpp, "adapter_error": ctx.as_ref().err(),
            "limits_here": here, "limits_stated": big, "variants": rows,
        });
        let gpu = ctx.as_ref().ok().map(|c| GpuInfo::from_adapter(&c.adapter_info));
        print_json(&with_provenance(doc, &Provenance::new("variants", gpu, &[])));
        return Ok(());
    }
    match (&ctx, &here) {
        (Ok(c), Some(l)) => println!(
            "adapter: {}; per buffer {} (max_buffer_size {}, max_storage_buffer_binding_size {}); device memory {} ({})",
            c.describe(),
            fmt_bytes(l.buffer_cap() as f64),
            l.max_buffer_size,
            l.max_binding_size,
            l.memory.map_or("unknown".into(), |m| fmt_bytes(m as f64)),
            l.memory_source
        ),
        _ => println!("adapter: none ({})", ctx.as_ref().err().cloned().unwrap_or_default()),
    }
    println!("stated adapter: {}; cells per particle {cpp:.4} (oscillating-drop)", big.memory_source);
    print_memory_table(n, &rows);
    Ok(())
}

/// The table of `--memory N`, one row per variant.
fn print_memory_table(n: u64, rows: &[serde_json::Value]) {
    println!(
        "{:<44} {:>6} {:>8} {:>9} {:>12} {:>22} {:>6} {:>12} {:>12}",
        "variant",
        "lists",
        "slots",
        "B/part.",
        format!("N={n}"),
        "largest buffer",
        "chunks",
        "max N here",
        "max N 140G"
    );
    for r in rows {
        let s = |k: &str| r[k].as_str().unwrap_or("").to_string();
        let u = |k: &str| r[k].as_u64().map_or("-".into(), |x| x.to_string());
        let largest =
            format!("{} {}", s("largest_buffer"), fmt_bytes(r["largest_buffer_bytes"].as_f64().unwrap_or(0.0)));
        println!(
            "{:<44} {:>6} {:>8} {:>9.1} {:>12} {:>22} {:>6} {:>12} {:>12}",
            s("id"),
            r["lists"].as_str().unwrap_or("-"),
            r["slots"].as_str().unwrap_or("-"),
            r["bytes_per_particle"].as_f64().unwrap_or(0.0),
            fmt_bytes(r["total_bytes"].as_f64().unwrap_or(0.0)),
            largest,
            u("list_chunks"),
            u("max_n_here"),
            u("max_n_stated")
        );
    }
}
