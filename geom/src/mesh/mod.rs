//! Triangle meshes of the exact surface: tessellation within a chosen tolerance, the G1 error
//! along seams per vertex, and ray picking refined on the exact patches.
//!
//! It works on plain bicubic patches ([`PatchPoints`], 16 control points each) and uses nothing
//! but [`crate::curve`] and glam; the renderer and the exporters (in the `nendo` crate) both
//! draw on it, so what the window shows is what a file gets.

mod pick;
mod seams;
mod tessellate;

pub use pick::{Ray, SurfaceHit, pick};
pub use seams::{
    max_seam_angle_deg, seam_angles_deg, seam_bands, update_seam_angles_deg, update_seam_bands,
};
pub use tessellate::{
    LiveTessellation, MeshSize, MeshUpdate, PatchBlock, PatchPoints, TessellateError, Tessellation,
    TriMesh, estimate, eval_patch, patch_normal, tessellate, try_tessellate,
};
