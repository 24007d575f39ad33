//! # sphlab — a GPU-vs-CPU performance laboratory for 2D multiphase SPH
//!
//! The lab around the solver of [`sphlab_core`] (Hu–Adams multiphase SPH with surface tension
//! and contact angles, a CPU reference and wgpu variants): it runs scenes, checks every GPU
//! variant against the CPU reference, times them (the thesis's Chapter 6 study and beyond),
//! maps stability, validates the physics against the thesis and analytic results, and writes
//! the reports. The core's modules are re-exported under their own names, so `sphlab::cpu`
//! is `sphlab_core::cpu`.
//!
//! Module map of the lab:
//! * [`run`]: the `sphlab run` driver and its outputs ([`output`], [`diagnostics`]);
//!   [`resources`]: the lab's buffers in a run's resource plan;
//! * [`verify`]: `sphlab verify`, every GPU variant against the CPU reference (the one
//!   comparison measure and tolerance table, also used by the GPU tests);
//! * [`stability`]: `sphlab stability`, the measured stability map per backend and precision;
//! * [`study`]: `sphlab study`, the Chapter 6 timing study and its report; [`sweep`]: the
//!   `--shard` and `--budget` controls the sweeps share;
//! * [`validate`]: `sphlab validate`, the thesis validation cases and their reports;
//! * [`forces`]: `sphlab forces`, the pair forces of a run folder split by term and partner;
//! * [`analytic`]: analytic drop-spread models; [`plot`]: SVG plots of the reports;
//! * [`provenance`]: what produced a result (commit, adapter, driver, date); [`fallible`]:
//!   allocation that reports failure instead of aborting; [`error`]: the kind of failure that
//!   ends a command and its exit code.

pub use sphlab_core::{
    backend, backend_id, cpu, exec, fields, gpu, model, neighbours, physics, plan, real, scene, stage,
};

pub mod analytic;
pub mod diagnostics;
pub mod error;
pub(crate) mod fallible;
pub mod forces;
pub mod output;
pub mod plot;
pub mod provenance;
pub mod resources;
pub mod run;
pub mod stability;
pub mod study;
pub mod sweep;
pub mod validate;
pub mod verify;
