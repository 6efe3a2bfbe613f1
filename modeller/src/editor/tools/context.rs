//! What the tools may look at — the camera, the viewport, the surface and the curves — and
//! the picking on it: the surface or curve under a pixel, the joint handle near it.

use glam::{DVec3, Vec2};

use crate::curve::Curve;
use crate::editor::camera::OrbitCamera;
use crate::editor::curve_edit::{CurveJoint, joint_points, joints};
use crate::mesh::{PatchPoints, Ray, SurfaceHit, TriMesh, pick};

/// What the tools may look at.
#[derive(Debug, Clone, Copy)]
pub struct ToolContext<'a> {
    /// The camera.
    pub camera: &'a OrbitCamera,
    /// Viewport size in pixels.
    pub viewport: Vec2,
    /// The surface's patches.
    pub patches: &'a [PatchPoints],
    /// Their tessellation (for picking).
    pub mesh: &'a TriMesh,
    /// The model's 3D curves with their indices in the model.
    pub curves: &'a [(usize, &'a Curve<DVec3>)],
}

impl ToolContext<'_> {
    pub(super) fn ray(&self, pixel: Vec2) -> Ray {
        self.camera.ray(pixel, self.viewport)
    }

    pub(super) fn pick_surface(&self, pixel: Vec2) -> Option<SurfaceHit> {
        pick(self.patches, self.mesh, &self.ray(pixel))
    }

    /// World units per pixel at parameter `t` along a view ray (in perspective, distance `t`
    /// from the eye; the same at every depth in orthographic projection).
    pub(super) fn units_per_pixel_at(&self, t: f64) -> f64 {
        self.camera.units_per_pixel_at(t, self.viewport.y)
    }

    /// The nearest curve to the ray through `pixel`, within `PICK_PIXELS` on screen:
    /// `(position in `curves`, u, point, ray parameter)`.
    pub(super) fn pick_curve(&self, pixel: Vec2) -> Option<(usize, f64, DVec3, f64)> {
        let ray = self.ray(pixel);
        let mut best: Option<(f64, (usize, f64, DVec3, f64))> = None;
        for (slot, (_, curve)) in self.curves.iter().enumerate() {
            let Some(near) = curve.ray_closest(ray.origin, ray.direction) else {
                continue;
            };
            let score = near.distance / self.units_per_pixel_at(near.ray_t.max(1e-6));
            if score <= PICK_PIXELS && best.is_none_or(|(s, _)| score < s) {
                best = Some((score, (slot, near.u, near.point, near.ray_t)));
            }
        }
        best.map(|(_, b)| b)
    }

    /// Projects a world point to viewport pixels (`None` behind the camera).
    pub(super) fn project(&self, p: DVec3) -> Option<Vec2> {
        let view = self.camera.view(self.viewport.x / self.viewport.y.max(1.0));
        let clip = view.clip_from_world * p.as_vec3().extend(1.0);
        (clip.w > 0.0).then(|| {
            let ndc = clip.truncate() / clip.w;
            Vec2::new(
                (ndc.x + 1.0) * 0.5 * self.viewport.x,
                (1.0 - ndc.y) * 0.5 * self.viewport.y,
            )
        })
    }

    /// The joint handle nearest to `pixel` within `PICK_PIXELS`: `(joint, left side)`, with
    /// joints indexed in `curves`.
    pub(super) fn pick_handle(&self, pixel: Vec2) -> Option<(CurveJoint, bool)> {
        let curves: Vec<Curve<DVec3>> = self.curves.iter().map(|(_, c)| (*c).clone()).collect();
        let mut best: Option<(f32, (CurveJoint, bool))> = None;
        for joint in joints(&curves) {
            let Some((ql, _, qr)) = joint_points(&curves, joint) else {
                continue;
            };
            for (p, left) in [(ql, true), (qr, false)] {
                let Some(s) = self.project(p) else { continue };
                let d = s.distance(pixel);
                if d <= PICK_PIXELS as f32 && best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, (joint, left)));
                }
            }
        }
        best.map(|(_, b)| b)
    }
}

/// How close (in pixels) the cursor must be to a curve or a handle to pick it.
pub const PICK_PIXELS: f64 = 10.0;
