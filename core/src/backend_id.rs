//! [`BackendId`], the one typed id of a backend (`cpu1.cells.f64`, `cpu.tracking.f32`,
//! `tracking.thread.recomputed.f32`, …) that the CLI parses once and `run`, `verify`, `study`,
//! `stability`, the bench and `records.csv` use, and the factory that builds the backend it names
//! ([`BackendId::build`]): the one module that knows both executors.

use crate::backend::Backend;
use crate::cpu::CpuSolver;
use crate::exec::Exec;
use crate::gpu::variant::{VariantSpec, DEFAULT_VARIANT};
use crate::gpu::GpuContext;
use crate::neighbours::SearchKind;
use crate::real::Precision;
use crate::scene::build::Layout;
use crate::scene::Scene;
use serde::Serialize;
use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

/// A backend: the CPU reference (execution, neighbour search, precision), written
/// `{cpu|cpu1}.{search}.{precision}`, or a GPU variant, written as its [`VariantSpec`] id.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackendId {
    /// The CPU reference.
    Cpu {
        /// All cores (`cpu`) or one thread (`cpu1`).
        exec: Exec,
        /// Neighbour search.
        search: SearchKind,
        /// Working precision.
        precision: Precision,
    },
    /// A GPU variant.
    Gpu(VariantSpec),
}

impl Default for BackendId {
    fn default() -> Self {
        BackendId::Cpu { exec: Exec::Parallel, search: SearchKind::Cells, precision: Precision::F64 }
    }
}

impl fmt::Display for BackendId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BackendId::Cpu { exec, search, precision } => {
                write!(f, "{}.{}.{}", exec.name(), search.name(), precision.name())
            }
            BackendId::Gpu(spec) => write!(f, "{spec}"),
        }
    }
}

impl FromStr for BackendId {
    type Err = String;
    /// Parses an id; a GPU id must name an implemented variant.
    fn from_str(id: &str) -> Result<Self, String> {
        let parts: Vec<&str> = id.split('.').collect();
        let exec = match parts[0] {
            "cpu" => Some(Exec::Parallel),
            "cpu1" => Some(Exec::Serial),
            _ => None,
        };
        let Some(exec) = exec else {
            return id.parse::<VariantSpec>().map(BackendId::Gpu);
        };
        let bad = || format!("unknown CPU backend `{id}`: {{cpu|cpu1}}.{{direct|cells|tracking}}.{{f64|f32}}");
        let [_, search, precision] = parts.as_slice() else { return Err(bad()) };
        let search = SearchKind::parse(search).ok_or_else(bad)?;
        let precision = Precision::parse(precision).ok_or_else(bad)?;
        Ok(BackendId::Cpu { exec, search, precision })
    }
}

impl Serialize for BackendId {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl BackendId {
    /// The backend of the command-line options: `--backend` is `cpu`, `cpu1`, `gpu` or a full
    /// id; `--variant` (a GPU variant id, default [`DEFAULT_VARIANT`]) applies only to `gpu`;
    /// `--precision` and `--search` (defaults f64, cells) only to `cpu`/`cpu1`. Each option is
    /// `Some` only when the user gave it: one that does not apply is an error, never ignored.
    /// The variant is the id as given: whether it applies is said before whether it parses.
    pub fn from_cli(
        backend: &str,
        variant: Option<&str>,
        precision: Option<Precision>,
        search: Option<SearchKind>,
    ) -> Result<Self, String> {
        let not_cpu = |what: &str, v: &dyn fmt::Display| {
            format!(
                "--{what} {v}: applies only to --backend cpu or cpu1 (a full id or a GPU variant id carries its own)"
            )
        };
        let exec = match backend {
            "cpu" => Exec::Parallel,
            "cpu1" => Exec::Serial,
            _ if backend == "gpu" || backend.contains('.') => {
                if let Some(p) = precision {
                    return Err(not_cpu("precision", &p));
                }
                if let Some(k) = search {
                    return Err(not_cpu("search", &k));
                }
                if backend == "gpu" {
                    let id = variant.unwrap_or(DEFAULT_VARIANT);
                    return id.parse::<VariantSpec>().map(BackendId::Gpu).map_err(|e| format!("--variant: {e}"));
                }
                if let Some(v) = variant {
                    return Err(format!(
                        "--variant {v}: applies only to --backend gpu (the backend is the full id {backend})"
                    ));
                }
                return backend.parse().map_err(|e| format!("--backend: {e}"));
            }
            other => {
                return Err(format!(
                    "--backend: unknown backend `{other}` (cpu, cpu1, gpu, or a full id such as cpu1.cells.f64 \
                     or {DEFAULT_VARIANT})"
                ))
            }
        };
        if let Some(v) = variant {
            return Err(format!("--variant {v}: applies only to --backend gpu (the backend is {backend})"));
        }
        Ok(BackendId::Cpu {
            exec,
            search: search.unwrap_or(SearchKind::Cells),
            precision: precision.unwrap_or(Precision::F64),
        })
    }

    /// `cpu`, `cpu1` or `gpu`.
    pub fn kind(&self) -> &'static str {
        match self {
            BackendId::Cpu { exec, .. } => exec.name(),
            BackendId::Gpu(_) => "gpu",
        }
    }

    /// The working precision.
    pub fn precision(&self) -> Precision {
        match self {
            BackendId::Cpu { precision, .. } => *precision,
            BackendId::Gpu(spec) => spec.precision,
        }
    }

    /// Builds the backend for `scene`'s `layout`; a GPU backend on `gpu` (a new context when
    /// `None`). Errors say why (no adapter, unsupported variant).
    pub fn build(
        &self,
        scene: &Scene,
        layout: &Layout,
        gpu: Option<&Arc<GpuContext>>,
    ) -> Result<Box<dyn Backend>, String> {
        Ok(match *self {
            BackendId::Cpu { exec, search, precision: Precision::F64 } => {
                Box::new(CpuSolver::<f64>::new(scene, layout, exec, search))
            }
            BackendId::Cpu { exec, search, precision: Precision::F32 } => {
                Box::new(CpuSolver::<f32>::new(scene, layout, exec, search))
            }
            BackendId::Gpu(spec) => {
                let ctx = match gpu {
                    Some(c) => c.clone(),
                    None => Arc::new(GpuContext::new().map_err(|e| format!("{self}: {e}"))?),
                };
                spec.support(&ctx).map_err(|e| format!("unsupported on this adapter: {e}"))?;
                crate::gpu::solver::new_backend(ctx, scene, layout, spec).map_err(|e| e.to_string())?
            }
        })
    }
}
