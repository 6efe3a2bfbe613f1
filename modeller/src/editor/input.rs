//! The modeller's input as plain events: the pointer over the 3D view in viewport pixels, and
//! which button orbits. The window's shell translates winit's events into these (after egui
//! took what was its own); the tests and the benches make them up directly.

use glam::Vec2;

/// Mouse buttons the viewport listens to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Button {
    /// Tools.
    Left,
    /// Orbit (with Shift: pan), or pan with [`OrbitButton::Middle`].
    Right,
    /// Pan, or orbit with [`OrbitButton::Middle`].
    Middle,
}

/// Pointer input in viewport pixels (origin top-left of the 3D view), already filtered by
/// egui's `consumed` flag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointerInput {
    /// The cursor moved.
    Moved(Vec2),
    /// A button went down.
    Pressed(Button, Vec2),
    /// A button went up.
    Released(Button, Vec2),
    /// Wheel notches, positive away from the user.
    Wheel(f32),
    /// The cursor left the window.
    Left,
}

/// Which mouse button orbits the camera (a remembered setting).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OrbitButton {
    /// The right button orbits, the middle one pans (nendo's default).
    #[default]
    Right,
    /// The middle button orbits, Shift+middle or the right button pans (Blender's).
    Middle,
}

impl OrbitButton {
    /// The setting's name in the panel.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            OrbitButton::Right => "right button (nendo)",
            OrbitButton::Middle => "middle button (Blender)",
        }
    }

    /// Whether a move with these buttons held (left, right, middle) and Shift orbits or pans
    /// the camera: `(orbit, pan)`.
    #[must_use]
    pub fn camera_drag(self, [_, right, middle]: [bool; 3], shift: bool) -> (bool, bool) {
        match self {
            OrbitButton::Right => (right && !shift, middle || (right && shift)),
            OrbitButton::Middle => (middle && !shift, right || (middle && shift)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The right button orbits by default and pans with Shift; with the middle button
    /// orbiting, the two swap roles; the left button alone does neither.
    #[test]
    fn the_orbit_setting_swaps_the_camera_buttons() {
        let (left, right, middle) = (
            [true, false, false],
            [false, true, false],
            [false, false, true],
        );
        assert_eq!(OrbitButton::Right.camera_drag(right, false), (true, false));
        assert_eq!(OrbitButton::Right.camera_drag(right, true), (false, true));
        assert_eq!(OrbitButton::Right.camera_drag(middle, false), (false, true));
        assert_eq!(
            OrbitButton::Middle.camera_drag(middle, false),
            (true, false)
        );
        assert_eq!(OrbitButton::Middle.camera_drag(middle, true), (false, true));
        assert_eq!(OrbitButton::Middle.camera_drag(right, false), (false, true));
        for orbit in [OrbitButton::Right, OrbitButton::Middle] {
            assert_eq!(orbit.camera_drag(left, false), (false, false));
        }
    }
}
