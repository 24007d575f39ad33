//! # sphlab — a GPU-vs-CPU performance laboratory for 2D multiphase SPH
//!
//! sphlab rebuilds the solver of Farrokhpanah (2012): Hu–Adams multiphase SPH, surface tension
//! by the surface stress tensor, and a contact-angle model with two corrections near the triple
//! point. The CPU reference ([`cpu`]) is the physics truth, in `f64` and `f32`; the same physics
//! exists once more in WGSL under `shaders/` for the GPU variants.
//!
//! Module map:
//! * [`physics`]: pure physics functions (kernels, EOS, pair terms, stress, walls, contact
//!   angle, integrators): the CPU twins of `shaders/*.wgsl`;
//! * [`scene`]: scene description (TOML), built-in scenes, particle layout;
//! * [`model`]: the scene turned into solver constants in the working precision;
//! * [`neighbours`]: direct, cell-grid and tracking-list neighbour searches with boundary images;
//! * [`cpu`]: the CPU reference solver, stage by stage;
//! * [`run`]: the `sphlab run` driver and its outputs;
//! * [`stability`]: `sphlab stability`, the measured stability map per backend and precision;
//! * [`validate`]: `sphlab validate`, the thesis validation cases and their reports.

pub mod analytic;
pub mod backend;
pub mod cpu;
pub mod diagnostics;
pub mod exec;
pub mod gpu;
pub mod model;
pub mod neighbours;
pub mod output;
pub mod physics;
pub mod plot;
pub mod real;
pub mod run;
pub mod scene;
pub mod stability;
pub mod study;
pub mod study_report;
pub mod validate;
pub mod verify;
