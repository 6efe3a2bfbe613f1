//! The mouse as a hand: the view ray is the finger.
//!
//! The window turns the cursor into a view ray (`nendo_devices::ViewRay`); the device layer's
//! `MouseDevice` puts the hand on that ray, pointing along it, index finger straight. For
//! modelling, a [`MouseFinger`] chooses *where* on the ray the fingertip is, and the hand loop
//! ([`super::session`], finger model [`super::FingerModel::Ray`]) does the rest exactly as for
//! a glove — so mouse frames can be recorded as traces and replayed like any other.
//!
//! | gesture | fingertip on the ray | what the loop does |
//! |---|---|---|
//! | no button | the mouse hand's own depth (hovering) | nothing: the mouse finger acts only while a button is held |
//! | left press | on the surface under the cursor, then `click depth` past it | a push of the click depth |
//! | left drag | `click depth` past the surface as it was when the button went down, under the cursor | a groove drawn along the cursor's path (draw-a-line) |
//! | right press | on the surface, then `click depth` in front of it | gripped: a pull of the click depth |
//! | right drag | `click depth` in front of the surface as it was | a ridge along the path |
//! | wheel while pressed | `wheel_step` deeper (or shallower) per step | pushes further, or (right button) pulls further |
//!
//! A press emits two frames at the same instant: the fingertip touching the surface (so the
//! grip of the right button catches), then the fingertip at its depth. The surface the drag
//! follows is the one under the cursor when the button went down (a copy is kept while a
//! button is held), so a stroke keeps its depth instead of following its own groove down.

use glam::DVec3;
use nendo_devices::profile::MouseProfile;
use nendo_devices::{HandFrame, Joint, MouseDevice, Timestamp, ViewRay, buttons};

use super::HandError;
use super::contact::Probe;
use crate::surface::Grid;

/// What a held button anchors to.
#[derive(Debug, Clone)]
struct Press {
    /// The surface when the button went down.
    surface: Grid,
    /// Distance along the ray to that surface at the last cursor position that found it.
    t_surface: f64,
    /// Signed depth past the surface (negative: in front of it, for the grip).
    depth: f64,
}

/// The mouse hand for modelling (see the module docs).
#[derive(Debug, Clone)]
pub struct MouseFinger {
    hand: MouseDevice,
    profile: MouseProfile,
    click_depth: f64,
    probe: Probe,
    press: Option<Press>,
    held: u32,
}

impl MouseFinger {
    /// A mouse finger with this profile and click depth (world units).
    ///
    /// # Errors
    /// [`HandError::Options`] when the click depth is not a positive finite number.
    pub fn new(profile: MouseProfile, click_depth: f64) -> Result<Self, HandError> {
        if !(click_depth.is_finite() && click_depth > 0.0) {
            return Err(HandError::Options(format!(
                "click depth must be a positive number, not {click_depth}"
            )));
        }
        Ok(Self {
            hand: MouseDevice::new(profile),
            profile,
            click_depth,
            probe: Probe::new(),
            press: None,
            held: 0,
        })
    }

    /// The depth of a click.
    #[must_use]
    pub fn click_depth(&self) -> f64 {
        self.click_depth
    }

    /// Sets the depth of the next clicks (ignored unless a positive finite number).
    pub fn set_click_depth(&mut self, depth: f64) {
        if depth.is_finite() && depth > 0.0 {
            self.click_depth = depth;
        }
    }

    /// True while a button holds the finger on the surface.
    #[must_use]
    pub fn is_pressed(&self) -> bool {
        self.press.is_some()
    }

    /// The joints of the mouse hand's pointing pose (the trace columns of mouse frames).
    #[must_use]
    pub fn pointing_joints(&self) -> Vec<Joint> {
        self.hand.pointing_pose().iter().map(|(j, _)| j).collect()
    }

    /// Wheel steps (positive: away from the eye). While pressed they move the fingertip
    /// deeper past (or, negative, back toward) the surface by the profile's `wheel_step` each;
    /// otherwise they move the hovering hand along the ray.
    pub fn wheel(&mut self, steps: f64) {
        if !steps.is_finite() {
            return;
        }
        match &mut self.press {
            Some(p) => p.depth += steps * self.profile.wheel_step,
            None => self.hand.wheel(steps),
        }
    }

    /// The frames for a cursor event: the view ray, the buttons held
    /// ([`buttons::PRIMARY`] left, [`buttons::SECONDARY`] right), at `time`. One frame, or two
    /// at a press (see the module docs).
    ///
    /// # Errors
    /// [`HandError::Mouse`] for a ray with a zero or non-finite direction or a non-finite origin.
    pub fn frames(
        &mut self,
        time: Timestamp,
        ray: ViewRay,
        held: u32,
        grid: &Grid,
    ) -> Result<Vec<HandFrame>, HandError> {
        let dir = ray
            .direction
            .try_normalize()
            .filter(|_| ray.origin.is_finite())
            .ok_or_else(|| HandError::Mouse(format!("view ray {ray:?}")))?;
        let held = held & (buttons::PRIMARY | buttons::SECONDARY);
        let mut out = Vec::with_capacity(2);
        if held == 0 {
            self.press = None;
        } else if self.held == 0 || self.press.is_none() && self.held != held {
            // A press: anchor on the surface under the cursor.
            let far = far_distance(grid, ray.origin);
            if let Some(hit) = self.probe.first_crossing(grid, ray.origin, dir, far) {
                let depth = if held & buttons::SECONDARY != 0 {
                    -self.click_depth
                } else {
                    self.click_depth
                };
                out.push(self.frame_at(time, ray.origin, dir, hit.t, held)?);
                self.press = Some(Press {
                    surface: grid.clone(),
                    t_surface: hit.t,
                    depth,
                });
            }
        }
        self.held = held;
        let frame = match &mut self.press {
            Some(p) => {
                let far = far_distance(&p.surface, ray.origin);
                if let Some(hit) = self.probe.first_crossing(&p.surface, ray.origin, dir, far) {
                    p.t_surface = hit.t;
                }
                let t = p.t_surface + p.depth;
                self.frame_at(time, ray.origin, dir, t, held)?
            }
            None => self
                .hand
                .frame(
                    time,
                    ViewRay {
                        origin: ray.origin,
                        direction: dir,
                    },
                    held,
                )
                .map_err(|e| HandError::Mouse(e.to_string()))?,
        };
        out.push(frame);
        Ok(out)
    }

    /// The mouse hand's frame with the fingertip at distance `t` along the ray.
    fn frame_at(
        &self,
        time: Timestamp,
        origin: DVec3,
        dir: DVec3,
        t: f64,
        held: u32,
    ) -> Result<HandFrame, HandError> {
        let shifted = ViewRay {
            origin: origin + (t - self.hand.depth()) * dir,
            direction: dir,
        };
        self.hand
            .frame(time, shifted, held)
            .map_err(|e| HandError::Mouse(e.to_string()))
    }
}

/// A distance along any ray from `origin` past which the grid cannot be.
fn far_distance(grid: &Grid, origin: DVec3) -> f64 {
    let b = grid.bounds();
    (b.center() - origin).length() + b.half_extents().length() + 1.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hand::{FingerModel, Hand, HandOptions, HandSession};
    use crate::surface::{Primitive, PrimitiveParams, Regulation};
    use nendo_devices::{HandSize, WorldFromTracker};

    #[test]
    fn a_left_click_pushes_by_the_click_depth_and_a_right_click_pulls() {
        let grid = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
        let hand = Hand::new(HandSize::default(), WorldFromTracker::default()).unwrap();
        let options = HandOptions {
            finger: FingerModel::Ray,
            ..HandOptions::default()
        };
        let mut s = HandSession::new(grid, Regulation::None, hand, options).unwrap();
        let mut m = MouseFinger::new(MouseProfile::default(), 0.25).unwrap();
        let eye = DVec3::new(0.0, 0.0, 10.0);
        let at = |x: f64, y: f64| ViewRay {
            origin: eye,
            direction: DVec3::new(x, y, 0.0) - eye,
        };
        let feed = |s: &mut HandSession, m: &mut MouseFinger, ray: ViewRay, b: u32, k: u64| {
            let frames = m.frames(Timestamp(k), ray, b, s.grid()).unwrap();
            for f in &frames {
                s.feed(f);
            }
            frames.len()
        };
        assert_eq!(
            feed(&mut s, &mut m, at(0.5, 0.5), 0, 0),
            1,
            "hovering: one frame"
        );
        assert_eq!(s.hand_loop().stats().operations(), 0);
        for k in 1..20 {
            let n = feed(&mut s, &mut m, at(0.5, 0.5), buttons::PRIMARY, k);
            assert_eq!(n, if k == 1 { 2 } else { 1 });
        }
        feed(&mut s, &mut m, at(0.5, 0.5), 0, 20);
        let z = |s: &HandSession, x: f64, y: f64| {
            let mut p = Probe::new();
            p.first_crossing(s.grid(), DVec3::new(x, y, 5.0), -DVec3::Z, 10.0)
                .unwrap()
                .point
                .z
        };
        assert!((z(&s, 0.5, 0.5) + 0.25).abs() < 0.01, "{}", z(&s, 0.5, 0.5));
        for k in 21..40 {
            feed(&mut s, &mut m, at(-3.0, -3.0), buttons::SECONDARY, k);
        }
        feed(&mut s, &mut m, at(-3.0, -3.0), 0, 40);
        // Pulled back along the view ray, toward the eye.
        let ray = at(-3.0, -3.0);
        let mut p = Probe::new();
        let t = p
            .first_crossing(s.grid(), eye, ray.direction, 20.0)
            .unwrap()
            .t;
        let t0 = ray.direction.length();
        assert!((t0 - t - 0.25).abs() < 0.01, "{}", t0 - t);
        let st = s.hand_loop().stats();
        assert_eq!((st.pushes, st.pulls, st.strokes), (1, 1, 0), "{st:?}");
        assert!(
            m.frames(
                Timestamp(41),
                ViewRay {
                    origin: eye,
                    direction: DVec3::ZERO
                },
                0,
                s.grid()
            )
            .is_err()
        );
    }
}
