#![forbid(unsafe_code)]
//! # nendo-geom: the exact geometry under nendo's clay
//!
//! Everything here is the geometry of the papers summarised in `docs/design.md` (cited in the
//! docs as `P0`, `P2`, `P3`, `P4` with their sections, listed in `docs/design.md` §2), and nothing
//! else: no files, devices, GPU or UI. The crate depends on glam, thiserror and nalgebra (dense
//! least squares and eigenvectors); `serde` derives are behind the `serde` feature. The file
//! formats (model, curve JSON, SVG, mesh writers), the hand and the window live in the `nendo`
//! crate, which re-exports these modules under the same names.
//!
//! | module | what it is | may use |
//! |---|---|---|
//! | [`curve`] | Bernstein forms, Bezier and B-spline curves in 2D/3D, closest point / pick / probe sphere / ray by Bezier clipping, grab, split, tangent edit, similarity-preserving refinement, curve-driven warping | glam, nalgebra |
//! | [`surface`] | patch grids in five topologies, control-point groups, deformation by shape functions through the Bernstein inverse (one engine for the mouse and the hand), G1 regulation, continuity and deviation measures; its folders are layers (base → net → constraint → operation → engine) | `curve`, glam, nalgebra |
//! | [`mesh`] | tessellation of the exact patches within a tolerance, seam G1 error per vertex, exact ray picking | `curve`, the patch evaluator `surface::patch`, glam |
//! | [`num`] | numbers in error messages: [`num::Compact`] prints `1e308` as `1e308`, not 309 digits | std |
//!
//! `cargo test -p nendo-geom` builds and tests this crate alone; `cargo tree -p nendo-geom`
//! shows no GPU, window, device, JSON or image crate.
#![warn(missing_docs)]

pub mod curve;
pub mod mesh;
pub mod num;
pub mod surface;

#[cfg(test)]
mod seeded;
