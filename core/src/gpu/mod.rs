//! The wgpu backend: headless device ([`context`]), WGSL composition ([`compose`]) and typed
//! buffers ([`buffers`]). The GPU physics itself lives in `shaders/*.wgsl` (twins of
//! [`crate::physics`], tested in `tests/wgsl_twins.rs`); the solver ([`solver`]) runs the
//! stages of [`stages`] for a [`variant`].

pub mod bandwidth;
pub(crate) mod buffers;
pub(crate) mod clock;
pub mod compose;
pub(crate) mod context;
pub(crate) mod counters;
pub mod list_chunks;
pub mod mask_lists;
pub mod params;
pub(crate) mod pipeline_cache;
pub mod plan;
pub mod pooled_lists;
mod readback;
pub mod reorder;
pub mod residency;
pub mod solver;
pub mod solver_buffers;
pub mod stages;
pub(crate) mod staging;
pub(crate) mod timing;
pub mod variant;
pub mod variant_buffers;
pub mod walk_probe;

pub use buffers::{GpuVec, Uniform};
pub use compose::{compose, compose_variant, Composed};
pub use context::{gpu_required, GpuContext};
pub use readback::NeighbourView;

/// Everything that can go wrong on the GPU side.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter (no GPU and no software Vulkan such as lavapipe).
    #[error("no GPU adapter: {0}")]
    NoAdapter(String),
    /// The adapter lacks a feature that this operation needs.
    #[error("adapter lacks the feature {0}")]
    MissingFeature(&'static str),
    /// A composition or naga error, located in the original file.
    #[error("{file}:{line}: {msg}")]
    ShaderCompose {
        /// File that holds the faulty line (`shaders/…`, `kernels-variants/…`, `<entry>`).
        file: String,
        /// 1-based line in that file (0 when unknown).
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A wgpu validation error caught by an error scope.
    #[error("wgpu validation: {0}")]
    Validation(String),
    /// Mapping or copying a buffer back failed.
    #[error("readback: {0}")]
    Readback(String),
    /// The variant is not implemented in this build or not supported by the adapter.
    #[error("{0}")]
    Unsupported(String),
    /// The solver detected a condition that invalidates the results (neighbour overflow).
    #[error(transparent)]
    Solver(#[from] crate::backend::SolverError),
    /// A kernel's output differs from the host's computation of it (no time is reported).
    #[error("{0}")]
    Mismatch(String),
    /// A buffer would exceed a device limit.
    #[error("{what}: {bytes} bytes exceeds the device limit of {limit} bytes")]
    TooLarge {
        /// What was being allocated.
        what: String,
        /// Requested size.
        bytes: u64,
        /// The limit it exceeds.
        limit: u64,
    },
}
