//! The import rules of the two wings, checked on the sources and manifests: the solver core
//! (`core/`, crate `sphlab-core`) depends on no lab crate, so the compiler keeps it from the lab;
//! inside the core the CPU and GPU executors import neither each other nor the factory that
//! builds both (`backend_id`); they share only the backend API, the search vocabulary and the
//! physics.

use std::path::{Path, PathBuf};

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

fn core_files(module: &str) -> Vec<PathBuf> {
    let mut files = Vec::new();
    rust_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("core/src").join(module), &mut files);
    assert!(!files.is_empty(), "core/src/{module}");
    files
}

fn module(path: &str) -> &str {
    path.trim_start_matches("crate::").split("::").next().unwrap_or("")
}

/// The `[dependencies]` table's keys of a manifest.
fn dependencies(manifest: &str) -> Vec<String> {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(manifest)).unwrap();
    let mut out = Vec::new();
    let mut inside = false;
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == "[dependencies]";
        } else if inside && !line.is_empty() && !line.starts_with('#') {
            out.push(line.split('=').next().unwrap().trim().to_string());
        }
    }
    out
}

#[test]
fn the_core_depends_on_no_lab_crate_and_the_lab_on_the_core() {
    let core = dependencies("core/Cargo.toml");
    assert!(core.contains(&"wgpu".to_string()), "{core:?}");
    let lab_only = [
        "sphlab",
        "clap",
        "csv",
        "plotters",
        "serde_json",
        "indicatif",
        "ctrlc",
        "signal-hook",
        "sha2",
        "tar",
        "flate2",
    ];
    let bad: Vec<&String> = core.iter().filter(|d| lab_only.contains(&d.as_str())).collect();
    assert!(bad.is_empty(), "the core depends on the lab or its tools: {bad:?}");
    assert!(dependencies("Cargo.toml").contains(&"sphlab-core".to_string()));
    // No source folder of the lab's modules is left inside the core, nor the reverse.
    for lab in ["run.rs", "verify.rs", "study", "validate", "stability", "output", "diagnostics", "plot.rs"] {
        assert!(!Path::new(env!("CARGO_MANIFEST_DIR")).join("core/src").join(lab).exists(), "{lab} in the core");
    }
    for solver in ["cpu", "gpu", "physics", "neighbours", "scene", "stage.rs", "backend.rs"] {
        assert!(!Path::new(env!("CARGO_MANIFEST_DIR")).join("src").join(solver).exists(), "{solver} in the lab");
    }
}

#[test]
fn the_cpu_and_gpu_executors_import_neither_each_other_nor_the_factory() {
    for (from, banned) in [("cpu", ["gpu", "backend_id"]), ("gpu", ["cpu", "backend_id"])] {
        let bad: Vec<_> =
            crate_paths(&core_files(from)).into_iter().filter(|(_, p)| banned.contains(&module(p))).collect();
        assert!(bad.is_empty(), "{from} imports {bad:?}");
    }
    // The backend API is what both implement; it names neither.
    let api: Vec<_> = crate_paths(&core_files("backend.rs"))
        .into_iter()
        .filter(|(_, p)| ["cpu", "gpu", "backend_id"].contains(&module(p)))
        .collect();
    assert!(api.is_empty(), "{api:?}");
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
