//! Triangle meshes of the exact surface: the tessellation, seam G1 error and ray picking of
//! [`nendo_geom::mesh`] (re-exported here under the same names), and the OBJ / binary STL / GLB
//! writers, so what the window shows is what a file gets, each with its up axis ([`up`]).

pub use nendo_geom::mesh::*;

mod export;
mod glb;
mod obj;
mod stl;
pub mod up;

pub use export::{ExportError, MeshFormat, save_mesh, save_mesh_up};
pub use glb::write_glb;
pub use obj::write_obj;
pub use stl::write_stl;
pub use up::UpAxis;
