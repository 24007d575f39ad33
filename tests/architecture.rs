//! The import rules of the two wings, checked on the source: the solver wing (physics, real,
//! scene, model, stage, fields, neighbours, cpu, gpu, backend, plan, exec) uses nothing of the
//! lab but the byte counts of the lab's buffers that the resource plan adds up (listed below),
//! and inside the solver the CPU and GPU executors do not import each other.

use std::path::{Path, PathBuf};

const SOLVER: [&str; 13] = [
    "physics",
    "real.rs",
    "scene",
    "model.rs",
    "stage.rs",
    "fields.rs",
    "neighbours",
    "cpu",
    "gpu",
    "backend.rs",
    "plan.rs",
    "plan",
    "exec.rs",
];
const LAB: [&str; 13] = [
    "analytic",
    "diagnostics",
    "fallible",
    "forces",
    "output",
    "plot",
    "provenance",
    "run",
    "stability",
    "study",
    "sweep",
    "validate",
    "verify",
];
/// What the solver may name of the lab: (file, path) — the plan counts these buffers' bytes.
const ALLOWED: [(&str, &str); 2] = [
    ("src/plan.rs", "crate::diagnostics::contact_angle::max_bytes"),
    ("src/plan.rs", "crate::output::snapshot::vtk_buffer_bytes"),
];

fn rust_files(p: &Path, out: &mut Vec<PathBuf>) {
    if p.is_dir() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(p).unwrap().map(|e| e.unwrap().path()).collect();
        entries.sort();
        for e in entries {
            rust_files(&e, out);
        }
    } else if p.extension().is_some_and(|x| x == "rs") {
        out.push(p.to_path_buf());
    }
}

/// Every `crate::<module>…` path in the code (comments left out), with the file it is in.
fn crate_paths(files: &[PathBuf]) -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for f in files {
        let rel = f.strip_prefix(root).unwrap_or(f).display().to_string();
        for line in std::fs::read_to_string(f).unwrap().lines() {
            let code = line.split("//").next().unwrap_or("");
            let mut rest = code;
            while let Some(k) = rest.find("crate::") {
                let tail = &rest[k + "crate::".len()..];
                if let Some(group) = tail.strip_prefix('{') {
                    // `use crate::{a::b, c};` names each item of the group.
                    let inner = group.split('}').next().unwrap_or("");
                    out.extend(inner.split(',').map(|i| (rel.clone(), format!("crate::{}", i.trim()))));
                    rest = &group[inner.len()..];
                    continue;
                }
                let end = tail.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':')).unwrap_or(tail.len());
                out.push((rel.clone(), format!("crate::{}", tail[..end].trim_end_matches(':'))));
                rest = &tail[end..];
            }
        }
    }
    out
}

fn solver_files(only: Option<&str>) -> Vec<PathBuf> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for m in SOLVER.iter().filter(|m| only.is_none_or(|o| o == **m)) {
        rust_files(&src.join(m), &mut files);
    }
    assert!(!files.is_empty());
    files
}

fn module(path: &str) -> &str {
    path.trim_start_matches("crate::").split("::").next().unwrap_or("")
}

#[test]
fn the_solver_wing_uses_nothing_of_the_lab_but_the_plans_byte_counts() {
    let bad: Vec<(String, String)> = crate_paths(&solver_files(None))
        .into_iter()
        .filter(|(_, p)| LAB.contains(&module(p)))
        .filter(|(f, p)| !ALLOWED.contains(&(f.as_str(), p.as_str())))
        .collect();
    assert!(bad.is_empty(), "the solver wing imports the lab: {bad:?}");
}

#[test]
fn the_cpu_and_gpu_executors_do_not_import_each_other() {
    let cpu_to_gpu: Vec<_> =
        crate_paths(&solver_files(Some("cpu"))).into_iter().filter(|(_, p)| module(p) == "gpu").collect();
    let gpu_to_cpu: Vec<_> =
        crate_paths(&solver_files(Some("gpu"))).into_iter().filter(|(_, p)| module(p) == "cpu").collect();
    assert!(cpu_to_gpu.is_empty(), "{cpu_to_gpu:?}");
    assert!(gpu_to_cpu.is_empty(), "{gpu_to_cpu:?}");
}

#[test]
fn the_scan_sees_paths_and_groups_and_skips_comments() {
    let d = tempfile::tempdir().unwrap();
    let f = d.path().join("probe.rs");
    let text = "use crate::run::measure; // crate::study::x\nuse crate::{output::write_json, gpu};\nlet a = crate::gpu::variant::VariantSpec::all();\n";
    std::fs::write(&f, text).unwrap();
    let got = crate_paths(std::slice::from_ref(&f));
    let paths: Vec<&str> = got.iter().map(|(_, p)| p.as_str()).collect();
    assert_eq!(
        paths,
        ["crate::run::measure", "crate::output::write_json", "crate::gpu", "crate::gpu::variant::VariantSpec::all"]
    );
    assert_eq!(module(paths[0]), "run");
    assert_eq!(module(paths[1]), "output");
}
