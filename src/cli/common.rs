//! What several commands share: the backend flags, the typed `--precision` and `--search` parsers, the resource
//! limits' flags, loading a scene with `--set`, the `--out` check, the interrupt handler, the
//! provenance envelope, the GPU context and the `--variants` list.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::Args;
use sphlab::backend_id::BackendId;
use sphlab::error::Error;
use sphlab::gpu::variant::VariantSpec;
use sphlab::gpu::GpuContext;
use sphlab::neighbours::SearchKind;
use sphlab::plan::{parse_bytes, Limits};
use sphlab::provenance::Provenance;
use sphlab::real::Precision;
use sphlab::scene::{builtin, overrides::apply_overrides, Scene};
use std::path::Path;
use std::sync::Arc;

/// The backend flags `run` and `validate` share, turned into one [`BackendId`].
#[derive(Args)]
pub struct BackendArgs {
    /// cpu (all cores), cpu1 (one thread), gpu, or a full id (cpu1.cells.f64, a GPU variant id).
    #[arg(long, default_value = "cpu")]
    backend: String,
    /// GPU variant id (see `sphlab variants`); only with --backend gpu.
    #[arg(long)]
    variant: Option<String>,
    /// Precision of the CPU backends (default f64); a GPU variant's is part of its id.
    #[arg(long, value_parser = precision_parser())]
    precision: Option<Precision>,
}

impl BackendArgs {
    /// The backend these flags and `search` (`--search`, where the command has it) name.
    pub fn id(&self, search: Option<SearchKind>) -> Result<BackendId, Error> {
        BackendId::from_cli(&self.backend, self.variant.as_deref(), self.precision, search).map_err(Error::Input)
    }
}

/// `--precision`: `f64` or `f32`, parsed into [`Precision`].
pub fn precision_parser() -> impl TypedValueParser<Value = Precision> {
    PossibleValuesParser::new([Precision::F64.name(), Precision::F32.name()])
        .map(|s| s.parse::<Precision>().expect("a possible value parses"))
}

/// `--search`: `direct`, `cells` or `tracking`, parsed into [`SearchKind`].
pub fn search_parser() -> impl TypedValueParser<Value = SearchKind> {
    PossibleValuesParser::new([
        PossibleValue::new(SearchKind::Direct.name()).help("All pairs, O(N²)"),
        PossibleValue::new(SearchKind::Cells.name()).help("Uniform cell grid rebuilt every evaluation"),
        PossibleValue::new(SearchKind::Tracking.name()).help("Tracking lists with a skin (thesis §6.3)"),
    ])
    .map(|s| s.parse::<SearchKind>().expect("a possible value parses"))
}

/// `--max-particles` and `--max-memory`: the limits of the resource plan.
#[derive(Args)]
pub struct LimitArgs {
    /// Refuse scenes of more particles (fluid + wall) than this (default and most: 2^28 − 1).
    #[arg(long)]
    max_particles: Option<u64>,
    /// Refuse scenes whose planned host memory exceeds this (e.g. 4G, 512M); the machine's
    /// limits apply too (80% of MemAvailable, ulimit -v, the cgroup's memory.max): the smallest binds.
    #[arg(long, value_parser = parse_bytes)]
    max_memory: Option<u64>,
    /// Device memory of the GPU for its memory plan (e.g. 80G; default: host memory on a CPU
    /// adapter such as lavapipe, else unknown and only the per-buffer limits are checked).
    #[arg(long, value_parser = parse_bytes)]
    gpu_memory: Option<u64>,
    /// Run as on an adapter whose per-buffer limit is at most this (e.g. 256K, 2G): list slots
    /// past it are split into chunks as on a run of many millions of particles (at least 64K;
    /// default: the adapter's own limit).
    #[arg(long, value_parser = parse_bytes)]
    gpu_binding: Option<u64>,
}

impl LimitArgs {
    /// The limits; a bad one is bad input.
    pub fn limits(&self) -> Result<Limits, Error> {
        Limits::with(self.max_particles, self.max_memory)
            .and_then(|l| l.with_gpu_memory(self.gpu_memory))
            .and_then(|l| l.with_gpu_binding(self.gpu_binding))
            .map_err(Error::Input)
    }
}

/// Loads a scene by built-in name or TOML path, then applies `--set` overrides; any failure is
/// bad input.
pub fn load_scene(name: &str, sets: &[String]) -> Result<Scene, Error> {
    let base = if let Some(s) = builtin::builtin(name) {
        s
    } else if Path::new(name).is_file() {
        let text =
            std::fs::read_to_string(name).map_err(|e| Error::input(format!("cannot read scene file {name}: {e}")))?;
        Scene::from_toml(&text).map_err(|e| Error::input(format!("{name}: {e}")))?
    } else if Path::new(name).exists() {
        return Err(Error::input(format!("scene `{name}` is not a regular file")));
    } else {
        return Err(Error::input(format!(
            "unknown scene `{name}`: not a built-in ({}) and no such file",
            builtin::BUILTIN.join(", ")
        )));
    };
    apply_overrides(&base, sets).map_err(Error::input)
}

/// `--out DIR` (or another output option `opt`) checked before anything else happens: bad input
/// naming the option.
pub fn check_out(opt: &str, dir: &Path) -> Result<(), Error> {
    sphlab::output::check_out_dir(dir).map_err(|e| Error::input(format!("{opt}: {e}")))
}

/// Ctrl-C asks the running simulation to stop after its current step (final snapshot, summary
/// `interrupted`, exit 130); a second Ctrl-C exits at once. The `ctrlc` crate does this
/// portably in a few lines (a dedicated handler thread, no unsafe code here).
pub fn install_interrupt_handler() {
    let _ = ctrlc::set_handler(|| {
        if sphlab::run::request_interrupt() {
            std::process::exit(130);
        }
        eprintln!("\ninterrupt: stopping after this step (Ctrl-C again to quit at once)");
    });
}

/// A JSON value with the provenance envelope added: objects get a `provenance` key, anything
/// else becomes `{"provenance": …, "result": …}`.
pub fn with_provenance(v: serde_json::Value, prov: &Provenance) -> serde_json::Value {
    let p = serde_json::to_value(prov).expect("provenance serialises");
    match v {
        serde_json::Value::Object(mut m) => {
            m.insert("provenance".into(), p);
            serde_json::Value::Object(m)
        }
        other => serde_json::json!({ "provenance": p, "result": other }),
    }
}

/// Prints a JSON document, pretty.
pub fn print_json(v: &serde_json::Value) {
    println!("{}", serde_json::to_string_pretty(v).expect("json"));
}

/// The GPU context of this process, or why there is none.
pub fn gpu_context() -> Result<Arc<GpuContext>, String> {
    GpuContext::new().map(Arc::new).map_err(|e| e.to_string())
}

/// GPU variant ids of `--variants` (`all` or comma-separated); a CPU id, a bad id or an empty
/// list is bad input naming the flag.
pub fn gpu_variants(list: &str) -> Result<Vec<VariantSpec>, Error> {
    if list == "all" {
        return Ok(VariantSpec::all());
    }
    let mut v = Vec::new();
    for id in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        match id.parse::<BackendId>() {
            Ok(BackendId::Gpu(s)) => v.push(s),
            Ok(cpu) => return Err(Error::input(format!("--variants: `{cpu}` is a CPU backend, not a GPU variant"))),
            Err(e) => return Err(Error::input(format!("--variants: {e}"))),
        }
    }
    if v.is_empty() {
        return Err(Error::input("--variants: give `all` or at least one variant id"));
    }
    Ok(v)
}
