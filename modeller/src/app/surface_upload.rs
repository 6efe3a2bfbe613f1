//! Keeping the renderer's copy of the surface current: the tessellation with its seam heat
//! (the G1 angle, or the G2 mismatch when the panel asks for it), and, while an analysis
//! display mode is shown, the patches' control points the analysis pass evaluates.

use crate::editor::Modeller;
use crate::editor::scene::SurfaceDisplay;
use crate::mesh::{seam_bands, seam_g2_percent};
use crate::render::{Renderer, SurfaceMode};

/// What the renderer holds, by the modeller's surface generation.
#[derive(Debug, Default)]
pub(super) struct SurfaceUpload {
    /// The generation of the uploaded tessellation.
    surface: Option<u64>,
    /// The generation whose control points the analysis pass holds.
    analysis: Option<u64>,
    /// The uploaded seam heat is the G2 one (of the uploaded generation).
    g2: bool,
}

impl SurfaceUpload {
    /// Uploads what changed since the last call: the tessellation (only the changed vertex
    /// ranges during a stroke, when the heat is G1's), the G2 seam heat (recomputed on the
    /// whole surface), the analysis pass's control points when a mode other than clay is on.
    pub(super) fn update(
        &mut self,
        renderer: &mut Renderer,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        modeller: &Modeller,
    ) {
        let generation = modeller.surface_generation();
        let panel = modeller.panel();
        let want_g2 = panel.analysis.seam_g2 && panel.overlays.heat_map;
        let display = modeller.surface();
        if self.surface != Some(generation) || self.g2 != want_g2 {
            if want_g2 {
                let g2 = seam_g2_percent(modeller.surface_patches(), &display.mesh);
                let heat = seam_bands(&display.mesh, &g2, SurfaceDisplay::HEAT_BAND);
                renderer.set_surface(device, queue, &display.mesh, &heat);
            } else {
                // A live stroke re-uploads only the vertices of the patches it changed.
                let ranges = self
                    .surface
                    .filter(|_| !self.g2)
                    .and_then(|g| modeller.surface_ranges_since(g));
                match ranges {
                    Some(ranges) => renderer.update_surface_vertices(
                        device,
                        queue,
                        &display.mesh,
                        &display.seam_heat,
                        &ranges,
                    ),
                    None => renderer.set_surface(device, queue, &display.mesh, &display.seam_heat),
                }
            }
            self.surface = Some(generation);
            self.g2 = want_g2;
        }
        if panel.analysis.mode != SurfaceMode::Clay && self.analysis != Some(generation) {
            renderer.set_analysis_patches(device, queue, modeller.surface_patches(), &display.mesh);
            self.analysis = Some(generation);
        }
    }
}
