#![forbid(unsafe_code)]
//! # nendo (粘土, "clay")
//!
//! A free-form modeller in which surfaces are shaped like clay — pushed, pulled, grooved — and
//! curves are grabbed anywhere along their length, on exact geometry: grids of bicubic Bezier
//! patches kept tangent-continuous while they deform, and Bezier / B-spline curves queried by
//! Bezier clipping. The geometry follows the four papers summarised in `docs/design.md`.
//!
//! ## Crates, and which part may use which
//!
//! The geometry is its own crate, [`nendo_geom`], which depends on nothing of files, devices,
//! GPU or UI; this crate re-exports its modules as [`curve`], [`surface`], [`mesh`] and [`num`]
//! and adds what the application needs around them. The device crate, `nendo-devices` (`devices/`),
//! knows nothing of geometry. This crate is the package `nendo-modeller` (`modeller/`); above it
//! sit only the measurement suites behind `nendo bench` (`nendo-bench`, `bench/`) and the
//! `nendo` binary (the root package), which joins the two. The compiler holds these boundaries;
//! inside this crate the table below does.
//!
//! | part | what it is | may use |
//! |---|---|---|
//! | [`curve`], [`surface`], [`mesh`] | the geometry of `nendo-geom` re-exported, plus the curve file formats ([`curve::json`], [`curve::svg`]) and the OBJ / STL / GLB writers ([`mesh`]) | `nendo-geom`, serde, the file writer |
//! | [`model`] | the `nendo-model` JSON document (surface + curves) and the sculpt operations, validated reading, safe writing | geometry, serde |
//! | [`cad`] | the exact surface and curves for CAD: STEP (AP214) and IGES 5.3 writers, no approximation | geometry, [`model`], the file writer |
//! | [`figure`] | 2D metacircle figures (fit, iso-curves, pictures, warping, morphing) and 3D metaball shapes fitted to sections (P0 §4), with their documents and pictures; it lives here, not in `nendo-geom`, because it reads and writes its own files and PNG/SVG pictures | geometry, serde, png |
//! | [`hand`] | the kinematic hand (bend angles → joint positions), the contact of the fingertip capsule with the surface, the loop that turns device frames into displacement fields applied through `nendo-geom`'s deformation pipeline, the mouse as a hand, scripted traces; here because it joins devices and geometry | geometry, `nendo_devices` |
//! | [`render`] | what the renderer is handed (view, style, line and sphere batches, the GPU data layouts) and, with feature `gui`, the wgpu renderer (CPU tessellation from `mesh`, drawn as clay, or in an analysis mode — zebra, curvature, isophotes — per pixel from the exact patches) | everything above; wgpu only with `gui` |
//! | [`editor`] | the headless editor: the modeller (commands carried out, the pointer state machine on plain input events), document, history, lifecycle, live strokes, symmetry, camera, scene, display cache, settings (and the device loop); builds without `gui` | everything above |
//! | `app` | the thin egui / winit shell around the editor: the window (winit events into the editor's input), the panels and dialogs drawn with egui, returning commands; feature `gui` | everything above; nothing depends on it but the window's entry (`nendo window`) |
//! | [`cli`] | the subcommands of the `nendo` binary (the headless ones and the window's entry; `nendo bench` is `nendo-bench`'s) | everything |
//!
//! No module imports one below it in this table. Nothing but `app` (and the one entry that opens
//! the window, `cli::window`) uses winit or egui, and nothing outside `render` and `app` uses wgpu.
#![warn(missing_docs)]

#[cfg(feature = "gui")]
pub mod app;
pub mod cad;
pub mod cli;
pub mod curve;
pub mod editor;
pub mod figure;
pub mod hand;
pub mod json_doc;
pub mod mesh;
pub mod model;
pub mod render;

pub use nendo_geom::num;
pub use nendo_geom::surface;
