//! The orbit camera: yaw and pitch about a target, `+Z` up, with the usual mouse conventions
//! (see the window, `app`) and the named views of `nendo render --view`.
//!
//! With yaw `ψ` and pitch `θ`, the unit vector from the target to the eye is
//! `e = (cos θ cos ψ, cos θ sin ψ, sin θ)`, the camera's right is `r = (−sin ψ, cos ψ, 0)` and
//! its up is `e × r`; `world_from_view = [r, e × r, e, eye]` (the camera looks down `−e`).
//! `r` does not depend on `θ`, so straight top and bottom views are well defined.
//!
//! ## Orthographic projection
//! The camera projects in perspective (field of view `φ`, the vertical `fov_y`) or
//! orthographically ([`Projection`], numpad 5 in the window, `nendo render --ortho`). The
//! orthographic view shows the box `|x| ≤ h·a`, `|y| ≤ h` of the view plane with the half
//! height
//!
//! ```text
//! h = d · tan(φ/2)          (d the distance from the eye to the target)
//! ```
//!
//! the half height the perspective view shows at the target's depth, so toggling keeps the
//! framing there; zooming and panning change `d` and the target alike in both. Its rays are
//! parallel: the ray through the pixel at NDC `(x, y)` runs along `−e` from
//! `target + (d + R)·e + x·h·a·r + y·h·u`, with `R = 20 d + 10` (the perspective view's far
//! reach): the orthographic view draws, and picks in, the slab of depths `(−R, R)` around the
//! eye's plane, so nothing between the eye and the target is cut off when zooming in.

use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};
use std::fmt;
use std::str::FromStr;

use crate::mesh::Ray;
use crate::render::View;

/// A named direction to look from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ViewPreset {
    /// From −Y: X to the right, Z up.
    Front,
    /// From +Y.
    Back,
    /// From −X.
    Left,
    /// From +X.
    Right,
    /// From +Z: X to the right, Y up.
    Top,
    /// From −Z.
    Bottom,
    /// From the front-right, above: the default.
    Iso,
}

impl ViewPreset {
    /// Every preset.
    pub const ALL: [ViewPreset; 7] = [
        ViewPreset::Front,
        ViewPreset::Back,
        ViewPreset::Left,
        ViewPreset::Right,
        ViewPreset::Top,
        ViewPreset::Bottom,
        ViewPreset::Iso,
    ];

    /// Lower-case name, as on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ViewPreset::Front => "front",
            ViewPreset::Back => "back",
            ViewPreset::Left => "left",
            ViewPreset::Right => "right",
            ViewPreset::Top => "top",
            ViewPreset::Bottom => "bottom",
            ViewPreset::Iso => "iso",
        }
    }

    /// `(yaw, pitch)` in radians.
    #[must_use]
    pub fn angles(self) -> (f32, f32) {
        match self {
            ViewPreset::Front => (-FRAC_PI_2, 0.0),
            ViewPreset::Back => (FRAC_PI_2, 0.0),
            ViewPreset::Left => (std::f32::consts::PI, 0.0),
            ViewPreset::Right => (0.0, 0.0),
            ViewPreset::Top => (-FRAC_PI_2, FRAC_PI_2),
            ViewPreset::Bottom => (-FRAC_PI_2, -FRAC_PI_2),
            ViewPreset::Iso => (-FRAC_PI_4 - 0.35, 0.55),
        }
    }
}

impl fmt::Display for ViewPreset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ViewPreset {
    type Err = crate::surface::UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ViewPreset::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| crate::surface::UnknownName {
                kind: "view",
                given: s.to_owned(),
                expected: "front, back, left, right, top, bottom or iso",
            })
    }
}

/// How the camera projects the scene (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Projection {
    /// Perspective, of the camera's field of view.
    #[default]
    Perspective,
    /// Orthographic: parallel rays, the perspective view's framing at the target.
    Orthographic,
}

impl Projection {
    /// The other projection (what numpad 5 does).
    #[must_use]
    pub fn toggled(self) -> Self {
        match self {
            Projection::Perspective => Projection::Orthographic,
            Projection::Orthographic => Projection::Perspective,
        }
    }

    /// `perspective` or `orthographic`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Projection::Perspective => "perspective",
            Projection::Orthographic => "orthographic",
        }
    }
}

/// An orbit camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// The point orbited around.
    pub target: Vec3,
    /// Distance from the target to the eye.
    pub distance: f32,
    /// Yaw `ψ` about +Z, radians.
    pub yaw: f32,
    /// Pitch `θ` above the XY plane, radians, in `[−π/2, π/2]`.
    pub pitch: f32,
    /// Vertical field of view, radians (in orthographic projection it sets the half height
    /// `distance · tan(fov_y / 2)`).
    pub fov_y: f32,
    /// Perspective or orthographic.
    pub projection: Projection,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        let (yaw, pitch) = ViewPreset::Iso.angles();
        Self {
            target: Vec3::ZERO,
            distance: 10.0,
            yaw,
            pitch,
            fov_y: 0.7,
            projection: Projection::Perspective,
        }
    }
}

impl OrbitCamera {
    /// Radians of orbit per pixel of drag.
    pub const ORBIT_PER_PIXEL: f32 = 0.008;

    /// A camera looking from `preset` at `points`, framed to fit a viewport of aspect ratio
    /// `aspect` (width / height).
    #[must_use]
    pub fn framing(preset: ViewPreset, points: &[Vec3], aspect: f32) -> Self {
        let (yaw, pitch) = preset.angles();
        let mut camera = Self {
            yaw,
            pitch,
            ..Self::default()
        };
        camera.frame(points, aspect);
        camera
    }

    /// Looks at the centre of the bounding box of `points` from the nearest distance at which
    /// every point is in view, with a 5 % margin (nothing changes for no points). In
    /// orthographic projection a point is in view when `|x| ≤ d tan_x` and `|y| ≤ d tan_y`,
    /// whatever its depth.
    pub fn frame(&mut self, points: &[Vec3], aspect: f32) {
        let Some(first) = points.first() else { return };
        let (lo, hi) = points
            .iter()
            .fold((*first, *first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        self.target = 0.5 * (lo + hi);
        let tan_y = (0.5 * self.fov_y).tan();
        let tan_x = tan_y * aspect.max(1e-3);
        let (r, u, e) = (self.right(), self.up(), self.to_eye());
        let mut distance = 1e-3f32;
        let mut depth = 0.0f32;
        for p in points {
            // A point at (x, y, z) in the camera's basis is in view from distance d when
            // |x| ≤ (d − z) tan_x and |y| ≤ (d − z) tan_y.
            let q = *p - self.target;
            let (x, y, z) = (q.dot(r), q.dot(u), q.dot(e));
            let z = match self.projection {
                Projection::Perspective => z,
                Projection::Orthographic => 0.0,
            };
            distance = distance.max(x.abs() / tan_x + z).max(y.abs() / tan_y + z);
            depth = depth.max(z);
        }
        self.distance = (1.05 * distance).max(1.5 * depth).max(1e-3);
    }

    /// Unit vector from the target to the eye, `e`.
    #[must_use]
    pub fn to_eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(cp * cy, cp * sy, sp)
    }

    /// The camera's right, `r`.
    #[must_use]
    pub fn right(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        Vec3::new(-sy, cy, 0.0)
    }

    /// The camera's up, `e × r`.
    #[must_use]
    pub fn up(&self) -> Vec3 {
        self.to_eye().cross(self.right())
    }

    /// The eye position.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.target + self.distance * self.to_eye()
    }

    /// World from view: columns `r`, `up`, `e`, eye.
    #[must_use]
    pub fn world_from_view(&self) -> Mat4 {
        Mat4::from_cols(
            self.right().extend(0.0),
            self.up().extend(0.0),
            self.to_eye().extend(0.0),
            self.eye().extend(1.0),
        )
    }

    /// The half height of the view at the target's depth, `h = distance · tan(fov_y / 2)`:
    /// the orthographic view's half height (see the module docs).
    #[must_use]
    pub fn half_height(&self) -> f32 {
        self.distance * (0.5 * self.fov_y).tan()
    }

    /// How far beyond the target the view reaches: the perspective far plane's distance
    /// from the eye, and in orthographic projection the half depth `R` of the slab drawn.
    #[must_use]
    pub fn reach(&self) -> f32 {
        self.distance * 20.0 + 10.0
    }

    /// The view for a viewport of aspect ratio `aspect` (width / height).
    #[must_use]
    pub fn view(&self, aspect: f32) -> View {
        let world_from_view = self.world_from_view();
        let aspect = aspect.max(1e-3);
        let proj = match self.projection {
            Projection::Perspective => {
                let near = (self.distance * 0.01).max(1e-4);
                glam::camera::rh::proj::directx::perspective(self.fov_y, aspect, near, self.reach())
            }
            Projection::Orthographic => {
                let h = self.half_height().max(1e-6);
                let w = h * aspect;
                let reach = self.reach();
                glam::camera::rh::proj::directx::orthographic(-w, w, -h, h, -reach, reach)
            }
        };
        View {
            clip_from_world: proj * world_from_view.inverse(),
            world_from_view,
        }
    }

    /// The ray through `pixel` (origin top-left) of a viewport of `size` pixels: from the eye
    /// in perspective; in orthographic projection along `−e` from the near side of the slab
    /// drawn (see the module docs).
    #[must_use]
    pub fn ray(&self, pixel: Vec2, size: Vec2) -> Ray {
        let size = size.max(Vec2::ONE);
        let ndc = Vec2::new(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
        let t = (0.5 * self.fov_y).tan();
        let across = self.right() * (ndc.x * t * size.x / size.y) + self.up() * (ndc.y * t);
        match self.projection {
            Projection::Perspective => Ray {
                origin: self.eye().as_dvec3(),
                direction: (across - self.to_eye()).normalize().as_dvec3(),
            },
            Projection::Orthographic => {
                let (e, d) = (self.to_eye().as_dvec3(), f64::from(self.distance));
                Ray {
                    origin: self.target.as_dvec3()
                        + (d + f64::from(self.reach())) * e
                        + d * across.as_dvec3(),
                    direction: -e,
                }
            }
        }
    }

    /// The parameter along [`OrbitCamera::ray`] at which the ray through `p`'s pixel reaches
    /// `p`: its distance from the eye in perspective, from the ray's origin plane in
    /// orthographic projection.
    #[must_use]
    pub fn ray_parameter(&self, p: glam::DVec3) -> f64 {
        let eye = self.eye().as_dvec3();
        match self.projection {
            Projection::Perspective => (p - eye).length(),
            Projection::Orthographic => {
                f64::from(self.reach()) + (eye - p).dot(self.to_eye().as_dvec3())
            }
        }
    }

    /// The unit vector from `p` towards the viewer: towards the eye in perspective, `e` in
    /// orthographic projection.
    #[must_use]
    pub fn towards_viewer(&self, p: glam::DVec3) -> glam::DVec3 {
        match self.projection {
            Projection::Perspective => (self.eye().as_dvec3() - p).normalize_or_zero(),
            Projection::Orthographic => self.to_eye().as_dvec3(),
        }
    }

    /// World units per pixel at the target's depth, for a viewport `height` pixels high.
    #[must_use]
    pub fn units_per_pixel(&self, height: f32) -> f32 {
        2.0 * self.half_height() / height.max(1.0)
    }

    /// World units per pixel at ray parameter `t` ([`OrbitCamera::ray`]), for a viewport
    /// `height` pixels high: `2 t tan(φ/2) / height` in perspective, the same at every depth in
    /// orthographic projection.
    #[must_use]
    pub fn units_per_pixel_at(&self, t: f64, height: f32) -> f64 {
        let height = f64::from(height.max(1.0));
        match self.projection {
            Projection::Perspective => 2.0 * t * f64::from((0.5 * self.fov_y).tan()) / height,
            Projection::Orthographic => 2.0 * f64::from(self.half_height()) / height,
        }
    }

    /// Orbits by a drag of `delta` pixels: right turns the model to the right, down tilts the
    /// view from above.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw -= delta.x * Self::ORBIT_PER_PIXEL;
        self.pitch = (self.pitch + delta.y * Self::ORBIT_PER_PIXEL).clamp(-FRAC_PI_2, FRAC_PI_2);
    }

    /// Pans so that the point under the cursor follows a drag of `delta` pixels.
    pub fn pan(&mut self, delta: Vec2, viewport_height: f32) {
        let k = self.units_per_pixel(viewport_height);
        self.target += (-delta.x * self.right() + delta.y * self.up()) * k;
    }

    /// Zooms by `steps` wheel notches (positive: closer), 12 % per notch.
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * (-0.12 * steps).exp()).clamp(1e-3, 1e6);
    }

    /// Zooms by `steps` notches toward the point under `pixel` (in a viewport of `size`
    /// pixels): the point `p` where the ray through `pixel` meets the plane through the
    /// target facing the camera stays under the cursor. With the factor
    /// `f = distance′ / distance`, the target moves to `p + f (target − p)`, so the eye moves
    /// to `p + f (eye − p)` along the same view direction: a homothety about `p`, which
    /// keeps `p`'s pixel.
    pub fn zoom_toward(&mut self, steps: f32, pixel: Vec2, size: Vec2) {
        let ray = self.ray(pixel, size);
        let normal = self.to_eye().as_dvec3();
        let denom = ray.direction.dot(normal);
        let t = (self.target.as_dvec3() - ray.origin).dot(normal) / denom;
        let before = self.distance;
        self.zoom(steps);
        if denom.abs() < 1e-9 || !(t.is_finite() && t > 0.0) {
            return;
        }
        let f = self.distance / before;
        let p = ray.at(t).as_vec3();
        self.target = p + (self.target - p) * f;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Zooming toward the cursor keeps the point under it where it was on screen, and moves
    /// the eye closer.
    #[test]
    fn zoom_toward_keeps_the_point_under_the_cursor() {
        for projection in [Projection::Perspective, Projection::Orthographic] {
            zoom_toward_keeps_the_point_under_the_cursor_in(projection);
        }
    }

    fn zoom_toward_keeps_the_point_under_the_cursor_in(projection: Projection) {
        let size = Vec2::new(800.0, 600.0);
        let mut cam = OrbitCamera {
            projection,
            ..OrbitCamera::default()
        };
        let pixel = Vec2::new(620.0, 150.0);
        let normal = cam.to_eye();
        let ray = cam.ray(pixel, size);
        let t = (cam.target.as_dvec3() - ray.origin).dot(normal.as_dvec3())
            / ray.direction.dot(normal.as_dvec3());
        let p = ray.at(t).as_vec3();
        let project = |c: &OrbitCamera| {
            let clip = c.view(size.x / size.y).clip_from_world * p.extend(1.0);
            Vec2::new(clip.x / clip.w, clip.y / clip.w)
        };
        let before = project(&cam);
        cam.zoom_toward(3.0, pixel, size);
        assert!(cam.distance < 10.0);
        let after = project(&cam);
        assert!((after - before).length() < 1e-4, "{before} → {after}");
    }

    #[test]
    fn presets_look_along_the_axes() {
        let cam = |p: ViewPreset| OrbitCamera {
            yaw: p.angles().0,
            pitch: p.angles().1,
            ..OrbitCamera::default()
        };
        let front = cam(ViewPreset::Front);
        assert!((front.to_eye() - Vec3::NEG_Y).length() < 1e-6);
        assert!((front.right() - Vec3::X).length() < 1e-6);
        assert!((front.up() - Vec3::Z).length() < 1e-6);
        let top = cam(ViewPreset::Top);
        assert!((top.to_eye() - Vec3::Z).length() < 1e-6);
        assert!((top.up() - Vec3::Y).length() < 1e-6);
    }

    /// In both projections the ray through a point's pixel passes through the point, at the
    /// parameter [`OrbitCamera::ray_parameter`] gives; orthographic rays are parallel to the
    /// view direction, and a point nearer than the eye's plane is still in front of them.
    #[test]
    fn the_ray_through_a_projected_point_passes_through_it() {
        for projection in [Projection::Perspective, Projection::Orthographic] {
            let camera = OrbitCamera {
                target: Vec3::new(1.0, 2.0, 0.5),
                distance: 7.0,
                projection,
                ..OrbitCamera::default()
            };
            let size = Vec2::new(640.0, 480.0);
            let view = camera.view(size.x / size.y);
            let behind_eye = camera.eye() + 0.5 * camera.to_eye() + 0.3 * camera.right();
            let points = [Vec3::new(1.7, 1.4, 1.1), behind_eye];
            let count = if projection == Projection::Orthographic {
                2
            } else {
                1
            };
            for p in &points[..count] {
                let clip = view.clip_from_world * p.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                assert!(
                    (0.0..=1.0).contains(&ndc.z),
                    "{projection:?}: depth {}",
                    ndc.z
                );
                let pixel = Vec2::new((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y);
                let ray = camera.ray(pixel, size);
                let to_p = p.as_dvec3() - ray.origin;
                let off = (to_p - ray.direction * to_p.dot(ray.direction)).length();
                assert!(off < 1e-4, "{projection:?}: {off}");
                let t = camera.ray_parameter(p.as_dvec3());
                assert!(t > 0.0, "{projection:?}: in front of the ray");
                assert!((ray.at(t) - p.as_dvec3()).length() < 1e-4, "{projection:?}");
                if projection == Projection::Orthographic {
                    let along = ray.direction + camera.to_eye().as_dvec3();
                    assert!(along.length() < 1e-6, "parallel rays");
                }
            }
        }
    }

    /// Toggling the projection keeps the framing at the target: a point on the plane through
    /// the target facing the camera stays on its pixel, and so does the pixel size there.
    #[test]
    fn the_toggle_keeps_the_framing_at_the_target() {
        let size = Vec2::new(640.0, 480.0);
        let persp = OrbitCamera {
            target: Vec3::new(0.5, -1.0, 0.2),
            distance: 9.0,
            ..OrbitCamera::default()
        };
        let ortho = OrbitCamera {
            projection: persp.projection.toggled(),
            ..persp
        };
        assert_eq!(ortho.projection, Projection::Orthographic);
        let pixel = |c: &OrbitCamera, p: Vec3| {
            let clip = c.view(size.x / size.y).clip_from_world * p.extend(1.0);
            Vec2::new(clip.x / clip.w, clip.y / clip.w)
        };
        for (x, y) in [(0.0, 0.0), (2.0, 1.0), (-3.0, 2.5)] {
            let p = persp.target + x * persp.right() + y * persp.up();
            let (a, b) = (pixel(&persp, p), pixel(&ortho, p));
            assert!((a - b).length() < 1e-5, "{a} vs {b}");
        }
        assert_eq!(persp.units_per_pixel(480.0), ortho.units_per_pixel(480.0));
        let t = f64::from(persp.distance);
        let (a, b) = (
            persp.units_per_pixel_at(t, 480.0),
            ortho.units_per_pixel_at(ortho.ray_parameter(persp.target.as_dvec3()), 480.0),
        );
        assert!((a - b).abs() < 1e-6 * a, "{a} vs {b}");
    }

    #[test]
    fn framing_keeps_the_box_in_view() {
        let bounds = (Vec3::new(-5.0, -5.0, -0.5), Vec3::new(5.0, 5.0, 0.5));
        for preset in ViewPreset::ALL {
            let corners: Vec<Vec3> = (0..8)
                .map(|k| {
                    Vec3::new(
                        if k & 1 == 0 { bounds.0.x } else { bounds.1.x },
                        if k & 2 == 0 { bounds.0.y } else { bounds.1.y },
                        if k & 4 == 0 { bounds.0.z } else { bounds.1.z },
                    )
                })
                .collect();
            for projection in [Projection::Perspective, Projection::Orthographic] {
                let mut camera = OrbitCamera::framing(preset, &corners, 16.0 / 9.0);
                camera.projection = projection;
                camera.frame(&corners, 16.0 / 9.0);
                let view = camera.view(16.0 / 9.0);
                for c in &corners {
                    let clip = view.clip_from_world * c.extend(1.0);
                    let ndc = clip.truncate() / clip.w;
                    assert!(
                        ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z),
                        "{preset} {projection:?}: {ndc}"
                    );
                }
            }
        }
    }
}
