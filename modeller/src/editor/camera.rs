//! The orbit camera: yaw and pitch about a target, `+Z` up, with the usual mouse conventions
//! (see the window, `app`) and the named views of `nendo render --view`.
//!
//! With yaw `ψ` and pitch `θ`, the unit vector from the target to the eye is
//! `e = (cos θ cos ψ, cos θ sin ψ, sin θ)`, the camera's right is `r = (−sin ψ, cos ψ, 0)` and
//! its up is `e × r`; `world_from_view = [r, e × r, e, eye]` (the camera looks down `−e`).
//! `r` does not depend on `θ`, so straight top and bottom views are well defined.

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
    /// Vertical field of view, radians.
    pub fov_y: f32,
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
    /// every point is in view, with a 5 % margin (nothing changes for no points).
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

    /// The view for a viewport of aspect ratio `aspect` (width / height).
    #[must_use]
    pub fn view(&self, aspect: f32) -> View {
        let world_from_view = self.world_from_view();
        let near = (self.distance * 0.01).max(1e-4);
        let far = self.distance * 20.0 + 10.0;
        let proj =
            glam::camera::rh::proj::directx::perspective(self.fov_y, aspect.max(1e-3), near, far);
        View {
            clip_from_world: proj * world_from_view.inverse(),
            world_from_view,
        }
    }

    /// The ray from the eye through `pixel` (origin top-left) of a viewport of `size` pixels.
    #[must_use]
    pub fn ray(&self, pixel: Vec2, size: Vec2) -> Ray {
        let size = size.max(Vec2::ONE);
        let ndc = Vec2::new(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
        let t = (0.5 * self.fov_y).tan();
        let dir =
            self.right() * (ndc.x * t * size.x / size.y) + self.up() * (ndc.y * t) - self.to_eye();
        Ray {
            origin: self.eye().as_dvec3(),
            direction: dir.normalize().as_dvec3(),
        }
    }

    /// World units per pixel at the target's depth, for a viewport `height` pixels high.
    #[must_use]
    pub fn units_per_pixel(&self, height: f32) -> f32 {
        2.0 * self.distance * (0.5 * self.fov_y).tan() / height.max(1.0)
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
        let size = Vec2::new(800.0, 600.0);
        let mut cam = OrbitCamera::default();
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

    #[test]
    fn the_ray_through_a_projected_point_passes_through_it() {
        let camera = OrbitCamera {
            target: Vec3::new(1.0, 2.0, 0.5),
            distance: 7.0,
            ..OrbitCamera::default()
        };
        let size = Vec2::new(640.0, 480.0);
        let view = camera.view(size.x / size.y);
        let p = Vec3::new(1.7, 1.4, 1.1);
        let clip = view.clip_from_world * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        assert!((0.0..=1.0).contains(&ndc.z));
        let pixel = Vec2::new((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y);
        let ray = camera.ray(pixel, size);
        let to_p = p.as_dvec3() - ray.origin;
        let off = (to_p - ray.direction * to_p.dot(ray.direction)).length();
        assert!(off < 1e-4, "{off}");
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
            let camera = OrbitCamera::framing(preset, &corners, 16.0 / 9.0);
            let view = camera.view(16.0 / 9.0);
            for c in corners {
                let clip = view.clip_from_world * c.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                assert!(
                    ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z),
                    "{preset}: {ndc}"
                );
            }
        }
    }
}
