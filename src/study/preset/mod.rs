//! `sphlab study --preset gpu` (and `scripts/gpu-report.sh`): a short GPU loan turned into the
//! whole report by one command that never builds anything and always leaves its results.
//!
//! It refuses what is not the GPU it was meant for (exit 2, naming adapter and backend): a CPU
//! adapter unless `--allow-cpu-adapter` (then the parts run at the `rehearsal` scale), and any
//! backend but Vulkan, Metal or DX12 (a GL fallback). It prints the adapter, its limits and the
//! plan (each part's share of the budget and the sizes it runs; `--dry-run` stops there), writes
//! `provenance.json` (adapter, driver, backend, limits, date, commit, binary hash) and
//! `variants.csv`, then runs the [`parts`] in order, each as a `sphlab` child process within its
//! share: what a part leaves unused goes to the parts after it, a part still running at the end
//! of its share is stopped (`cut`, its journal kept), and a failed smoke test stops the preset
//! (exit 1). After every part `summary.md` and, with `--archive DIR`, `DIR/gpu-report.tar.gz`
//! are rewritten ([`archive`]); SIGINT and SIGTERM stop the part in flight and finish both
//! before exiting 130 / 143. A part already `done` in the same output directory (an earlier,
//! interrupted run) is not run again.

pub mod archive;
pub mod parts;

use crate::error::Error;
use crate::gpu::variant::VariantSpec;
use crate::gpu::GpuContext;
use crate::provenance::{GpuInfo, Provenance};
use archive::Outcome;
use parts::{Part, Scale};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub use parts::IMPACT_RUNS;

/// Default budget of the preset (s).
pub const DEFAULT_BUDGET_S: f64 = 480.0;
/// Seconds kept at the end for the last merge and archive.
const RESERVE_S: f64 = 3.0;
/// A part is stopped this far past its share (fraction, plus [`GRACE_S`]).
const OVERRUN: f64 = 0.05;
/// Seconds a part may run past its share besides [`OVERRUN`] (start-up of its process).
const GRACE_S: f64 = 2.0;
/// No part runs past this multiple of the budget.
const HARD_END: f64 = 1.05;

/// What `--preset gpu` was asked to do.
#[derive(Clone, Debug)]
pub struct PresetOptions {
    /// The report root (`reports/gpu`); the report goes to `<root>/<adapter>/`.
    pub out_root: PathBuf,
    /// Wall-time budget of the whole preset (s).
    pub budget_s: f64,
    /// Run on a CPU adapter (the `rehearsal` scale).
    pub allow_cpu_adapter: bool,
    /// Print the plan and stop.
    pub dry_run: bool,
    /// Where to write `gpu-report.tar.gz` and `summary.md` after every part.
    pub archive: Option<PathBuf>,
}

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
            let Ok(scene) = super::study_scene_with(nx, &[]) else { return false };
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
fn variants_csv(ctx: &GpuContext) -> String {
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
fn provenance(ctx: &GpuContext, exe: &Path, o: &PresetOptions, scale: &str) -> Result<serde_json::Value, String> {
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

/// How a child part ended.
fn run_part(exe: &Path, args: &[String], dir: &Path, deadline: Instant, signal: &AtomicUsize) -> (String, String) {
    let log = match std::fs::File::create(dir.join("log.txt")) {
        Ok(f) => f,
        Err(e) => return ("failed".into(), format!("log.txt: {e}")),
    };
    let child = log
        .try_clone()
        .and_then(|err| Command::new(exe).args(args).stdin(Stdio::null()).stdout(log).stderr(err).spawn());
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return ("failed".into(), format!("could not start {}: {e}", exe.display())),
    };
    loop {
        match child.try_wait() {
            Ok(Some(st)) if st.success() => return ("done".into(), archive::result_line(dir)),
            Ok(Some(st)) => {
                let code = st.code().map_or("a signal".to_string(), |c| format!("exit {c}"));
                return ("failed".into(), format!("{code}: {}", archive::last_lines(&dir.join("log.txt"), 2)));
            }
            Ok(None) => {}
            Err(e) => return ("failed".into(), format!("wait: {e}")),
        }
        let stop = if signal.load(Ordering::SeqCst) != 0 {
            Some("interrupted")
        } else {
            (Instant::now() >= deadline).then_some("cut")
        };
        if let Some(status) = stop {
            let _ = child.kill();
            let _ = child.wait();
            let why = if status == "cut" {
                "stopped at the end of its share; kept what it wrote: "
            } else {
                "stopped by a signal; kept: "
            };
            return (status.into(), format!("{why}{}", archive::result_line(dir)));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The plan: adapter, budget, scale, and each part with its planned share and command.
fn plan_text(adapter: &str, dir: &Path, o: &PresetOptions, scale: &Scale, parts: &[Part]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{adapter}\noutput: {}", dir.display());
    if let Some(a) = &o.archive {
        let _ = writeln!(s, "archive: {} (rewritten after every part)", a.join(archive::ARCHIVE).display());
    }
    let _ =
        writeln!(s, "budget: {:.0} s; scale: {}; parts (shares if every part uses its own):", o.budget_s, scale.name);
    let mut left = o.budget_s - RESERVE_S;
    for (k, p) in parts.iter().enumerate() {
        let share = part_share(parts, k, o.budget_s, left);
        left -= share;
        let cmd = parts::command(p, child_budget(share), &PathBuf::from("parts").join(&p.name));
        let _ = writeln!(s, "  {} share {share:.0} s: {}\n      sphlab {}", p.name, p.what, cmd.join(" "));
    }
    s
}

/// The share (s) of `parts[k]` with `left_s` of the budget left: the smoke test at most
/// [`parts::SMOKE_MAX_S`] and a fifth of the budget, every later part by its weight.
fn part_share(parts: &[Part], k: usize, budget_s: f64, left_s: f64) -> f64 {
    if k == 0 {
        parts::SMOKE_MAX_S.min(0.2 * budget_s).min(left_s.max(0.0))
    } else {
        parts::share(parts, k, left_s)
    }
}

/// Runs the preset (or prints its plan with `dry_run`). A refused adapter is [`Error::Input`];
/// a failed smoke test [`Error::CheckFailed`], SIGINT [`Error::Interrupted`] and SIGTERM
/// [`Error::Terminated`], each without a message (the summary says it).
pub fn run(o: &PresetOptions) -> Result<(), Error> {
    let t0 = Instant::now();
    let ctx = GpuContext::new().map_err(|e| Error::Input(format!("--preset gpu: no GPU adapter ({e})")))?;
    check_adapter(&ctx.adapter_info, o.allow_cpu_adapter).map_err(Error::Input)?;
    let scale = if ctx.adapter_info.device_type == wgpu::DeviceType::Cpu {
        Scale::rehearsal()
    } else {
        Scale::gpu(&fitting_sizes(&ctx))
    };
    let parts = parts::parts(&scale);
    let dir = o.out_root.join(adapter_slug(&ctx.adapter_info.name));
    let plan = plan_text(&describe_adapter(&ctx), &dir, o, &scale, &parts);
    eprint!("{plan}");
    if o.dry_run {
        return Ok(());
    }
    let fail = Error::Failed;
    let exe = std::env::current_exe().map_err(|e| fail(format!("the sphlab binary: {e}")))?;
    std::fs::create_dir_all(dir.join("parts")).map_err(|e| fail(format!("{}: {e}", dir.display())))?;
    let prov = provenance(&ctx, &exe, o, scale.name).map_err(fail)?;
    crate::output::write_json(dir.join("provenance.json"), &prov).map_err(|e| fail(e.to_string()))?;
    std::fs::write(dir.join("plan.txt"), &plan).map_err(|e| fail(e.to_string()))?;
    std::fs::write(dir.join("variants.csv"), variants_csv(&ctx)).map_err(|e| fail(e.to_string()))?;
    let adapter = ctx.describe();
    drop(ctx);
    let signal = Arc::new(AtomicUsize::new(0));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize)
            .map_err(|e| fail(format!("signal handler: {e}")))?;
    }
    let sha = prov["binary_sha256"].as_str().unwrap_or("").chars().take(16).collect::<String>();
    let head = format!(
        "Commit `{}`{}, {}; binary SHA-256 `{sha}…`.",
        prov["commit"].as_str().unwrap_or("?"),
        if prov["dirty"].as_bool() == Some(true) { " (dirty)" } else { "" },
        prov["date"].as_str().unwrap_or("?")
    );
    let header = archive::Header { adapter: &adapter, scale: scale.name, budget_s: o.budget_s, provenance: &head };
    let mut outcomes: Vec<Outcome> = parts.iter().map(|p| Outcome::pending(&p.name, &p.what)).collect();
    let refresh = |outcomes: &[Outcome], ending: &str| {
        let md = archive::summary(&header, outcomes, t0.elapsed().as_secs_f64(), ending);
        let _ = std::fs::write(dir.join("summary.md"), &md);
        let _ = crate::output::write_json(dir.join("parts.json"), &outcomes);
        if let Some(a) = &o.archive {
            match archive::write(&dir, a, &md) {
                Ok(bytes) => eprintln!(
                    "preset: archive {} ({:.1} MiB)",
                    a.join(archive::ARCHIVE).display(),
                    bytes as f64 / 1048576.0
                ),
                Err(e) => eprintln!("preset: archive not written: {e}"),
            }
        }
    };
    refresh(&outcomes, "started");
    let hard_end = t0 + Duration::from_secs_f64(HARD_END * o.budget_s);
    let mut blocked: Option<String> = None;
    for (k, part) in parts.iter().enumerate() {
        let pdir = dir.join("parts").join(&part.name);
        let left = o.budget_s - RESERVE_S - t0.elapsed().as_secs_f64();
        let share = part_share(&parts, k, o.budget_s, left);
        if signal.load(Ordering::SeqCst) != 0 {
            break;
        }
        let out = &mut outcomes[k];
        out.share_s = share;
        out.command = format!("sphlab {}", parts::command(part, child_budget(share), &pdir).join(" "));
        if let Some(why) = &blocked {
            (out.status, out.note) = ("skipped".into(), why.clone());
            continue;
        }
        if done_earlier(&pdir) {
            (out.status, out.note) =
                ("done".into(), format!("done by an earlier run: {}", archive::result_line(&pdir)));
            continue;
        }
        if share < parts::MIN_SHARE_S {
            (out.status, out.note) = (
                "skipped".into(),
                format!("its share, {share:.1} s, is below the {} s a part needs", parts::MIN_SHARE_S),
            );
            continue;
        }
        if let Err(e) = std::fs::create_dir_all(&pdir) {
            (out.status, out.note) = ("failed".into(), format!("{}: {e}", pdir.display()));
            continue;
        }
        eprintln!("preset: {} ({share:.0} s): {}", part.name, out.command);
        out.status = "running".into();
        refresh(&outcomes, "running");
        let out = &mut outcomes[k];
        let started = Instant::now();
        let deadline = (started + Duration::from_secs_f64(share * (1.0 + OVERRUN) + GRACE_S)).min(hard_end);
        let args = parts::command(part, child_budget(share), &pdir);
        (out.status, out.note) = run_part(&exe, &args, &pdir, deadline, &signal);
        out.used_s = started.elapsed().as_secs_f64();
        eprintln!("preset: {} {} in {:.1} s: {}", part.name, out.status, out.used_s, out.note);
        let _ = crate::output::write_json(pdir.join("part.json"), &*out);
        if part.gate && out.status != "done" {
            blocked = Some(format!("not run: {} did not pass ({})", part.name, out.status));
        }
        if part.study {
            merge_studies(&dir, &parts);
        }
        let ending = if signal.load(Ordering::SeqCst) != 0 { "interrupted" } else { "running" };
        refresh(&outcomes, ending);
    }
    let sig = signal.load(Ordering::SeqCst);
    for out in outcomes.iter_mut().filter(|o| o.status == "pending") {
        out.status = "skipped".into();
        out.note = if sig != 0 { "not reached: interrupted".into() } else { "not reached".into() };
    }
    let ending = match sig {
        0 if blocked.is_some() => "stopped: the smoke test failed",
        0 => "finished",
        _ => "interrupted by a signal",
    };
    refresh(&outcomes, ending);
    eprintln!(
        "preset: {ending} after {:.0} s of {:.0} s; report in {}",
        t0.elapsed().as_secs_f64(),
        o.budget_s,
        dir.display()
    );
    // The summary says what happened; the error only sets the exit code.
    match sig {
        0 if blocked.is_some() => Err(Error::CheckFailed(String::new())),
        0 => Ok(()),
        s if s == signal_hook::consts::SIGTERM as usize => Err(Error::Terminated(String::new())),
        _ => Err(Error::Interrupted(String::new())),
    }
}

/// The budget a part's own command is given: below its share, leaving room for its process
/// start and its report.
fn child_budget(share: f64) -> f64 {
    (0.85 * share - 1.0).max(1.0)
}

/// True when an earlier run in this directory finished the part.
fn done_earlier(pdir: &Path) -> bool {
    std::fs::read_to_string(pdir.join("part.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v["status"] == "done")
}

/// The study parts that wrote records, merged into `study/`.
fn merge_studies(dir: &Path, parts: &[Part]) {
    let inputs: Vec<PathBuf> = parts
        .iter()
        .filter(|p| p.study)
        .map(|p| dir.join("parts").join(&p.name))
        .filter(|d| d.join("records.csv").exists() || d.join(super::report::JOURNAL).exists())
        .collect();
    if inputs.is_empty() {
        return;
    }
    if let Err(e) = super::report::merge(&inputs, &dir.join("study")) {
        eprintln!("preset: merging the study parts: {e}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(backend: wgpu::Backend, device_type: wgpu::DeviceType) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: "Some Adapter".into(),
            vendor: 0,
            device: 0,
            device_type,
            driver: String::new(),
            driver_info: String::new(),
            backend,
            ..wgpu::AdapterInfo::new(wgpu::DeviceType::Other, wgpu::Backend::Noop)
        }
    }

    #[test]
    fn only_a_gpu_on_vulkan_metal_or_dx12_passes() {
        use wgpu::{Backend as B, DeviceType as D};
        assert!(check_adapter(&info(B::Vulkan, D::DiscreteGpu), false).is_ok());
        assert!(check_adapter(&info(B::Dx12, D::IntegratedGpu), false).is_ok());
        let gl = check_adapter(&info(B::Gl, D::DiscreteGpu), true).unwrap_err();
        assert!(gl.contains("Some Adapter") && gl.contains("Gl") && gl.contains("WGPU_BACKEND"), "{gl}");
        let cpu = check_adapter(&info(B::Vulkan, D::Cpu), false).unwrap_err();
        assert!(cpu.contains("Some Adapter") && cpu.contains("Vulkan") && cpu.contains("--allow-cpu-adapter"), "{cpu}");
        assert!(check_adapter(&info(B::Vulkan, D::Cpu), true).is_ok());
    }

    #[test]
    fn a_part_done_earlier_is_recognised() {
        let d = tempfile::tempdir().unwrap();
        assert!(!done_earlier(d.path()));
        std::fs::write(d.path().join("part.json"), r#"{"status":"cut"}"#).unwrap();
        assert!(!done_earlier(d.path()));
        std::fs::write(d.path().join("part.json"), r#"{"status":"done"}"#).unwrap();
        assert!(done_earlier(d.path()));
    }

    #[test]
    fn slugs() {
        assert_eq!(adapter_slug("NVIDIA H200"), "nvidia-h200");
        assert_eq!(adapter_slug("llvmpipe (LLVM 15.0.6, 256 bits)"), "llvmpipe-llvm-15-0-6-256-bits");
        assert_eq!(adapter_slug("!!"), "adapter");
    }
}
