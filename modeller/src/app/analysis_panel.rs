//! The panel's surface-analysis controls: the display mode (clay, zebra, curvature,
//! isophotes) with its settings, the curvature map's legend and range, the seam heat map's
//! measure (G1 angle or G2 curvature mismatch), and the clay's shading (lit or a matcap).

use egui::{Color32, Ui};

use crate::mesh::PatchPoints;
use crate::render::display_mode::{auto_range, legend_colour};
use crate::render::{CurvatureKind, Matcap, SurfaceAnalysis, SurfaceMode};

/// The controls, editing `analysis` in place; `patches` for fitting the curvature range.
pub(super) fn analysis_ui(ui: &mut Ui, analysis: &mut SurfaceAnalysis, patches: &[PatchPoints]) {
    ui.horizontal_wrapped(|ui| {
        ui.label("surface")
            .on_hover_text("E cycles: every mode is computed per pixel from the patches' exact derivatives, so a coarse tessellation shows no false breaks");
        for mode in SurfaceMode::ALL {
            ui.radio_value(&mut analysis.mode, mode, mode.name());
        }
    });
    match analysis.mode {
        SurfaceMode::Clay => {}
        SurfaceMode::Zebra => {
            ui.add(egui::Slider::new(&mut analysis.stripes, 2.0..=60.0).text("stripes per 180°"))
                .on_hover_text("More stripes: narrower, and a crease of α shifts them by 2α·stripes/180° of a period");
            ui.add(
                egui::Slider::new(&mut analysis.stripe_angle_deg, -90.0..=90.0)
                    .text("° stripe direction"),
            )
            .on_hover_text("0° vertical on the screen; turn them to cross a seam you are checking");
        }
        SurfaceMode::Curvature => {
            let before = analysis.kind;
            ui.horizontal(|ui| {
                for kind in CurvatureKind::ALL {
                    ui.radio_value(&mut analysis.kind, kind, kind_label(kind));
                }
            });
            if analysis.kind != before
                && let Some(range) = auto_range(patches, analysis.kind)
            {
                analysis.range = range;
            }
            ui.horizontal(|ui| {
                let [lo, hi] = &mut analysis.range;
                ui.add(egui::DragValue::new(lo).speed(0.01).prefix("blue "));
                ui.add(egui::DragValue::new(hi).speed(0.01).prefix("red "));
                if ui
                    .button("fit")
                    .on_hover_text("The 2nd to 98th percentile of the curvature on the model")
                    .clicked()
                    && let Some(range) = auto_range(patches, analysis.kind)
                {
                    analysis.range = range;
                }
            });
            let [lo, hi] = analysis.range;
            if !lo.is_finite() || !hi.is_finite() {
                analysis.range = [-1.0, 1.0];
            } else if lo >= hi {
                analysis.range[1] = lo + 1e-3;
            }
            legend_ui(ui, analysis.range, analysis.kind);
        }
        SurfaceMode::Isophotes => {
            ui.add(egui::Slider::new(&mut analysis.isophotes, 2.0..=60.0).text("lines per 180°"))
                .on_hover_text("Curves of equal light from the key light; they break at a crease and kink at a curvature jump");
        }
    }
    ui.horizontal(|ui| {
        ui.label("seam heat map measures");
        ui.radio_value(&mut analysis.seam_g2, false, "G1")
            .on_hover_text("The angle between the two sides' normals, degrees");
        ui.radio_value(&mut analysis.seam_g2, true, "G2")
            .on_hover_text("The curvature mismatch across the seam, |κ₁ − κ₂| / (|κ₁| + |κ₂|), percent (as `nendo check` reports it)");
    });
    if analysis.seam_g2 {
        ui.add(
            egui::Slider::new(&mut analysis.g2_red_percent, 0.01..=100.0)
                .logarithmic(true)
                .text("% = red (G2)"),
        );
    }
}

/// The clay's shading: lit, or one of the matcaps (remembered in the settings).
pub(super) fn matcap_ui(ui: &mut Ui, matcap: &mut Option<Matcap>) {
    ui.horizontal_wrapped(|ui| {
        ui.label("shading").on_hover_text(
            "lit: the scene's lights; a matcap colours the clay by its normal as seen from the camera, the same look from every side",
        );
        ui.radio_value(matcap, None, "lit");
        for m in Matcap::ALL {
            ui.radio_value(matcap, Some(m), m.label());
        }
    });
}

fn kind_label(kind: CurvatureKind) -> &'static str {
    match kind {
        CurvatureKind::Mean => "mean",
        CurvatureKind::Gaussian => "Gaussian",
        CurvatureKind::MaxPrincipal => "max principal",
    }
}

/// The map's colour bar with its ends and middle.
fn legend_ui(ui: &mut Ui, [lo, hi]: [f32; 2], kind: CurvatureKind) {
    let (rect, _) =
        ui.allocate_exact_size(egui::vec2(ui.available_width(), 12.0), egui::Sense::hover());
    let steps = 32;
    for k in 0..steps {
        let t0 = k as f32 / steps as f32;
        let t1 = (k + 1) as f32 / steps as f32;
        let [r, g, b] = legend_colour(0.5 * (t0 + t1)).map(|c| (c * 255.0) as u8);
        ui.painter().rect_filled(
            egui::Rect::from_x_y_ranges(
                rect.left() + rect.width() * t0..=rect.left() + rect.width() * t1,
                rect.y_range(),
            ),
            0.0,
            Color32::from_rgb(r, g, b),
        );
    }
    let unit = if kind == CurvatureKind::Gaussian {
        "1/u²"
    } else {
        "1/u"
    };
    ui.horizontal(|ui| {
        ui.small(format!("{lo:.4}"));
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            ui.small(format!("{hi:.4} {unit}"));
            ui.small(format!("{:.4} ·", 0.5 * (lo + hi)));
        });
    });
    ui.small(match kind {
        CurvatureKind::Gaussian => "K: + dome, − saddle",
        _ => "convexity: + bulging towards you (a ball from outside), − hollow",
    });
}
