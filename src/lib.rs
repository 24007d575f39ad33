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
//! * [`real`]: the working precision (`f64`/`f32`), 2-vectors and the symmetric tensor;
//! * [`scene`]: scene description (TOML), built-in scenes, particle layout;
//! * [`model`]: the scene turned into solver constants in the working precision;
//! * [`stage`]: the stage table, the one source of each stage's name, activity, inputs, outputs
//!   and clears; [`fields`]: the per-evaluation fields both backends share;
//! * [`neighbours`]: direct, cell-grid and tracking-list neighbour searches with boundary images;
//! * [`exec`]: one thread or all cores for the CPU loops; [`fallible`]: allocation that
//!   reports failure instead of aborting;
//! * [`cpu`]: the CPU reference solver, stage by stage;
//! * [`gpu`]: the wgpu solver and its variants (WGSL composition, buffers, kernels per stage,
//!   timestamps);
//! * [`backend`]: what the run driver steps, and [`backend::BackendId`], the typed backend id;
//! * [`run`]: the `sphlab run` driver and its outputs ([`output`], [`diagnostics`]);
//! * [`verify`]: `sphlab verify`, every GPU variant against the CPU reference (the one
//!   comparison measure and tolerance table, also used by the GPU tests);
//! * [`stability`]: `sphlab stability`, the measured stability map per backend and precision;
//! * [`study`]: `sphlab study`, the Chapter 6 timing study and its report; [`sweep`]: the
//!   `--shard` and `--budget` controls the sweeps share;
//! * [`validate`]: `sphlab validate`, the thesis validation cases and their reports;
//! * [`analytic`]: analytic drop-spread models; [`plot`]: SVG plots of the reports.

pub mod analytic;
pub mod backend;
pub mod cpu;
pub mod diagnostics;
pub mod exec;
pub mod fallible;
pub mod fields;
pub mod forces;
pub mod gpu;
pub mod model;
pub mod neighbours;
pub mod output;
pub mod physics;
pub mod plan;
pub mod plot;
pub mod provenance;
pub mod real;
pub mod run;
pub mod scene;
pub mod stability;
pub mod stage;
pub mod study;
pub mod sweep;
pub mod validate;
pub mod verify;
