//! Triangle meshes of the exact surface: tessellation within a chosen tolerance, the G1 error
//! along seams per vertex, ray picking refined on the exact patches, and OBJ / binary STL / GLB
//! writers.
//!
//! Geometry-level code: it works on plain bicubic patches ([`PatchPoints`], 16 control points
//! each) and uses nothing but [`crate::curve`] and glam; the renderer and the exporters both
//! draw on it, so what the window shows is what a file gets.

mod export;
mod glb;
mod obj;
mod pick;
mod seams;
mod stl;
mod tessellate;

pub use export::{ExportError, MeshFormat, save_mesh};
pub use glb::write_glb;
pub use obj::write_obj;
pub use pick::{Ray, SurfaceHit, pick};
pub use seams::{max_seam_angle_deg, seam_angles_deg, seam_bands};
pub use stl::write_stl;
pub use tessellate::{
    PatchBlock, PatchPoints, Tessellation, TriMesh, eval_patch, patch_normal, tessellate,
};
