//! # nendo (粘土, "clay")
//!
//! A free-form modeller in which surfaces are shaped like clay — pushed, pulled, grooved — and
//! curves are grabbed anywhere along their length, on exact geometry: grids of bicubic Bezier
//! patches kept tangent-continuous while they deform, and Bezier / B-spline curves queried by
//! Bezier clipping. The geometry follows the four papers summarised in `shared/SPEC.md`.
//!
//! ## Parts, and which part may use which
//!
//! | part | what it is | may use |
//! |---|---|---|
//! | [`curve`] | Bernstein forms, Bezier and B-spline curves, closest point / pick / probe sphere / ray queries by Bezier clipping | glam |
//! | [`surface`] | patch grids in five topologies, connected control-point groups, deformation by shape functions through the Bernstein inverse, G1 regulation, continuity measures | `curve`, glam |
//! | [`model`] | the `nendo-model` JSON document (surface + curves), validated reading, atomic writing | `curve`, `surface`, serde |
//! | [`mesh`] | tessellation of the exact patches within a tolerance, seam G1 error per vertex, ray picking, OBJ / STL / GLB writers | `curve`, `surface`, glam |
//! | [`hand`] | the kinematic hand (bend angles → joint positions), contact of the fingertip capsule with the surface, the loop that turns device frames into push / pull / draw-a-line operations, the mouse as a hand, scripted traces | `surface`, `mesh` (ray picking), `nendo_devices` |
//! | `render`, `app` | the wgpu renderer (CPU tessellation from `mesh`, drawn as clay) and the egui window; feature `gui` | everything above; nothing depends on them |
//! | [`cli`] | the headless subcommands of the `nendo` binary | everything |
//! | [`bench`] | the measurement suites behind `nendo bench` | everything |
//!
//! The rule the table encodes: **geometry (`curve`, `surface`) knows nothing of devices, the
//! GPU, files or the UI**; the device crate (`nendo-devices`, in `devices/`) knows nothing of
//! geometry; the application layers wire them together. The geometry modules never import a
//! module below them in this table.
#![warn(missing_docs)]

#[cfg(feature = "gui")]
pub mod app;
pub mod bench;
pub mod cli;
pub mod curve;
pub mod figure;
pub mod hand;
pub mod mesh;
pub mod model;
#[cfg(feature = "gui")]
pub mod render;
pub mod surface;
