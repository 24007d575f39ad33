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

/// Most lines of a file in `src/` or `core/src/`.
const MAX_FILE_LINES: usize = 500;
/// Most lines of a function, from its `fn` line to its closing brace.
const MAX_FN_LINES: usize = 120;
/// Most lines of the binary's `main.rs`.
const MAX_MAIN_LINES: usize = 100;

/// The code of a line with string and char literals and comments removed; `raw` carries an
/// open raw string's terminator and `open` an open ordinary string across lines.
fn code_of(line: &str, raw: &mut Option<String>, open: &mut bool) -> String {
    let b: Vec<char> = line.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < b.len() {
        if let Some(end) = raw.as_deref() {
            let rest: String = b[i..].iter().collect();
            match rest.find(end) {
                Some(k) => {
                    i += rest[..k].chars().count() + end.chars().count();
                    *raw = None;
                }
                None => return out,
            }
            continue;
        }
        if *open {
            match b[i] {
                '\\' => i += 2,
                '"' => {
                    *open = false;
                    i += 1;
                }
                _ => i += 1,
            }
            continue;
        }
        let c = b[i];
        if c == '/' && b.get(i + 1) == Some(&'/') {
            break;
        }
        if c == 'r' && (i == 0 || !b[i - 1].is_alphanumeric()) {
            let hashes = b[i + 1..].iter().take_while(|&&h| h == '#').count();
            if b.get(i + 1 + hashes) == Some(&'"') {
                *raw = Some(format!("\"{}", "#".repeat(hashes)));
                i += hashes + 2;
                continue;
            }
        }
        if c == '"' {
            *open = true;
            i += 1;
            continue;
        }
        if c == '\'' {
            // A char literal ('x', '\n', '{'); a lifetime has no closing quote two or three on.
            if b.get(i + 2) == Some(&'\'') {
                i += 3;
                continue;
            }
            if b.get(i + 1) == Some(&'\\') {
                if let Some(k) = b[i + 2..].iter().position(|&q| q == '\'') {
                    i += k + 3;
                    continue;
                }
            }
        }
        out.push(c);
        i += 1;
    }
    out
}

/// The name of the function a line of code declares (`[pub[(…)]] [const] [async] [unsafe]
/// [extern "C"] fn name`), if it does.
fn fn_name(code: &str) -> Option<String> {
    let mut rest = code.trim_start();
    if let Some(r) = rest.strip_prefix("pub") {
        rest = r.trim_start();
        if rest.starts_with('(') {
            rest = rest[rest.find(')')? + 1..].trim_start();
        }
    }
    for q in ["const ", "async ", "unsafe ", "extern \"C\" "] {
        rest = rest.strip_prefix(q).unwrap_or(rest).trim_start();
    }
    let name = rest.strip_prefix("fn ")?.trim_start();
    let end = name.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(name.len());
    (end > 0).then(|| name[..end].to_string())
}

/// (name, first line, length) of every function of `text` longer than `max` lines.
fn long_functions(text: &str, max: usize) -> Vec<(String, usize, usize)> {
    let (mut raw, mut open) = (None, false);
    let mut stack: Vec<(String, usize, usize)> = Vec::new();
    let (mut depth, mut pending, mut out) = (0usize, None::<(String, usize)>, Vec::new());
    for (n, line) in text.lines().enumerate() {
        let code = code_of(line, &mut raw, &mut open);
        if let Some(name) = fn_name(&code) {
            pending = Some((name, n + 1));
        }
        for ch in code.chars() {
            match ch {
                '{' => {
                    depth += 1;
                    if let Some((name, start)) = pending.take() {
                        stack.push((name, start, depth));
                    }
                }
                '}' => {
                    if stack.last().is_some_and(|s| s.2 == depth) {
                        let (name, start, _) = stack.pop().unwrap();
                        let len = n + 1 - start + 1;
                        if len > max {
                            out.push((name, start, len));
                        }
                    }
                    depth = depth.saturating_sub(1);
                }
                ';' => pending = None,
                _ => {}
            }
        }
    }
    out
}

#[test]
fn files_and_functions_are_small_enough_to_read_at_once() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("core/src"), &mut files);
    let mut too_big = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let rel = f.strip_prefix(root).unwrap().display().to_string();
        let lines = text.lines().count();
        if lines > MAX_FILE_LINES {
            too_big.push(format!("{rel}: {lines} lines"));
        }
        for (name, start, len) in long_functions(&text, MAX_FN_LINES) {
            too_big.push(format!("{rel}:{start}: fn {name}, {len} lines"));
        }
        assert!(text.starts_with("//!"), "{rel} has no `//!` header");
        for (k, _) in text.match_indices("allow(") {
            let attribute = text[..k].ends_with("#[") || text[..k].ends_with("#![");
            let end = text[k..].find(")]").map_or(text.len(), |e| k + e);
            assert!(!attribute || text[k..end].contains("reason = "), "{rel}: `{}` has no reason", &text[k..end]);
        }
    }
    assert!(too_big.is_empty(), "over {MAX_FILE_LINES} lines a file or {MAX_FN_LINES} a function: {too_big:#?}");
    let main = std::fs::read_to_string(root.join("src/main.rs")).unwrap().lines().count();
    assert!(main < MAX_MAIN_LINES, "src/main.rs has {main} lines");
}

#[test]
fn the_size_scan_counts_functions_and_skips_braces_in_literals_and_comments() {
    let body = "    let s = \"{{{\"; // }}}\n    let c = '{';\n    let r = r#\"}\"#;\n".repeat(3);
    let text = format!("pub(crate) fn short() {{\n{body}}}\n\nfn nested() {{\n    let f = |x: u32| {{ x }};\n    fn inner() {{}}\n}}\n");
    let all = long_functions(&text, 0);
    let names: Vec<(&str, usize, usize)> = all.iter().map(|(n, s, l)| (n.as_str(), *s, *l)).collect();
    assert_eq!(names, [("short", 1, 11), ("inner", 15, 1), ("nested", 13, 4)]);
    assert_eq!(fn_name("    pub(in crate::gpu) fn record_step(&self) {").as_deref(), Some("record_step"));
    assert_eq!(fn_name("let f = fn_name(x);"), None);
    assert!(long_functions(&text, 11).is_empty());
}
