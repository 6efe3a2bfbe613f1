//! The parts of the hand that press — the five fingers and the palm ([`Part`], the set
//! [`Fingers`]) — and which of them touch the surface for an input device ([`FingerModel`]),
//! with the buttons that make them act ([`Activation`]).

use nendo_devices::buttons;

use super::kinematics::Digit;

/// A contact shape of the hand: a fingertip capsule, or the palm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Part {
    /// The fingertip capsule of a finger.
    Digit(Digit),
    /// The palm: a wide, short capsule under the palm's centre, along its normal
    /// ([`Hand::palm`](super::Hand::palm)).
    Palm,
}

impl Part {
    /// Every part: the five fingers, thumb to little finger, then the palm.
    pub const ALL: [Part; 6] = [
        Part::Digit(Digit::Thumb),
        Part::Digit(Digit::Index),
        Part::Digit(Digit::Middle),
        Part::Digit(Digit::Ring),
        Part::Digit(Digit::Pinky),
        Part::Palm,
    ];

    /// The part's name on the command line (`thumb` … `pinky`, `palm`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Part::Digit(d) => d.name(),
            Part::Palm => "palm",
        }
    }

    fn bit(self) -> u8 {
        match self {
            Part::Digit(d) => 1 << d.index(),
            Part::Palm => 1 << 5,
        }
    }
}

/// Which parts of the hand press: a set of the five fingers and the palm. Written on the
/// command line as `all` (the five fingers), or a comma-separated list of `thumb`, `index`,
/// `middle`, `ring`, `pinky`, `palm` and `all` (`all,palm`: the whole hand).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fingers(pub(super) u8);

impl Fingers {
    /// The five fingers (not the palm).
    pub const ALL: Fingers = Fingers(0b1_1111);

    /// The thumb and the index finger (a pinch).
    pub const THUMB_AND_INDEX: Fingers = Fingers(0b11);

    /// One part alone.
    #[must_use]
    pub fn one(part: Part) -> Self {
        Fingers(part.bit())
    }

    /// This set and `part`.
    #[must_use]
    pub fn with(self, part: Part) -> Self {
        Fingers(self.0 | part.bit())
    }

    /// Whether `part` is in the set.
    #[must_use]
    pub fn contains(self, part: Part) -> bool {
        self.0 & part.bit() != 0
    }

    /// The parts in the set, in [`Part::ALL`]'s order.
    pub fn parts(self) -> impl Iterator<Item = Part> {
        Part::ALL.into_iter().filter(move |p| self.contains(*p))
    }

    /// The finger that stands for the set where one finger is needed (the one drawn as the
    /// fingertip, the one a mouse ray is): the index when it is in the set, else the first
    /// finger; the index for the palm alone.
    #[must_use]
    pub fn primary(self) -> Digit {
        if self.contains(Part::Digit(Digit::Index)) {
            return Digit::Index;
        }
        self.parts()
            .find_map(|p| match p {
                Part::Digit(d) => Some(d),
                Part::Palm => None,
            })
            .unwrap_or(Digit::Index)
    }
}

impl std::str::FromStr for Fingers {
    type Err = crate::surface::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let unknown = |given: &str| crate::surface::UnknownName {
            kind: "finger",
            given: given.to_owned(),
            expected: "thumb, index, middle, ring, pinky, palm or all (a comma-separated list)",
        };
        let mut set = Fingers(0);
        for name in s.split(',').map(str::trim) {
            set = match name {
                "all" => Fingers(set.0 | Fingers::ALL.0),
                "palm" => set.with(Part::Palm),
                _ => set.with(Part::Digit(
                    name.parse::<Digit>().map_err(|_| unknown(name))?,
                )),
            };
        }
        Ok(set)
    }
}

impl std::fmt::Display for Fingers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut names = Vec::new();
        if self.0 & Fingers::ALL.0 == Fingers::ALL.0 {
            names.push("all");
        } else {
            names.extend(self.parts().filter(|p| *p != Part::Palm).map(Part::name));
        }
        if self.contains(Part::Palm) {
            names.push("palm");
        }
        f.write_str(&names.join(","))
    }
}

/// Which parts of the hand touch the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FingerModel {
    /// Parts of the kinematic hand (glove + tracker): fingertips (their tip and distal
    /// direction) and the palm.
    Hand(Fingers),
    /// The mouse: the frame's pose is the fingertip on the view ray, pointing along it (the
    /// hand is drawn behind it, its index finger on the ray). A single ray.
    Ray,
}

impl std::str::FromStr for FingerModel {
    type Err = crate::surface::UnknownName;

    /// `ray` (the mouse's view ray), or a list of the hand's parts as [`Fingers`] reads it
    /// (`index`, `thumb,index`, `all`, `palm`, …): the one reading of `--finger` and of a
    /// trace scene's `finger`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "ray" {
            return Ok(FingerModel::Ray);
        }
        s.parse::<Fingers>().map(FingerModel::Hand)
    }
}

impl Default for FingerModel {
    /// The index finger alone (the library's one-finger default; a glove profile presses
    /// with every finger, see [`FingerModel::for_profile`]).
    fn default() -> Self {
        FingerModel::Hand(Fingers::one(Part::Digit(Digit::Index)))
    }
}

impl FingerModel {
    /// The finger model for frames recorded with a profile of this name: the view ray for the
    /// `mouse` profile, every finger otherwise.
    #[must_use]
    pub fn for_profile_name(name: Option<&str>) -> Self {
        match name {
            Some("mouse") => FingerModel::Ray,
            _ => FingerModel::Hand(Fingers::ALL),
        }
    }

    /// The finger model of a profile: the view ray for mouse input, every finger otherwise.
    #[must_use]
    pub fn for_profile(profile: &nendo_devices::Profile) -> Self {
        match profile.input {
            nendo_devices::profile::Input::Mouse(_) => FingerModel::Ray,
            _ => FingerModel::Hand(Fingers::ALL),
        }
    }

    /// One finger of the kinematic hand.
    #[must_use]
    pub fn digit(digit: Digit) -> Self {
        FingerModel::Hand(Fingers::one(Part::Digit(digit)))
    }

    /// How buttons act for this finger.
    #[must_use]
    pub fn activation(self) -> Activation {
        match self {
            FingerModel::Hand(_) => Activation {
                press: 0,
                grip: buttons::PRIMARY,
            },
            FingerModel::Ray => Activation {
                press: buttons::PRIMARY | buttons::SECONDARY,
                grip: buttons::SECONDARY,
            },
        }
    }

    /// The finger that stands for the model where one is needed ([`Fingers::primary`]; the
    /// index for the mouse's ray).
    #[must_use]
    pub fn primary(self) -> Digit {
        match self {
            FingerModel::Hand(f) => f.primary(),
            FingerModel::Ray => Digit::Index,
        }
    }

    pub(super) fn parts(self) -> Fingers {
        match self {
            FingerModel::Hand(f) => f,
            FingerModel::Ray => Fingers::one(Part::Digit(Digit::Index)),
        }
    }
}

/// Which buttons make the finger act and grip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Activation {
    /// The finger acts only while one of these buttons is held; `0`: always.
    pub press: u32,
    /// While one of these is held the clay sticks to the finger (pull, ridge).
    pub grip: u32,
}
