//! Which model axis a mesh file calls "up".
//!
//! nendo is Z-up and right-handed. glTF 2.0 requires +Y up (§3.4: "+Y is up, +Z is forward"),
//! and Blender's OBJ importer (like most tools) assumes Y-up with −Z forward, so those files
//! get the rotation by −90° about x that takes the model's +Z to +Y and keeps the frame
//! right-handed and the triangles' winding:
//!
//! `(x, y, z) ↦ (x, z, −y)` for positions and normals alike (a rotation: lengths, angles and
//! orientation kept, and exact in floating point — only a sign changes).
//!
//! STL stays Z-up (the 3D-printing convention); OBJ is Y-up by default and Z-up on request.

use glam::Vec3;
use std::fmt;
use std::str::FromStr;

/// The axis a file calls up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UpAxis {
    /// +Y up: model `(x, y, z)` written as `(x, z, −y)`.
    Y,
    /// +Z up: coordinates written as they are.
    Z,
}

impl UpAxis {
    /// A model point or normal in this file frame.
    #[inline]
    #[must_use]
    pub fn apply(self, v: Vec3) -> Vec3 {
        match self {
            UpAxis::Y => Vec3::new(v.x, v.z, -v.y),
            UpAxis::Z => v,
        }
    }

    /// The name on the command line (`y`, `z`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            UpAxis::Y => "y",
            UpAxis::Z => "z",
        }
    }
}

impl fmt::Display for UpAxis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing an [`UpAxis`] name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown up axis {0:?}: expected y or z")]
pub struct UnknownUpAxis(pub String);

impl FromStr for UpAxis {
    type Err = UnknownUpAxis;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "y" => Ok(UpAxis::Y),
            "z" => Ok(UpAxis::Z),
            _ => Err(UnknownUpAxis(s.to_string())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_up_is_a_rotation_taking_z_to_y() {
        assert_eq!(UpAxis::Y.apply(Vec3::Z), Vec3::Y);
        assert_eq!(UpAxis::Y.apply(Vec3::Y), -Vec3::Z);
        assert_eq!(UpAxis::Y.apply(Vec3::X), Vec3::X);
        // Right-handed: the images of x and y cross to the image of z.
        let (x, y) = (UpAxis::Y.apply(Vec3::X), UpAxis::Y.apply(Vec3::Y));
        assert_eq!(x.cross(y), UpAxis::Y.apply(Vec3::Z));
        assert_eq!(
            UpAxis::Z.apply(Vec3::new(1.0, 2.0, 3.0)),
            Vec3::new(1.0, 2.0, 3.0)
        );
        assert_eq!("Y".parse::<UpAxis>(), Ok(UpAxis::Y));
        assert!("x".parse::<UpAxis>().is_err());
    }
}
