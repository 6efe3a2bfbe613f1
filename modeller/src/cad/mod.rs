//! The exact surface and the curves for CAD: STEP (ISO 10303-21, AP214) and IGES 5.3.
//!
//! Nothing is approximated. A bicubic Bezier patch `S(u,v) = Σ B_i³(u) B_j³(v) P_ij` *is* the
//! degree 3×3 B-spline surface on the knot vectors `0,0,0,0,1,1,1,1` with the same control
//! points, so each patch is written as such a surface carrying its own 16 control points;
//! a Bezier curve of degree `d` is the B-spline on `d+1` zeros and `d+1` ones, and a
//! B-spline curve is written with its own knots. Coordinates are multiplied by the scale
//! (file units per model unit) and nothing else; the file's unit is chosen ([`CadUnit`]:
//! millimetres by default, centimetres, metres or inches).
//!
//! With [`CadOptions::one_surface`] the whole grid is written as **one** bicubic B-spline
//! surface instead: the exact regulation keeps every grid line at a constant spacing ratio, so
//! the grid is exactly one B-spline with double interior knots spaced by the patch widths
//! ([`crate::surface::GridSpline`], whose module docs carry the proof); a grid that is not
//! (regulated another way) is refused ([`CadError::NotOneSurface`]).
//!
//! The model's name ([`CadOptions::name`], the model file's stem) names the STEP product and
//! the IGES file.
//!
//! - [`step`]: one `ADVANCED_FACE` per patch, sewn into one shell (each shared boundary curve
//!   one `EDGE_CURVE` used by the two faces), a closed shell and a `MANIFOLD_SOLID_BREP` for
//!   closed topologies (sphere, torus), an open shell otherwise; [`step_one`]: the one face.
//! - [`iges`]: entity 128 (rational B-spline surface, weights 1) per patch (or one for the
//!   whole grid) and 126 per curve, all in one group (entity 402).
//! - [`real`]: the number syntax both formats share (`3.`, `2.08E-17`).

pub mod iges;
pub mod real;
pub mod step;
pub mod step_one;

use std::path::Path;

use crate::model::{Model, first_non_finite};
use crate::surface::{GridSpline, NotOneSpline, ONE_SPLINE_TOLERANCE};

/// What can go wrong writing a CAD file.
#[derive(Debug, thiserror::Error)]
pub enum CadError {
    /// Writing the encoded file failed.
    #[error("cannot write the file: {0}")]
    Io(#[from] std::io::Error),
    /// The file could not be created, replaced or synced (the message does not name it:
    /// callers do).
    #[error("cannot write the file: {}", .0.reason())]
    Write(#[from] nendo_file::WriteError),
    /// A control point of the surface is NaN or infinite.
    #[error("patch {patch} control point {point} is not finite; nothing written")]
    NonFinite {
        /// The patch.
        patch: usize,
        /// The control point, `4 i + j`.
        point: usize,
    },
    /// A control point of a curve is NaN or infinite (or a knot is).
    #[error("curve {curve} has a coordinate or knot that is not finite; nothing written")]
    NonFiniteCurve {
        /// The curve.
        curve: usize,
    },
    /// The scale is not a positive number, or it makes a coordinate overflow.
    #[error(
        "the scale must be a positive number that keeps coordinates finite, not {}",
        crate::num::Compact(*.0)
    )]
    BadScale(f64),
    /// `--one-surface` on a grid that is not one B-spline surface.
    #[error("cannot write one surface: {0}; export per patch instead")]
    NotOneSurface(#[from] NotOneSpline),
}

/// The length unit a CAD file declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CadUnit {
    /// Millimetres (the default).
    #[default]
    Millimetre,
    /// Centimetres.
    Centimetre,
    /// Metres.
    Metre,
    /// Inches (25.4 mm).
    Inch,
}

impl CadUnit {
    /// Every unit, in the order of the option's help.
    pub const ALL: [CadUnit; 4] = [
        CadUnit::Millimetre,
        CadUnit::Centimetre,
        CadUnit::Metre,
        CadUnit::Inch,
    ];

    /// The name on the command line and in IGES's global section (`mm`, `cm`, `m`, `in`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CadUnit::Millimetre => "mm",
            CadUnit::Centimetre => "cm",
            CadUnit::Metre => "m",
            CadUnit::Inch => "in",
        }
    }

    /// STEP's SI prefix of the metre (`None`: the metre itself; the inch is not SI).
    #[must_use]
    pub fn si_prefix(self) -> Option<&'static str> {
        match self {
            CadUnit::Millimetre => Some(".MILLI."),
            CadUnit::Centimetre => Some(".CENTI."),
            CadUnit::Metre | CadUnit::Inch => None,
        }
    }

    /// IGES's unit flag (global parameter 14) and name (15): 2 `MM`, 10 `CM`, 6 `M`, 1 `IN`.
    #[must_use]
    pub fn iges_flag(self) -> (u32, &'static str) {
        match self {
            CadUnit::Millimetre => (2, "MM"),
            CadUnit::Centimetre => (10, "CM"),
            CadUnit::Metre => (6, "M"),
            CadUnit::Inch => (1, "IN"),
        }
    }

    /// Millimetres per unit.
    #[must_use]
    pub fn millimetres(self) -> f64 {
        match self {
            CadUnit::Millimetre => 1.0,
            CadUnit::Centimetre => 10.0,
            CadUnit::Metre => 1000.0,
            CadUnit::Inch => 25.4,
        }
    }
}

impl std::fmt::Display for CadUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`CadUnit`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown unit {0:?}: expected mm, cm, m or in")]
pub struct UnknownCadUnit(pub String);

impl std::str::FromStr for CadUnit {
    type Err = UnknownCadUnit;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let lower = s.to_ascii_lowercase();
        CadUnit::ALL
            .into_iter()
            .find(|u| u.name() == lower)
            .ok_or_else(|| UnknownCadUnit(s.to_owned()))
    }
}

/// How a CAD file is written.
#[derive(Debug, Clone, PartialEq)]
pub struct CadOptions {
    /// File units per model unit (a positive number).
    pub scale: f64,
    /// The file's length unit.
    pub unit: CadUnit,
    /// The model's name: the STEP product and the IGES file name.
    pub name: String,
    /// The whole grid as one B-spline surface instead of one per patch.
    pub one_surface: bool,
}

impl CadOptions {
    /// Per patch, millimetres, scale 1, for the model called `name`.
    #[must_use]
    pub fn named(name: &str) -> Self {
        Self {
            scale: 1.0,
            unit: CadUnit::Millimetre,
            name: name.to_owned(),
            one_surface: false,
        }
    }

    /// The model name of a model file: its stem (`nendo` if it has none).
    #[must_use]
    pub fn name_of(path: &Path) -> String {
        path.file_stem()
            .and_then(|n| n.to_str())
            .filter(|n| !n.is_empty())
            .unwrap_or("nendo")
            .to_owned()
    }
}

/// A CAD file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CadFormat {
    /// STEP, ISO 10303-21, application protocol 214 (`AUTOMOTIVE_DESIGN`).
    Step,
    /// IGES 5.3.
    Iges,
}

impl CadFormat {
    /// Every format, in menu order.
    pub const ALL: [CadFormat; 2] = [CadFormat::Step, CadFormat::Iges];

    /// The file extensions that name the format (lower case, no dot), usual one first.
    #[must_use]
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            CadFormat::Step => &["step", "stp"],
            CadFormat::Iges => &["igs", "iges"],
        }
    }

    /// The format a path's extension names (case-insensitive), if any.
    #[must_use]
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        Self::ALL
            .into_iter()
            .find(|f| f.extensions().contains(&ext.as_str()))
    }

    /// The format's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CadFormat::Step => "STEP AP214",
            CadFormat::Iges => "IGES 5.3",
        }
    }

    /// The whole file for `model` as `options` say; `file_name` is the file name recorded in
    /// STEP's header.
    ///
    /// # Errors
    /// As [`check`]; [`CadError::NotOneSurface`] for a one-surface export of a grid that is
    /// not one B-spline surface.
    pub fn encode(
        self,
        model: &Model,
        options: &CadOptions,
        file_name: &str,
    ) -> Result<Vec<u8>, CadError> {
        check(model, options.scale)?;
        let spline = one_surface(model, options)?;
        let stamp = HeaderTimestamp::now();
        Ok(match self {
            CadFormat::Step => {
                step::encode(model, options, spline.as_ref(), file_name, &stamp).into_bytes()
            }
            CadFormat::Iges => iges::encode(model, options, spline.as_ref(), &stamp).into_bytes(),
        })
    }
}

/// Refuses a model that cannot be written: a non-finite control point or knot, a scale that is
/// not a positive number, or one that makes a coordinate overflow.
///
/// # Errors
/// [`CadError::NonFinite`], [`CadError::NonFiniteCurve`], [`CadError::BadScale`].
pub fn check(model: &Model, scale: f64) -> Result<(), CadError> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(CadError::BadScale(scale));
    }
    if let Some((patch, point)) = first_non_finite(&model.surface) {
        return Err(CadError::NonFinite { patch, point });
    }
    if model
        .surface
        .nodes()
        .iter()
        .any(|p| !(*p * scale).is_finite())
    {
        return Err(CadError::BadScale(scale));
    }
    for (k, c) in model.curves.iter().enumerate() {
        let (coords, knots) = curve_numbers(c);
        if knots.iter().any(|t| !t.is_finite()) || coords.iter().any(|x| !x.is_finite()) {
            return Err(CadError::NonFiniteCurve { curve: k });
        }
        if coords.iter().any(|x| !(x * scale).is_finite()) {
            return Err(CadError::BadScale(scale));
        }
    }
    Ok(())
}

/// The grid as one B-spline surface when `options` ask for it (checked against the patches
/// with [`ONE_SPLINE_TOLERANCE`]).
///
/// # Errors
/// [`CadError::NotOneSurface`] when the grid is not one.
pub fn one_surface(model: &Model, options: &CadOptions) -> Result<Option<GridSpline>, CadError> {
    if !options.one_surface {
        return Ok(None);
    }
    Ok(Some(model.surface.one_spline(ONE_SPLINE_TOLERANCE)?))
}

/// Writes `model` to `path` in `format` with the one safe writer ([`nendo_file`]):
/// atomically, the target untouched on failure. Returns the number of bytes written.
///
/// # Errors
/// As [`CadFormat::encode`], or [`CadError::Write`] from the file system.
pub fn save_cad(
    path: &Path,
    format: CadFormat,
    model: &Model,
    options: &CadOptions,
) -> Result<usize, CadError> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("nendo");
    let bytes = format.encode(model, options, name)?;
    nendo_file::write_atomic(path, |file| {
        std::io::Write::write_all(file, &bytes)?;
        Ok::<(), CadError>(())
    })?;
    Ok(bytes.len())
}

/// A curve as the B-spline written for it: degree, the full knot vector (`n + p + 1`
/// values), and the control points in 3D (a planar curve at `z = 0`).
#[derive(Debug, Clone, PartialEq)]
pub struct CurveSpline {
    /// The degree.
    pub degree: usize,
    /// The knot vector.
    pub knots: Vec<f64>,
    /// The control points.
    pub points: Vec<glam::DVec3>,
}

impl CurveSpline {
    /// The B-spline of a model curve: a Bezier curve of degree `d` on `d+1` zeros and `d+1`
    /// ones, a B-spline with its own knots.
    #[must_use]
    pub fn of(curve: &crate::curve::json::DynCurve) -> Self {
        use crate::curve::Curve;
        use crate::curve::json::DynCurve;
        fn parts<P: crate::curve::Point>(
            c: &Curve<P>,
            lift: impl Fn(&P) -> glam::DVec3,
        ) -> CurveSpline {
            let points: Vec<glam::DVec3> = c.points().iter().map(lift).collect();
            match c {
                Curve::Bezier(b) => {
                    let d = b.degree();
                    let mut knots = vec![0.0; d + 1];
                    knots.extend(std::iter::repeat_n(1.0, d + 1));
                    CurveSpline {
                        degree: d,
                        knots,
                        points,
                    }
                }
                Curve::BSpline(s) => CurveSpline {
                    degree: s.degree(),
                    knots: s.knots().to_vec(),
                    points,
                },
            }
        }
        match curve {
            DynCurve::D2(c) => parts(c, |p| p.extend(0.0)),
            DynCurve::D3(c) => parts(c, |p| *p),
        }
    }

    /// True when every control point lies in `z = 0` (a planar curve).
    #[must_use]
    pub fn planar_z(&self) -> bool {
        self.points.iter().all(|p| p.z == 0.0)
    }

    /// The distinct knots and their multiplicities.
    #[must_use]
    pub fn knots_with_multiplicities(&self) -> (Vec<f64>, Vec<usize>) {
        let mut values: Vec<f64> = Vec::new();
        let mut mults: Vec<usize> = Vec::new();
        for &t in &self.knots {
            match values.last() {
                Some(&last) if last == t => {
                    if let Some(m) = mults.last_mut() {
                        *m += 1;
                    }
                }
                _ => {
                    values.push(t);
                    mults.push(1);
                }
            }
        }
        (values, mults)
    }
}

fn curve_numbers(c: &crate::curve::json::DynCurve) -> (Vec<f64>, Vec<f64>) {
    let s = CurveSpline::of(c);
    let coords = s.points.iter().flat_map(|p| p.to_array()).collect();
    (coords, s.knots)
}

/// A UTC date and time for file headers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HeaderTimestamp {
    /// Year.
    pub year: i64,
    /// Month, 1–12.
    pub month: u32,
    /// Day, 1–31.
    pub day: u32,
    /// Hour, minute, second.
    pub hms: (u32, u32, u32),
}

impl HeaderTimestamp {
    /// Now, from the system clock (the epoch if the clock is before it).
    #[must_use]
    pub fn now() -> Self {
        let secs = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Self::from_unix(secs)
    }

    /// The civil UTC time of a Unix time (Howard Hinnant's `civil_from_days`).
    #[must_use]
    pub fn from_unix(secs: u64) -> Self {
        let days = (secs / 86_400) as i64;
        let rem = (secs % 86_400) as u32;
        let z = days + 719_468;
        let era = z.div_euclid(146_097);
        let doe = z - era * 146_097;
        let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
        let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
        let mp = (5 * doy + 2) / 153;
        let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
        let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
        let year = yoe + era * 400 + i64::from(month <= 2);
        Self {
            year,
            month,
            day,
            hms: (rem / 3600, rem / 60 % 60, rem % 60),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates_of_known_unix_times() {
        let t = HeaderTimestamp::from_unix(0);
        assert_eq!((t.year, t.month, t.day, t.hms), (1970, 1, 1, (0, 0, 0)));
        // 2000-02-29 12:34:56 UTC and 2026-12-02 03:53:38 UTC.
        let t = HeaderTimestamp::from_unix(951_827_696);
        assert_eq!((t.year, t.month, t.day, t.hms), (2000, 2, 29, (12, 34, 56)));
        let t = HeaderTimestamp::from_unix(1_796_183_618);
        assert_eq!((t.year, t.month, t.day, t.hms), (2026, 12, 2, (3, 53, 38)));
    }

    #[test]
    fn formats_by_extension() {
        for (name, f) in [
            ("a.step", Some(CadFormat::Step)),
            ("a.STP", Some(CadFormat::Step)),
            ("a.igs", Some(CadFormat::Iges)),
            ("a.Iges", Some(CadFormat::Iges)),
            ("a.obj", None),
            ("a", None),
        ] {
            assert_eq!(CadFormat::from_path(Path::new(name)), f, "{name}");
        }
    }
}
