//! [`HandSession`]: a [`HandLoop`] with its own grid and regulation, for `nendo replay`, the
//! tests and the benches — feed it frames, read the surface.

use nendo_devices::HandFrame;

use super::HandError;
use super::hand_loop::HandLoop;
use super::kinematics::Hand;
use super::options::HandOptions;
use super::outcome::FrameOutcome;
use crate::surface::{Grid, Op, Regulation};

/// A [`HandLoop`] with its own grid and regulation: `nendo replay`, tests, benches.
#[derive(Debug, Clone)]
pub struct HandSession {
    grid: Grid,
    regulation: Regulation,
    hand_loop: HandLoop,
    log: Option<Vec<Vec<Op>>>,
}

impl HandSession {
    /// A session sculpting `grid`.
    ///
    /// # Errors
    /// [`HandError::Options`] for bad options.
    pub fn new(
        grid: Grid,
        regulation: Regulation,
        hand: Hand,
        options: HandOptions,
    ) -> Result<Self, HandError> {
        Ok(Self {
            grid,
            regulation,
            hand_loop: HandLoop::new(hand, options)?,
            log: None,
        })
    }

    /// Keeps the operations of every contact (see [`HandSession::contacts`]).
    #[must_use]
    pub fn logging_contacts(mut self) -> Self {
        self.log = Some(Vec::new());
        self
    }

    /// Feeds one frame.
    pub fn feed(&mut self, frame: &HandFrame) -> FrameOutcome {
        let out = self.hand_loop.frame(frame, &mut self.grid, self.regulation);
        if let (Some(log), Some(ops)) = (&mut self.log, &out.committed) {
            log.push(ops.clone());
        }
        out
    }

    /// Ends a contact still in progress (the end of a trace).
    pub fn finish(&mut self) {
        if let Some(ops) = self.hand_loop.end_contact()
            && let Some(log) = &mut self.log
        {
            log.push(ops);
        }
    }

    /// The surface now.
    #[must_use]
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The surface, taking the session apart (a contact in progress is kept as it is).
    #[must_use]
    pub fn into_grid(self) -> Grid {
        self.grid
    }

    /// The regulation method.
    #[must_use]
    pub fn regulation(&self) -> Regulation {
        self.regulation
    }

    /// Presses every contact together with its mirror image ([`HandLoop::set_mirror`]).
    pub fn set_mirror(&mut self, symmetry: Option<crate::surface::Symmetry>) {
        self.hand_loop.set_mirror(symmetry);
    }

    /// Gates and filters the frames from now on with `settings` ([`HandLoop::set_filter`]).
    pub fn set_filter(&mut self, settings: nendo_devices::FilterSettings) {
        self.hand_loop.set_filter(settings);
    }

    /// The loop (pose, fingertip, touch, counters).
    #[must_use]
    pub fn hand_loop(&self) -> &HandLoop {
        &self.hand_loop
    }

    /// The operations of every ended contact, when logging ([`HandSession::logging_contacts`]).
    #[must_use]
    pub fn contacts(&self) -> Option<&[Vec<Op>]> {
        self.log.as_deref()
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn thumb_and_index_is_the_pinch_pair() {
        assert_eq!(Fingers::THUMB_AND_INDEX.to_string(), "thumb,index");
        assert_eq!(
            "thumb,index".parse::<Fingers>().ok(),
            Some(Fingers::THUMB_AND_INDEX)
        );
    }

    use super::*;
    use crate::hand::contact::Probe;
    use crate::hand::outcome::Touch;
    use crate::hand::parts::Fingers;
    use crate::hand::script::Choreography;
    use crate::surface::{Primitive, PrimitiveParams};
    use glam::DVec3;
    use nendo_devices::SourceState;
    use nendo_devices::{HandFrame, HandSize, WorldFromTracker};

    fn plane_session(regulation: Regulation) -> HandSession {
        let grid = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
        let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
        HandSession::new(grid, regulation, hand, HandOptions::default()).unwrap()
    }

    fn z_at(grid: &Grid, x: f64, y: f64) -> f64 {
        let mut probe = Probe::new();
        probe
            .first_crossing(grid, DVec3::new(x, y, 10.0), -DVec3::Z, 20.0)
            .unwrap()
            .point
            .z
    }

    #[test]
    fn a_press_meets_the_fingertip_and_stops_when_the_finger_stops() {
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        let down = -DVec3::Z;
        c.place(DVec3::new(0.5, 0.5, 0.5), down, DVec3::Y);
        c.move_to(DVec3::new(0.5, 0.5, -0.3), down, 24);
        c.hold(36);
        c.move_to(DVec3::new(0.5, 0.5, 0.5), down, 24);
        let trace = c.finish("test").unwrap();
        // Every regulation, g2 included: a held finger's clay stops moving when the finger does.
        for regulation in Regulation::ALL {
            let mut s = plane_session(regulation);
            // The contact rules on the exact frames: through the One-Euro filter the finger
            // comes to rest a little later (tests/it/hand_filter.rs measures how much).
            s.set_filter(nendo_devices::FilterSettings::off());
            let mut last_change = 0;
            let mut committed = Vec::new();
            for (k, f) in trace.frames.iter().enumerate() {
                let out = s.feed(f);
                if !out.changed.is_empty() {
                    last_change = k;
                }
                if k == 59 {
                    let z = z_at(s.grid(), 0.5, 0.5);
                    assert!(
                        (z + 0.3).abs() < 2e-3,
                        "{regulation}: the clay meets the fingertip: {z}"
                    );
                }
                committed.extend(out.committed);
            }
            assert!(
                last_change < 55,
                "{regulation}: a finger held still stops deforming"
            );
            let st = s.hand_loop().stats();
            assert_eq!(
                (st.contacts, st.pushes, st.strokes, st.pulls),
                (1, 1, 0, 0),
                "{regulation}"
            );
            assert_eq!(committed.len(), 1);
            assert!(matches!(committed[0][..], [Op::Push { .. }]));
            // Withdrawing leaves the dent; far away nothing moved (under g2, the window two
            // patches past what moved shifts by what a curvature-continuous dent needs: 8.8e-4
            // at (4, 4), 1.3e-4 at (4.8, 4.8)).
            assert!((z_at(s.grid(), 0.5, 0.5) + 0.3).abs() < 2e-3);
            let far = z_at(s.grid(), 4.0, 4.0);
            if regulation == Regulation::G2 {
                assert!(far.abs() < 2e-3, "{far}");
            } else {
                assert_eq!(far, 0.0);
            }
        }
    }

    #[test]
    fn a_stroke_cuts_a_groove_as_deep_as_the_finger_not_deeper() {
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        let down = -DVec3::Z;
        c.place(DVec3::new(-3.0, 0.5, 0.3), down, DVec3::X);
        c.move_to(DVec3::new(-3.0, 0.5, -0.25), down, 20);
        c.move_to(DVec3::new(3.0, 0.5, -0.25), down, 300);
        c.move_to(DVec3::new(3.0, 0.5, 0.3), down, 20);
        let trace = c.finish("test").unwrap();
        let mut s = plane_session(Regulation::default());
        for f in &trace.frames {
            s.feed(f);
        }
        let st = *s.hand_loop().stats();
        assert_eq!((st.contacts, st.strokes), (1, 1), "{st:?}");
        assert!(st.placements < 100, "straight runs merge: {st:?}");
        for x in [-2.0, -1.0, 0.0, 1.0, 2.0] {
            let z = z_at(s.grid(), x, 0.5);
            assert!((z + 0.25).abs() < 0.02, "x = {x}: {z}");
        }
    }

    /// A frame with the fingertip 0.3 above the plane at the origin, and the next with it
    /// 0.2 into the plane: the tip crosses the plane from above between them.
    fn above_and_in() -> (HandFrame, HandFrame) {
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        c.place(DVec3::new(0.0, 0.0, 0.3), -DVec3::Z, DVec3::Y);
        c.hold(1);
        c.move_to(DVec3::new(0.0, 0.0, -0.2), -DVec3::Z, 1);
        let t = c.finish("test").unwrap();
        (t.frames[0], t.frames[t.frames.len() - 1])
    }

    #[test]
    fn no_pose_or_a_silent_glove_means_no_finger() {
        let (above, mut frame) = above_and_in();
        let mut s = plane_session(Regulation::default());
        let mut lost = frame;
        lost.pose = None;
        assert_eq!(s.feed(&above).touch, Touch::Free);
        assert_eq!(s.feed(&lost).touch, Touch::Free);
        let mut silent = frame;
        silent.joints = None;
        silent.status.glove = SourceState::Silent;
        assert!(s.feed(&silent).changed.is_empty());
        assert_eq!(s.grid(), plane_session(Regulation::default()).grid());
        // The hand back in the clay without having been seen to enter it: where it came from
        // is not known, so it does not press (rule 3).
        frame.time.0 += 1;
        let out = s.feed(&frame);
        assert_eq!(out.touch, Touch::Free);
        assert!(out.changed.is_empty());
        // Seen above the clay, then in it: it presses.
        assert_eq!(s.feed(&above).touch, Touch::Free);
        let out = s.feed(&frame);
        assert!(!out.changed.is_empty());
        assert_eq!(out.touch, Touch::Pressing);
        assert_eq!(s.hand_loop().stats().frames_with_finger, 4);
        // The glove going silent mid-contact ends the contact.
        assert!(s.feed(&silent).committed.is_some());
    }

    /// A jump of the hand (a tracker glitch, two recordings joined) from below the paper's
    /// sphere to above it: the fingertip's path passes through the clay and out again, so it
    /// is still outside, and pressing down from there dents the north pole to the fingertip
    /// (counting only the first crossing, the tip would have been taken for in the clay from
    /// below, pushing the pole up by the 1 side between it and the tip).
    #[test]
    fn a_jump_through_the_clay_and_out_leaves_the_finger_outside() {
        let sphere = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .unwrap();
        let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
        let mut s =
            HandSession::new(sphere, Regulation::default(), hand, HandOptions::default()).unwrap();
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        // Below, pointing up at the sphere (the whole hand below it); then above, pointing
        // down at it.
        c.place(DVec3::new(0.0, 0.0, -4.0), DVec3::Z, DVec3::Y);
        c.hold(2);
        c.place(DVec3::new(0.0, 0.0, 4.0), -DVec3::Z, -DVec3::Y);
        c.hold(2);
        c.move_to(DVec3::new(0.0, 0.0, 2.8), -DVec3::Z, 20);
        c.hold(10);
        let t = c.finish("test").unwrap();
        for (k, f) in t.frames.iter().enumerate() {
            let out = s.feed(f);
            if k < 4 {
                assert_eq!(out.touch, Touch::Free, "frame {k}");
            }
        }
        assert_eq!(s.hand_loop().touch(), Touch::Pressing);
        let top = 10.0
            - Probe::new()
                .first_crossing(s.grid(), DVec3::new(0.0, 0.0, 10.0), -DVec3::Z, 20.0)
                .unwrap()
                .t;
        assert!((top - 2.8).abs() < 2e-3, "the pole at {top}");
    }

    #[test]
    fn values_of_a_source_that_is_not_ok_never_act() {
        let (above, frame) = above_and_in();
        let untouched = plane_session(Regulation::default());
        // The pressing frame with its pose and angles kept, but a source not delivering.
        let mut stale = Vec::new();
        for state in [
            SourceState::Silent,
            SourceState::Disconnected,
            SourceState::Absent,
        ] {
            let mut f = frame;
            f.status.tracker = state;
            stale.push(f);
        }
        for state in [SourceState::Silent, SourceState::Disconnected] {
            let mut f = frame;
            f.status.glove = state;
            stale.push(f);
        }
        for f in &stale {
            let mut s = plane_session(Regulation::default());
            assert!(s.hand_loop().finger_of(f).is_none(), "{:?}", f.status);
            s.feed(&above);
            let out = s.feed(f);
            assert_eq!(out.touch, Touch::Free, "{:?}", f.status);
            assert!(out.changed.is_empty(), "{:?}", f.status);
            assert_eq!(s.grid(), untouched.grid());
        }
        // The same frames from delivering sources press.
        let mut s = plane_session(Regulation::default());
        s.feed(&above);
        assert_eq!(s.feed(&frame).touch, Touch::Pressing);
    }

    #[test]
    fn bad_options_are_refused() {
        let hand = Hand::new(HandSize::default(), WorldFromTracker::default()).unwrap();
        for o in [
            HandOptions {
                finger_radius: 0.0,
                ..HandOptions::default()
            },
            HandOptions {
                min_depth: f64::NAN,
                ..HandOptions::default()
            },
            HandOptions {
                grip_distance: -1.0,
                ..HandOptions::default()
            },
            HandOptions {
                pinch_closed: 0.0,
                ..HandOptions::default()
            },
            HandOptions {
                pinch_open: 0.2,
                ..HandOptions::default()
            },
        ] {
            assert!(HandLoop::new(hand, o).is_err(), "{o:?}");
        }
    }
}
