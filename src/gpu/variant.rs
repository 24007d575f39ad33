//! GPU variant ids (STUDY.md): search × mapping × accumulation × kernel values × precision,
//! written `"{search}.{mapping}[.{accum}].{kernel_values}.{precision}"`, e.g.
//! `cells.thread.recomputed.f32` or `tracking.block-atomic.fixed.cached.f32`. [`VariantSpec::all`]
//! lists every combination that makes sense (an accumulation only for the block mappings);
//! [`VariantSpec::support`] says why an adapter cannot run one.

use super::GpuContext;
use std::fmt;
use std::str::FromStr;

/// Neighbour search.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SearchVariant {
    /// Every particle under every image code.
    Direct,
    /// Cell grid by counting sort, rebuilt every evaluation.
    Cells,
    /// Tracking lists (candidates kept between evaluations).
    Tracking,
}

/// Work mapping of the neighbour sums.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mapping {
    /// One thread per particle, sequential gather (no atomics in the sums).
    Thread,
    /// One workgroup per particle, atomic accumulation.
    BlockAtomic,
    /// One workgroup per particle, tree reduction in workgroup memory.
    BlockTree,
}

/// How the block mappings accumulate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Accumulation {
    /// No accumulation across threads (thread mapping).
    None,
    /// Compare-and-swap loop on float bits.
    Cas,
    /// Native `atomic<f32>` add (SHADER_FLOAT32_ATOMIC).
    Native,
    /// Fixed-point integer atomics.
    Fixed,
}

/// Kernel values: recomputed in every stage or cached per neighbour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KernelValues {
    /// Recomputed from distances in every stage.
    Recomputed,
    /// Cached per neighbour pair once per evaluation.
    Cached,
}

/// Storage and arithmetic precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    /// f32.
    F32,
    /// f64 (SHADER_F64).
    F64,
}

/// One GPU variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VariantSpec {
    /// Neighbour search.
    pub search: SearchVariant,
    /// Work mapping.
    pub mapping: Mapping,
    /// Accumulation (`None` exactly for the thread mapping).
    pub accumulation: Accumulation,
    /// Kernel values.
    pub kernel_values: KernelValues,
    /// Precision.
    pub precision: Precision,
}

macro_rules! names {
    ($t:ty { $($v:ident = $s:literal),* }) => {
        impl $t {
            /// Every value.
            pub const ALL: &'static [$t] = &[$(<$t>::$v),*];
            /// The id component.
            pub fn name(self) -> &'static str {
                match self { $(<$t>::$v => $s),* }
            }
            fn parse(s: &str) -> Option<Self> {
                match s { $($s => Some(<$t>::$v),)* _ => None }
            }
        }
    };
}
names!(SearchVariant { Direct = "direct", Cells = "cells", Tracking = "tracking" });
names!(Mapping { Thread = "thread", BlockAtomic = "block-atomic", BlockTree = "block-tree" });
names!(Accumulation { None = "none", Cas = "cas", Native = "native", Fixed = "fixed" });
names!(KernelValues { Recomputed = "recomputed", Cached = "cached" });
names!(Precision { F32 = "f32", F64 = "f64" });

impl Default for VariantSpec {
    fn default() -> Self {
        DEFAULT_VARIANT.parse().expect("default id parses")
    }
}

/// The variant `--backend gpu` uses without `--variant`.
pub const DEFAULT_VARIANT: &str = "cells.thread.recomputed.f32";

impl VariantSpec {
    /// True when the accumulation fits the mapping (`none` exactly for `thread`).
    pub fn is_consistent(&self) -> bool {
        (self.mapping == Mapping::Thread) == (self.accumulation == Accumulation::None)
    }

    /// Every variant that makes sense, in a stable order.
    pub fn all() -> Vec<VariantSpec> {
        let mut v = Vec::new();
        for &search in SearchVariant::ALL {
            for &mapping in Mapping::ALL {
                for &accumulation in Accumulation::ALL {
                    for &kernel_values in KernelValues::ALL {
                        for &precision in Precision::ALL {
                            let s = VariantSpec { search, mapping, accumulation, kernel_values, precision };
                            if s.is_consistent() {
                                v.push(s);
                            }
                        }
                    }
                }
            }
        }
        v
    }

    /// Every id, comma separated (for error messages).
    pub fn all_ids() -> String {
        Self::all().iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")
    }

    /// `Err(reason)` when the adapter lacks a feature this variant needs.
    pub fn support(&self, ctx: &GpuContext) -> Result<(), String> {
        if self.precision == Precision::F64 && !ctx.has(wgpu::Features::SHADER_F64) {
            return Err(format!("{self}: the adapter lacks SHADER_F64"));
        }
        if self.accumulation == Accumulation::Native && !ctx.has(wgpu::Features::SHADER_FLOAT32_ATOMIC) {
            return Err(format!("{self}: the adapter lacks SHADER_FLOAT32_ATOMIC"));
        }
        Ok(())
    }

    /// `Err(reason)` when this build has no implementation of the variant.
    pub fn implemented(&self) -> Result<(), String> {
        let ok = self.mapping == Mapping::Thread
            && self.search != SearchVariant::Tracking
            && self.kernel_values == KernelValues::Recomputed;
        if ok {
            Ok(())
        } else {
            Err(format!(
                "not implemented in this build: {self} (implemented: {{direct, cells}}.thread.recomputed.{{f32, f64}})"
            ))
        }
    }
}

impl fmt::Display for VariantSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.search.name(), self.mapping.name())?;
        if self.accumulation != Accumulation::None {
            write!(f, ".{}", self.accumulation.name())?;
        }
        write!(f, ".{}.{}", self.kernel_values.name(), self.precision.name())
    }
}

impl FromStr for VariantSpec {
    type Err = String;
    fn from_str(id: &str) -> Result<Self, String> {
        let bad = || format!("unknown GPU variant `{id}`; valid ids: {}", VariantSpec::all_ids());
        let parts: Vec<&str> = id.split('.').collect();
        let (s, m, a, k, p) = match parts.as_slice() {
            [s, m, k, p] => (*s, *m, "none", *k, *p),
            [s, m, a, k, p] if *a != "none" => (*s, *m, *a, *k, *p),
            _ => return Err(bad()),
        };
        let spec = VariantSpec {
            search: SearchVariant::parse(s).ok_or_else(bad)?,
            mapping: Mapping::parse(m).ok_or_else(bad)?,
            accumulation: Accumulation::parse(a).ok_or_else(bad)?,
            kernel_values: KernelValues::parse(k).ok_or_else(bad)?,
            precision: Precision::parse(p).ok_or_else(bad)?,
        };
        if !spec.is_consistent() {
            return Err(bad());
        }
        Ok(spec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_round_trip() {
        let all = VariantSpec::all();
        assert_eq!(all.len(), 3 * 2 * 2 + 3 * 2 * 3 * 2 * 2);
        for s in &all {
            assert_eq!(s.to_string().parse::<VariantSpec>().unwrap(), *s, "{s}");
        }
        assert_eq!(VariantSpec::default().to_string(), DEFAULT_VARIANT);
        assert!("tracking.block-atomic.fixed.cached.f32".parse::<VariantSpec>().is_ok());
        for bad in ["cells.thread.cas.recomputed.f32", "cells.block-tree.recomputed.f32", "x", "cells.thread.none.recomputed.f32"] {
            assert!(bad.parse::<VariantSpec>().is_err(), "{bad}");
        }
    }
}
