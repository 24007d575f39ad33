//! `sphlab run` under the memory limits a process really runs under: an address-space limit
//! (`ulimit -v`, set in the child by `sh`) is one of the limits the resource plan is checked
//! against, so a scene beyond it exits 2 naming that limit and its bytes, before any output
//! directory is created (the two inputs below used to abort with SIGABRT after seconds);
//! `summary.json`'s plan lists the output and diagnostic buffers; a run that fails mid-way
//! closes its outputs and says `status: "failed"`.

use std::io::Read;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// `ulimit -v` of the issue's inputs: 6,000,000 KiB.
const SIX_GB_KIB: u64 = 6_000_000;

/// `sphlab ARGS` with its address space limited to `kib` KiB (`None`: unlimited); killed and
/// failed after a generous hang guard.
fn sphlab_under(kib: Option<u64>, args: &[&str]) -> Output {
    let script = match kib {
        Some(k) => format!("ulimit -v {k} && exec \"$@\""),
        None => "exec \"$@\"".to_string(),
    };
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg("sh")
        .arg(env!("CARGO_BIN_EXE_sphlab"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sh runs");
    let guard = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if guard.elapsed() > Duration::from_secs(600) {
            let _ = child.kill();
            panic!("{args:?}: still running after the hang guard");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let (mut stdout, mut stderr) = (Vec::new(), Vec::new());
    child.stdout.take().expect("piped").read_to_end(&mut stdout).expect("stdout");
    child.stderr.take().expect("piped").read_to_end(&mut stderr).expect("stderr");
    Output { status, stdout, stderr }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// 80 % of `MemAvailable` in bytes (the machine's own limit), if readable.
fn machine_share() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: f64 = text.lines().find(|l| l.starts_with("MemAvailable:"))?.split_whitespace().nth(1)?.parse().ok()?;
    Some(0.8 * kib * 1024.0)
}

#[test]
fn the_issue_inputs_exit_2_naming_the_address_space_limit_before_any_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let out_s = out.to_str().expect("utf8");
    // Where the machine itself offers less than the address space, its limit binds instead.
    let as_binds = machine_share().is_some_and(|m| m > (SIX_GB_KIB * 1024) as f64);
    for args in [
        vec!["run", "poiseuille", "--set", "domain.nx=2000", "--backend", "cpu", "--steps", "1", "--out", out_s],
        vec!["run", "sessile-90", "--set", "domain.y=[0,1000]", "--out", out_s],
    ] {
        let o = sphlab_under(Some(SIX_GB_KIB), &args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(e.contains("resource plan: ") && e.contains(" bytes (") && !e.contains("panicked"), "{args:?}: {e}");
        if as_binds {
            assert!(
                e.contains("exceed the address-space limit (RLIMIT_AS) of ")
                    && e.contains("soft limit 6144000000 bytes"),
                "{args:?}: {e}"
            );
        }
        assert!(!Path::new(&out).exists(), "{args:?}: no output directory for a refused run");
    }
}

#[test]
fn a_small_address_space_limit_binds_and_is_named() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    // 400,000 particles plan about 500 MB; 512 MiB of address space leaves less than that once
    // the program and its threads are mapped.
    let args = ["run", "poiseuille", "--set", "domain.nx=400", "--steps", "1", "--out", out.to_str().expect("utf8")];
    let o = sphlab_under(Some(512 << 10), &args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("exceed the address-space limit (RLIMIT_AS) of ")
            && e.contains("soft limit 536870912 bytes")
            && e.contains("the process already maps"),
        "{e}"
    );
    assert!(!out.exists());
    // `--max-memory` below it binds instead; above it, the address space still does.
    let o = sphlab_under(Some(512 << 10), &[&args[..], &["--max-memory", "64M"]].concat());
    assert!(
        o.status.code() == Some(2) && stderr(&o).contains("exceed the --max-memory of 67108864 bytes"),
        "{}",
        stderr(&o)
    );
    let o = sphlab_under(Some(512 << 10), &[&args[..], &["--max-memory", "100G"]].concat());
    assert!(o.status.code() == Some(2) && stderr(&o).contains("(RLIMIT_AS)"), "{}", stderr(&o));
}

#[test]
fn the_plan_in_summary_json_lists_the_output_and_diagnostic_buffers() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    let args = ["run", "sessile-90", "--steps", "2", "--vtk", "--quiet", "--out", out.to_str().expect("utf8")];
    let o = sphlab_under(Some(SIX_GB_KIB), &args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
    let plan = &v["plan"];
    let host = plan["host"].as_array().expect("host buffers");
    let has = |part: &str, name: &str| {
        host.iter().any(|b| {
            b["part"] == part && b["name"].as_str().is_some_and(|n| n.contains(name)) && b["bytes"].as_f64() > Some(0.0)
        })
    };
    assert!(has("outputs", "read-back frame") && has("outputs", "VTK text"), "{host:?}");
    assert!(has("diagnostics", "contact-angle gas grid"), "{host:?}");
    assert!(has("solver", "particle state") && has("neighbours", "neighbour lists"), "{host:?}");
    let sum: f64 = host.iter().map(|b| b["bytes"].as_f64().expect("bytes")).sum();
    let total = plan["total_bytes"].as_f64().expect("total");
    assert!(total > sum && plan["diagnostic_bytes"].as_f64() > Some(0.0), "{plan}");
    // The limits the run was admitted under: every one found, the address space among them.
    let limits = &v["options"]["limits"];
    let found = limits["memory_limits"].as_array().expect("memory limits");
    assert!(found.iter().any(|l| l["source"] == "address-space limit (RLIMIT_AS)"), "{limits}");
    assert!(limits["max_memory"].as_f64() >= Some(total), "{limits}");
}

#[test]
fn an_output_failing_mid_run_closes_the_outputs_with_status_failed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    // The first snapshot's file name is taken by a directory: the run starts, writes its summary
    // and the t = 0 series row, then cannot write the snapshot.
    std::fs::create_dir_all(out.join("particles_00000000.csv")).expect("mkdir");
    let o = sphlab_under(None, &["run", "sessile-90", "--steps", "2", "--quiet", "--out", out.to_str().expect("utf8")]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("particles_00000000.csv") && !e.contains("panicked"), "{e}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
    assert_eq!(v["status"], "failed", "{v}");
    assert!(v["error"].as_str().is_some_and(|m| m.contains("particles_00000000.csv")), "{}", v["error"]);
    let series = std::fs::read_to_string(out.join("series.csv")).expect("series");
    assert_eq!(series.lines().count(), 2, "header and the t = 0 row: {series}");
}
