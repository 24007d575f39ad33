//! # sphlab-core — the solver of sphlab
//!
//! Farrokhpanah's (2012) solver: Hu–Adams multiphase SPH, surface tension by the surface stress
//! tensor, and a contact-angle model with two corrections near the triple point. The CPU
//! reference ([`cpu`]) is the physics truth, in `f64` and `f32`; the same physics exists once
//! more in WGSL (the repository's `shaders/` and `kernels-variants/`) for the GPU executor
//! ([`gpu`]). This crate knows nothing of the lab (study, validation, reports).
//!
//! Module map:
//! * [`physics`]: pure physics functions (kernels, EOS, pair terms, stress, walls, contact
//!   angle, integrators): the CPU twins of `shaders/*.wgsl`;
//! * [`real`]: the working precision (`f64`/`f32`, [`real::Precision`]), 2-vectors and the
//!   symmetric tensor;
//! * [`scene`]: scene description (TOML), built-in scenes, the particle lattice and layout;
//! * [`model`]: the scene turned into solver constants in the working precision;
//! * [`stage`]: the stage table, the one source of each stage's name, activity, inputs, outputs
//!   and clears; [`fields`]: the per-evaluation fields both executors share;
//! * [`neighbours`]: direct, cell-grid and tracking-list neighbour searches with boundary images
//!   ([`neighbours::SearchKind`]), and the packing of a neighbour entry both executors use;
//! * [`exec`]: one thread or all cores for the CPU loops;
//! * [`cpu`]: the CPU reference executor, stage by stage;
//! * [`gpu`]: the wgpu executor and its variants (WGSL composition, buffers, kernels per stage,
//!   timestamps, the device-buffer plan);
//! * [`backend`]: what a run steps (the [`backend::Backend`] trait, frame, errors, counters);
//!   [`backend_id`]: the typed backend id and the factory that builds the backend it names;
//! * [`plan`]: the resource plan of a run, checked before anything big is allocated.

pub mod backend;
pub mod backend_id;
pub mod cpu;
pub mod exec;
pub mod fields;
pub mod gpu;
pub mod model;
pub mod neighbours;
pub mod physics;
pub mod plan;
pub mod real;
pub mod scene;
pub mod stage;
