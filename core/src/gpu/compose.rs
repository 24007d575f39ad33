//! The tiny WGSL preprocessor that composes the GPU variants from shared files.
//!
//! Directives (a line whose first non-blank character is `#`):
//! * `#import name`: pastes `shaders/name.wgsl` (`#import common/x`: `kernels-variants/common/x.wgsl`) once (de-duplicated over the whole composition,
//!   transitive; a cycle is harmless because a file is marked before it is expanded);
//! * `#ifdef X` / `#ifndef X` / `#else` / `#endif`: keep or drop lines by the define set.
//!
//! Every composition starts with the precision prelude: `alias real = f32; alias real2 =
//! vec2<f32>;`, or `f64` when the define `F64` is set, so the shared files are written once in
//! `real`/`real2` with `real(…)` literals. All files are embedded with `include_str!` (the tables
//! come from build.rs's folder scan: a new file needs no Rust edit), so the binary needs no
//! `shaders/` directory at run time. Errors name the original file and line;
//! [`Composed::locate`] maps a line of the flattened source back to its file and line, which is
//! how [`validate`] reports naga errors.

use super::GpuError;
use std::collections::HashSet;

/// The define that switches `real` to `f64`.
pub const F64: &str = "F64";

// `SHADERS` (every importable shared module of `shaders/`, by name without `.wgsl`) and
// `VARIANT_FILES` (every file of `kernels-variants/`, by path relative to that folder): found by
// the folder scan of build.rs (`shader_files`), each source embedded with `include_str!`.
include!(concat!(env!("OUT_DIR"), "/shader_files.rs"));

/// The source of a shared module by import name (`kernel`, `kernel.wgsl` or `shaders/kernel.wgsl`).
pub fn shader_source(name: &str) -> Option<&'static str> {
    let name = name.trim_start_matches("shaders/").trim_end_matches(".wgsl");
    SHADERS.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// A flattened WGSL module and, for each of its lines, the file and line it came from.
#[derive(Clone, Debug)]
pub struct Composed {
    /// The flat WGSL source, ready for `create_shader_module` or naga.
    pub source: String,
    /// `origin[k]` = (file, 1-based line) of flat line `k + 1`.
    pub origin: Vec<(String, usize)>,
}

impl Composed {
    /// File and line of the 1-based flat line `line` (`("<prelude>", n)` for the prelude).
    pub fn locate(&self, line: usize) -> (String, usize) {
        self.origin.get(line.wrapping_sub(1)).cloned().unwrap_or_else(|| ("<composed>".to_string(), line))
    }

    fn push(&mut self, file: &str, line: usize, text: &str) {
        self.source.push_str(text);
        self.source.push('\n');
        self.origin.push((file.to_string(), line));
    }
}

/// Composes `entry_source` (an entry-point file or test kernel) with its imports.
pub fn compose(entry_source: &str, defines: &[&str]) -> Result<String, GpuError> {
    compose_mapped("<entry>", entry_source, defines).map(|c| c.source)
}

/// Composes a file of `kernels-variants/` by its path relative to that folder.
pub fn compose_variant(path: &str, defines: &[&str]) -> Result<String, GpuError> {
    compose_variant_mapped(path, defines).map(|c| c.source)
}

/// [`compose_variant`] keeping the line origins.
pub fn compose_variant_mapped(path: &str, defines: &[&str]) -> Result<Composed, GpuError> {
    let path = path.trim_start_matches("kernels-variants/");
    let src =
        VARIANT_FILES.iter().find(|(p, _)| *p == path).map(|(_, s)| *s).ok_or_else(|| GpuError::ShaderCompose {
            file: format!("kernels-variants/{path}"),
            line: 0,
            msg: "no such embedded variant file".into(),
        })?;
    compose_mapped(&format!("kernels-variants/{path}"), src, defines)
}

/// Composes `entry_source` (named `file` in errors) and keeps the line origins.
pub fn compose_mapped(file: &str, entry_source: &str, defines: &[&str]) -> Result<Composed, GpuError> {
    let mut out = Composed { source: String::new(), origin: Vec::new() };
    let ty = if defines.contains(&F64) { "f64" } else { "f32" };
    out.push("<prelude>", 1, "// sphlab composed WGSL; precision prelude:");
    out.push("<prelude>", 2, &format!("alias real = {ty};"));
    out.push("<prelude>", 3, &format!("alias real2 = vec2<{ty}>;"));
    let mut seen = HashSet::new();
    expand(file, entry_source, defines, &mut seen, &mut out)?;
    Ok(out)
}

/// One open `#ifdef`: where it was, whether its branch is kept, whether `#else` was seen.
struct Cond {
    line: usize,
    keep: bool,
    parent_keep: bool,
    in_else: bool,
}

fn expand(
    file: &str,
    src: &str,
    defines: &[&str],
    seen: &mut HashSet<String>,
    out: &mut Composed,
) -> Result<(), GpuError> {
    let err = |line: usize, msg: String| GpuError::ShaderCompose { file: file.to_string(), line, msg };
    let mut stack: Vec<Cond> = Vec::new();
    for (k, text) in src.lines().enumerate() {
        let line = k + 1;
        let active = stack.last().is_none_or(|c| c.keep);
        let trimmed = text.trim_start();
        if !trimmed.starts_with('#') {
            if active {
                out.push(file, line, text);
            }
            continue;
        }
        let mut words = trimmed[1..].split_whitespace();
        let directive = words.next().unwrap_or("");
        let arg = words.next();
        if words.next().is_some() {
            return Err(err(line, format!("too many arguments to `#{directive}`")));
        }
        match (directive, arg) {
            ("import", Some(name)) => {
                if !active {
                    continue;
                }
                let name = name.trim_matches('"');
                let key = name.trim_start_matches("shaders/").trim_end_matches(".wgsl");
                // `common/x` names a shared file of kernels-variants/ (one that may hold the
                // bindings of the solver stages, which shaders/ modules must not).
                let (body, path) = if let Some(rest) = key.strip_prefix("common/") {
                    let p = format!("common/{rest}.wgsl");
                    let body = VARIANT_FILES.iter().find(|(f, _)| *f == p).map(|(_, s)| *s);
                    (body, format!("kernels-variants/{p}"))
                } else {
                    (shader_source(key), format!("shaders/{key}.wgsl"))
                };
                let Some(body) = body else {
                    return Err(err(
                        line,
                        format!("unknown import `{name}` (not in shaders/ or kernels-variants/common/)"),
                    ));
                };
                if seen.insert(key.to_string()) {
                    expand(&path, body, defines, seen, out)?;
                }
            }
            ("ifdef" | "ifndef", Some(name)) => {
                let set = defines.contains(&name);
                let cond = if directive == "ifdef" { set } else { !set };
                stack.push(Cond { line, keep: active && cond, parent_keep: active, in_else: false });
            }
            ("else", None) => match stack.last_mut() {
                Some(c) if !c.in_else => {
                    c.in_else = true;
                    c.keep = c.parent_keep && !c.keep;
                }
                Some(_) => return Err(err(line, "second `#else` for one `#ifdef`".into())),
                None => return Err(err(line, "`#else` without `#ifdef`".into())),
            },
            ("endif", None) => {
                if stack.pop().is_none() {
                    return Err(err(line, "`#endif` without `#ifdef`".into()));
                }
            }
            _ => return Err(err(line, format!("unknown or malformed directive `{}`", trimmed.trim_end()))),
        }
    }
    if let Some(c) = stack.last() {
        return Err(err(c.line, "`#ifdef` is never closed by `#endif`".into()));
    }
    Ok(())
}

/// Parses and validates a composition with naga (all capabilities, as the GPU tests request
/// every optional feature); errors are mapped back to the original file and line.
pub fn validate(composed: &Composed) -> Result<wgpu::naga::Module, GpuError> {
    use wgpu::naga::{front::wgsl, valid};
    let src = &composed.source;
    let at = |loc: Option<wgpu::naga::SourceLocation>, msg: String| {
        let (file, line) = loc.map_or(("<composed>".to_string(), 0), |l| composed.locate(l.line_number as usize));
        GpuError::ShaderCompose { file, line, msg }
    };
    let module = wgsl::parse_str(src).map_err(|e| at(e.location(src), e.emit_to_string(src)))?;
    let mut v = valid::Validator::new(valid::ValidationFlags::all(), valid::Capabilities::all());
    v.validate(&module).map_err(|e| at(e.location(src), e.emit_to_string(src)))?;
    Ok(module)
}
