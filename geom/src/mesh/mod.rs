//! Triangle meshes of the exact surface: tessellation within a chosen tolerance, the G1 error
//! along seams per vertex, and ray picking refined on the exact patches.
//!
//! It works on plain bicubic patches ([`PatchPoints`], 16 control points each), evaluated by
//! the one patch evaluator [`crate::surface::patch`] (and, for the G2 seam error, the curvature
//! measure [`crate::surface::curvature`]), and uses nothing else but [`crate::curve`] and glam; the renderer and the exporters (in the `nendo` crate) both
//! draw on it, so what the window shows is what a file gets.
//!
//! The parts: `tessellate` (the entry points and a patch's vertices), `plan` (segment counts
//! within the tolerance, the mesh's size beforehand), `edges` (shared edges tied, no cracks),
//! `trimesh` (the mesh type, welding), `live` (re-tessellation in place during a stroke),
//! `seams` (the G1 error per vertex), `seams_g2` (the G2 error per vertex) and `pick` (rays against the exact surface).

mod edges;
mod live;
mod pick;
mod plan;
mod seams;
mod seams_g2;
mod tessellate;
mod trimesh;

pub use live::{LiveTessellation, MeshUpdate};
pub use pick::{Ray, SurfaceHit, pick};
pub use plan::{MeshSize, Tessellation, estimate};
pub use seams::{
    max_seam_angle_deg, seam_angles_deg, seam_bands, update_seam_angles_deg, update_seam_bands,
};
pub use seams_g2::seam_g2_percent;
pub use tessellate::{
    PatchPoints, TessellateError, eval_patch, patch_normal, tessellate, try_tessellate,
};
pub use trimesh::{PatchBlock, TriMesh};
