//! The modeller window: winit + egui over the wgpu renderer.

pub mod camera;
pub mod scene;

pub use camera::{OrbitCamera, ViewPreset};
