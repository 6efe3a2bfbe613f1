//! The wgpu renderer: the clay surface, lines and spheres, drawn into a window's frame or
//! offscreen into an image.
//!
//! What the renderer is handed — [`View`], [`Style`], [`LineBatch`], [`SphereInstance`], the
//! GPU data layouts — builds without the `gui` feature, so the headless editor fills
//! it without a GPU; the GPU side (wgpu) comes with `gui`.
//!
//! It knows nothing of the application above it: it is handed a [`TriMesh`](crate::mesh::TriMesh)
//! (the library's own tessellation, done on the CPU — see [`crate::mesh`]), a [`LineBatch`],
//! [`SphereInstance`]s, a [`View`] and a [`Style`], and draws them. The shaders are in
//! `modeller/shaders/*.wgsl`, the per-frame uniform block once in
//! `modeller/shaders/globals.wgsl` (prepended to the shaders that read it); the data they read is
//! in [`gpu_data`].
//!
//! Headless use:
//!
//! ```no_run
//! use nendo::render::{GpuContext, Offscreen, Renderer, Style, look_at_view, OFFSCREEN_FORMAT};
//! # fn main() -> Result<(), nendo::render::RenderError> {
//! let gpu = GpuContext::headless()?;
//! let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 4);
//! let view = look_at_view(glam::Vec3::new(3.0, -4.0, 3.0), glam::Vec3::ZERO, 0.8, 4.0 / 3.0);
//! renderer.prepare(&gpu.queue, &view, &Style::default(), [800.0, 600.0]);
//! let image = Offscreen::new(&gpu.device, [800, 600], 4).render(&gpu, &renderer)?;
//! image.save_png(std::path::Path::new("out.png"))?;
//! # Ok(()) }
//! ```

#[cfg(feature = "gui")]
mod analysis;
#[cfg(feature = "gui")]
mod buffer;
#[cfg(feature = "gui")]
mod context;
pub mod display_mode;
pub mod gpu_data;
pub mod legend;
pub mod matcap;
#[cfg(feature = "gui")]
mod offscreen;
#[cfg(feature = "gui")]
mod renderer;
mod scene;
#[cfg(feature = "gui")]
mod targets;

#[cfg(feature = "gui")]
pub use analysis::ANALYSIS_WGSL;
#[cfg(feature = "gui")]
pub use context::GpuContext;
pub use display_mode::{CurvatureKind, SurfaceAnalysis, SurfaceMode};
pub use gpu_data::SphereInstance;
pub use matcap::Matcap;
#[cfg(feature = "gui")]
pub use offscreen::{OFFSCREEN_FORMAT, Offscreen, RgbaImage};
#[cfg(feature = "gui")]
pub use renderer::{GLOBALS_WGSL, Renderer, SHADERS, look_at_view, surface_vertices};
pub use scene::{LineBatch, Rgba, Style, ToolFootprint, View};
#[cfg(feature = "gui")]
pub use targets::{DEPTH_FORMAT, FrameTargets};

/// What can go wrong while rendering.
#[cfg(feature = "gui")]
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No GPU adapter is available (no driver, or none the enabled backends reach).
    #[error(
        "no GPU adapter found ({0}); for software rendering install Mesa's Vulkan driver \
         (Debian/Ubuntu: `apt-get install mesa-vulkan-drivers libvulkan1`) or select GL with WGPU_BACKEND=gl"
    )]
    NoAdapter(String),
    /// The adapter refused to open a device.
    #[error("cannot open the GPU device: {0}")]
    Device(String),
    /// Reading a frame back from the GPU failed.
    #[error("cannot read the frame back from the GPU: {0}")]
    Readback(String),
    /// Encoding or decoding a PNG failed.
    #[error("PNG: {0}")]
    Png(String),
    /// The image file could not be written. The I/O error is part of the message (not a
    /// separate `source`), so printing the error with its chain names it once.
    #[error("cannot write the image {}: {error}", path.display())]
    Io {
        /// The file that was being written.
        path: std::path::PathBuf,
        /// What went wrong.
        error: std::io::Error,
    },
}
