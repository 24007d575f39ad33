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

mod adapter;
pub mod archive;
pub mod parts;

pub use adapter::{adapter_slug, check_adapter, describe_adapter, fitting_sizes};
use adapter::{provenance, variants_csv};

use crate::error::Error;
use crate::gpu::GpuContext;
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
    let Some(setup) = prepare(o)? else { return Ok(()) };
    let signal = Arc::new(AtomicUsize::new(0));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize)
            .map_err(|e| Error::Failed(format!("signal handler: {e}")))?;
    }
    let report = Report {
        dir: &setup.dir,
        archive: o.archive.as_deref(),
        header: archive::Header {
            adapter: &setup.adapter,
            scale: setup.scale.name,
            budget_s: o.budget_s,
            provenance: &setup.head,
        },
        t0,
    };
    let parts = &setup.parts;
    let mut outcomes: Vec<Outcome> = parts.iter().map(|p| Outcome::pending(&p.name, &p.what)).collect();
    report.refresh(&outcomes, "started");
    let hard_end = t0 + Duration::from_secs_f64(HARD_END * o.budget_s);
    let mut blocked: Option<String> = None;
    for (k, part) in parts.iter().enumerate() {
        let left = o.budget_s - RESERVE_S - t0.elapsed().as_secs_f64();
        let share = part_share(parts, k, o.budget_s, left);
        if signal.load(Ordering::SeqCst) != 0 {
            break;
        }
        let turn = Turn { part, dir: setup.dir.join("parts").join(&part.name), share, hard_end };
        if !run_turn(&turn, &mut outcomes, k, &blocked, &setup.exe, &signal, &report) {
            continue;
        }
        if part.gate && outcomes[k].status != "done" {
            blocked = Some(format!("not run: {} did not pass ({})", part.name, outcomes[k].status));
        }
        if part.study {
            merge_studies(&setup.dir, parts);
        }
        let ending = if signal.load(Ordering::SeqCst) != 0 { "interrupted" } else { "running" };
        report.refresh(&outcomes, ending);
    }
    finish(&mut outcomes, signal.load(Ordering::SeqCst), blocked.is_some(), o, &report)
}

/// What the preset runs with, once the adapter is accepted and the report folder written.
struct Setup {
    /// `<out_root>/<adapter>`.
    dir: PathBuf,
    /// The sphlab binary the parts run.
    exe: PathBuf,
    /// The adapter line.
    adapter: String,
    /// The commit, date and binary-hash line.
    head: String,
    /// The scale of the parts.
    scale: Scale,
    /// The parts, in order.
    parts: Vec<Part>,
}

/// Accepts or refuses the adapter, prints the plan, and (unless `dry_run`: `None`) writes
/// `provenance.json`, `plan.txt` and `variants.csv`.
fn prepare(o: &PresetOptions) -> Result<Option<Setup>, Error> {
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
        return Ok(None);
    }
    let fail = Error::Failed;
    let exe = std::env::current_exe().map_err(|e| fail(format!("the sphlab binary: {e}")))?;
    std::fs::create_dir_all(dir.join("parts")).map_err(|e| fail(format!("{}: {e}", dir.display())))?;
    let prov = provenance(&ctx, &exe, o, scale.name).map_err(fail)?;
    crate::output::write_json(dir.join("provenance.json"), &prov).map_err(|e| fail(e.to_string()))?;
    std::fs::write(dir.join("plan.txt"), &plan).map_err(|e| fail(e.to_string()))?;
    std::fs::write(dir.join("variants.csv"), variants_csv(&ctx)).map_err(|e| fail(e.to_string()))?;
    let sha = prov["binary_sha256"].as_str().unwrap_or("").chars().take(16).collect::<String>();
    let head = format!(
        "Commit `{}`{}, {}; binary SHA-256 `{sha}…`.",
        prov["commit"].as_str().unwrap_or("?"),
        if prov["dirty"].as_bool() == Some(true) { " (dirty)" } else { "" },
        prov["date"].as_str().unwrap_or("?")
    );
    Ok(Some(Setup { dir, exe, adapter: ctx.describe(), head, scale, parts }))
}

/// Where the preset's summary goes after every part.
struct Report<'a> {
    dir: &'a Path,
    archive: Option<&'a Path>,
    header: archive::Header<'a>,
    t0: Instant,
}

impl Report<'_> {
    /// Rewrites `summary.md`, `parts.json` and, with `--archive`, the tarball.
    fn refresh(&self, outcomes: &[Outcome], ending: &str) {
        let md = archive::summary(&self.header, outcomes, self.t0.elapsed().as_secs_f64(), ending);
        let _ = std::fs::write(self.dir.join("summary.md"), &md);
        let _ = crate::output::write_json(self.dir.join("parts.json"), &outcomes);
        if let Some(a) = self.archive {
            match archive::write(self.dir, a, &md) {
                Ok(bytes) => eprintln!(
                    "preset: archive {} ({:.1} MiB)",
                    a.join(archive::ARCHIVE).display(),
                    bytes as f64 / 1048576.0
                ),
                Err(e) => eprintln!("preset: archive not written: {e}"),
            }
        }
    }
}

/// One part's turn: the part, its folder, its share (s) and the hard end of the preset.
struct Turn<'a> {
    part: &'a Part,
    dir: PathBuf,
    share: f64,
    hard_end: Instant,
}

/// Runs one part into `outcomes[k]` (true), or records why it is skipped, already done or
/// could not start (false).
fn run_turn(
    turn: &Turn,
    outcomes: &mut [Outcome],
    k: usize,
    blocked: &Option<String>,
    exe: &Path,
    signal: &AtomicUsize,
    report: &Report,
) -> bool {
    let (part, pdir, share) = (turn.part, &turn.dir, turn.share);
    let out = &mut outcomes[k];
    out.share_s = share;
    out.command = format!("sphlab {}", parts::command(part, child_budget(share), pdir).join(" "));
    if let Some(why) = blocked {
        (out.status, out.note) = ("skipped".into(), why.clone());
        return false;
    }
    if done_earlier(pdir) {
        (out.status, out.note) = ("done".into(), format!("done by an earlier run: {}", archive::result_line(pdir)));
        return false;
    }
    if share < parts::MIN_SHARE_S {
        let note = format!("its share, {share:.1} s, is below the {} s a part needs", parts::MIN_SHARE_S);
        (out.status, out.note) = ("skipped".into(), note);
        return false;
    }
    if let Err(e) = std::fs::create_dir_all(pdir) {
        (out.status, out.note) = ("failed".into(), format!("{}: {e}", pdir.display()));
        return false;
    }
    eprintln!("preset: {} ({share:.0} s): {}", part.name, out.command);
    out.status = "running".into();
    report.refresh(outcomes, "running");
    let out = &mut outcomes[k];
    let started = Instant::now();
    let deadline = (started + Duration::from_secs_f64(share * (1.0 + OVERRUN) + GRACE_S)).min(turn.hard_end);
    let args = parts::command(part, child_budget(share), pdir);
    (out.status, out.note) = run_part(exe, &args, pdir, deadline, signal);
    out.used_s = started.elapsed().as_secs_f64();
    eprintln!("preset: {} {} in {:.1} s: {}", part.name, out.status, out.used_s, out.note);
    let _ = crate::output::write_json(pdir.join("part.json"), &*out);
    true
}

/// Marks the parts not reached and writes the last summary; the error sets the exit code only
/// (the summary says what happened).
fn finish(
    outcomes: &mut [Outcome],
    sig: usize,
    blocked: bool,
    o: &PresetOptions,
    report: &Report,
) -> Result<(), Error> {
    for out in outcomes.iter_mut().filter(|o| o.status == "pending") {
        out.status = "skipped".into();
        out.note = if sig != 0 { "not reached: interrupted".into() } else { "not reached".into() };
    }
    let ending = match sig {
        0 if blocked => "stopped: the smoke test failed",
        0 => "finished",
        _ => "interrupted by a signal",
    };
    report.refresh(outcomes, ending);
    eprintln!(
        "preset: {ending} after {:.0} s of {:.0} s; report in {}",
        report.t0.elapsed().as_secs_f64(),
        o.budget_s,
        report.dir.display()
    );
    match sig {
        0 if blocked => Err(Error::CheckFailed(String::new())),
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
