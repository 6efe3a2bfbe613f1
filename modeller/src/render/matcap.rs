//! Matcaps: the surface coloured by its normal as seen from the camera alone, as sculpting
//! programs show clay — the same look from every side, whatever the lights. Each matcap here
//! is a formula, evaluated per pixel in `modeller/shaders/clay.wgsl` and on the CPU by
//! [`Matcap::colour`] (the tests compare the two); none is an image.
//!
//! With the camera's right `r`, up `u` and `e = r × u` (towards the viewer), the view-space
//! normal of a pixel is `n = (N·r, N·u, N·e)` (`N` the surface normal turned to the viewer).
//! Every matcap lights it with the light `L = normalize(−0.45, 0.55, 0.70)` (upper left, in
//! front) and the half vector `H = normalize(L + (0, 0, 1))`:
//!
//! ```text
//! wrap(k)  = max((n·L + k) / (1 + k), 0)           diffuse wrapped past the terminator
//! spec(s)  = max(n·H, 0)^s                          a highlight of sharpness s
//! rim      = (1 − max(n_z, 0))^4                    grazing view (Schlick's Fresnel term)
//!
//! clay      = (0.62, 0.42, 0.31) · (0.16 + 0.9 wrap(0.5)) · (0.6 + 0.4 max(n_z, 0)) + 0.05 spec(10)
//! red wax   = (0.50, 0.045, 0.035) · (0.08 + 0.85 wrap(0.3)) + 0.9 spec(90)
//!             + (0.45, 0.12, 0.10) · rim
//! soft grey = 0.66 · (0.32 + 0.48 wrap(1.0) + 0.2 (0.5 + 0.5 n_y))
//! ```
//!
//! (linear RGB; the target encodes sRGB). Clay is warm and matte with the silhouette darkened
//! (as ambient occlusion would); red wax is glossy, a sharp white highlight and a bright rim;
//! soft grey is lit almost all round from above, the neutral look for judging form.

use glam::Vec3;

/// A matcap (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Matcap {
    /// Warm matte clay.
    Clay,
    /// Glossy red wax.
    RedWax,
    /// Soft grey, lit from above.
    SoftGrey,
}

/// A name that is no matcap.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{given:?} is no matcap; expected clay, red-wax or soft-grey")]
pub struct UnknownMatcap {
    /// The name given.
    pub given: String,
}

impl Matcap {
    /// Every matcap, in the order the panel lists them.
    pub const ALL: [Matcap; 3] = [Matcap::Clay, Matcap::RedWax, Matcap::SoftGrey];

    /// The name on the command line and in the settings file.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Matcap::Clay => "clay",
            Matcap::RedWax => "red-wax",
            Matcap::SoftGrey => "soft-grey",
        }
    }

    /// The name in the panel.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Matcap::Clay => "clay",
            Matcap::RedWax => "red wax",
            Matcap::SoftGrey => "soft grey",
        }
    }

    /// The matcap named `name` (as [`Matcap::name`] writes it), if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Matcap> {
        Self::ALL.into_iter().find(|m| m.name() == name.trim())
    }

    /// The shader's number for the matcap (0 is the lit shading).
    #[must_use]
    pub fn code(self) -> u32 {
        match self {
            Matcap::Clay => 1,
            Matcap::RedWax => 2,
            Matcap::SoftGrey => 3,
        }
    }

    /// The light every matcap is lit by, in view space.
    #[must_use]
    pub fn light() -> Vec3 {
        Vec3::new(-0.45, 0.55, 0.70).normalize()
    }

    /// The matcap's linear RGB colour for the view-space unit normal `n` (the module docs'
    /// formulas; `modeller/shaders/clay.wgsl` evaluates the same).
    #[must_use]
    pub fn colour(self, n: Vec3) -> Vec3 {
        let l = Self::light();
        let h = (l + Vec3::Z).normalize();
        let wrap = |k: f32| ((n.dot(l) + k) / (1.0 + k)).max(0.0);
        let spec = |s: f32| n.dot(h).max(0.0).powf(s);
        let facing = n.z.max(0.0);
        match self {
            Matcap::Clay => {
                Vec3::new(0.62, 0.42, 0.31) * (0.16 + 0.9 * wrap(0.5)) * (0.6 + 0.4 * facing)
                    + Vec3::splat(0.05 * spec(10.0))
            }
            Matcap::RedWax => {
                let rim = (1.0 - facing).powi(4);
                Vec3::new(0.50, 0.045, 0.035) * (0.08 + 0.85 * wrap(0.3))
                    + Vec3::splat(0.9 * spec(90.0))
                    + Vec3::new(0.45, 0.12, 0.10) * rim
            }
            Matcap::SoftGrey => {
                Vec3::splat(0.66 * (0.32 + 0.48 * wrap(1.0) + 0.2 * (0.5 + 0.5 * n.y)))
            }
        }
    }
}

impl std::str::FromStr for Matcap {
    type Err = UnknownMatcap;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s).ok_or_else(|| UnknownMatcap {
            given: s.to_owned(),
        })
    }
}

impl std::fmt::Display for Matcap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The sRGB encoding of a linear channel in `[0, 1]` (what an sRGB target stores), 0..255.
#[must_use]
pub fn srgb8(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for m in Matcap::ALL {
            assert_eq!(m.name().parse::<Matcap>(), Ok(m));
        }
        let e = "chrome".parse::<Matcap>().unwrap_err();
        assert!(e.to_string().contains("red-wax"), "{e}");
    }

    /// Each matcap looks as described: clay darkens toward the silhouette, red wax has a
    /// highlight near the half vector far brighter than its body, soft grey is lighter above
    /// than below and grey; the three differ.
    #[test]
    fn the_matcaps_look_as_described() {
        let facing = Vec3::Z;
        let side = Vec3::new(0.98, 0.0, 0.2).normalize();
        let clay = Matcap::Clay;
        assert!(clay.colour(facing).x > clay.colour(side).x);
        let h = (Matcap::light() + Vec3::Z).normalize();
        let wax = Matcap::RedWax;
        assert!(
            wax.colour(h).y > 0.8,
            "a white highlight: {}",
            wax.colour(h)
        );
        assert!(wax.colour(facing).x > 3.0 * wax.colour(facing).y, "red");
        let grey = Matcap::SoftGrey;
        let above = grey.colour(Vec3::new(0.0, 0.8, 0.6));
        let below = grey.colour(Vec3::new(0.0, -0.8, 0.6));
        assert!(above.x > below.x);
        assert!((above.x - above.z).abs() < 1e-6, "grey");
        for (i, a) in Matcap::ALL.iter().enumerate() {
            for b in &Matcap::ALL[i + 1..] {
                let d = (a.colour(facing) - b.colour(facing)).abs().max_element();
                assert!(d > 0.05, "{a} and {b} differ");
            }
        }
    }

    #[test]
    fn srgb_encoding_matches_its_definition() {
        assert_eq!(srgb8(0.0), 0);
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(0.5), 188);
        assert_eq!(srgb8(0.002), 7);
    }
}
