//! Shape functions: the ideal shape a finger asks for (P2 §5; docs/design.md §11).
//!
//! An operation presses a virtual finger of radius `r_f` along the unit direction
//! `d̂ = unit(dir)` by `depth`: the finger's movement vector is `M = depth · d̂` (a negative
//! depth reverses `M`: a pull). Every surface sample within `r_f` of the finger moves by
//!
//! ```text
//! F = (b − a r²) · unit(M) = (1 − r²/r_f²) · M,     a = |M| / r_f²,  b = |M|,  r < r_f
//! ```
//!
//! (the paper's `d = a r² − b` read as a displacement of `−d` along `M`): a paraboloid of
//! depth `|M|` on the finger's axis, zero at `r = r_f`. `r` is the distance to the finger:
//!
//! - **push / pull** (§5.1): the finger is the half-line that ends at the pressed tip
//!   `at + |depth|·d̂` and extends back against `d̂`. A pull uses the same finger with `M`
//!   reversed, so pull is the exact mirror of push (bit for bit). Samples beyond the tip (the
//!   far side of a closed shape) are further than `r` from the finger than the tip distance,
//!   which keeps them still.
//! - **draw a line / drag** (§5.2): the finger, pressed the same way, is swept along a polyline
//!   `at_0, at_1, …`; each segment sweeps a half-strip (the segment between two pressed tips
//!   and everything behind it against `d̂`: the paper's finite plane `S_f` spanned by the
//!   finger centre-line `L_f = M` and the stroke `M_f`). `r` is the distance to the whole swept
//!   surface — the union of the half-strips — so the groove has depth `|L_f|` all along the
//!   stroke and the joints of the polyline are not pressed twice. Samples move parallel to
//!   `L_f` by `b − a r²`, `b = |L_f|`, `a = b / r_f²`.

use glam::DVec3;

use super::brush::{Brush, Falloff};
use super::sculpt_brush::SculptBrush;
use crate::surface::bounds::Aabb;
use crate::surface::error::SurfaceError;

/// One deformation operation.
#[derive(Debug, Clone, PartialEq)]
pub enum Op {
    /// Push (positive depth) or pull (negative depth) at one point.
    Push {
        /// Where the finger touches.
        at: DVec3,
        /// The finger's direction (any length but zero).
        dir: DVec3,
        /// How far the finger presses along `dir` (negative: pull).
        depth: f64,
        /// The finger radius `r_f`.
        radius: f64,
    },
    /// Draw a line: the finger pressed along `dir` and dragged along `path`.
    Drag {
        /// The stroke, at least two points.
        path: Vec<DVec3>,
        /// The finger's direction (any length but zero).
        dir: DVec3,
        /// How far the finger presses along `dir` (negative: a ridge).
        depth: f64,
        /// The finger radius `r_f`.
        radius: f64,
    },
    /// Push (positive depth) or pull (negative depth) along the surface's inward normal at
    /// the surface point nearest `at` (`"dir": "normal"`).
    PushNormal {
        /// Where the finger touches.
        at: DVec3,
        /// How far the finger presses along the inward normal (negative: pull, outward).
        depth: f64,
        /// The finger radius `r_f`.
        radius: f64,
    },
    /// Draw a line whose direction varies along the path (`"dir": "normal"` or `"dirs"`).
    Groove {
        /// The stroke, at least two points.
        path: Vec<DVec3>,
        /// The direction at each path point.
        dirs: Dirs,
        /// How far the finger presses along each point's direction (negative: a ridge).
        depth: f64,
        /// The finger radius `r_f`.
        radius: f64,
    },
    /// Grab and move: the surface point nearest `at` goes exactly to `to`, the clay within
    /// `radius` of it follows with the falloff `1 − r²/r_f²` ([`crate::surface::grab`]).
    Move {
        /// Where the clay is grabbed (the surface point nearest it is taken).
        at: DVec3,
        /// Where the grabbed point goes.
        to: DVec3,
        /// The finger radius `r_f`.
        radius: f64,
    },
    /// Smooth: one implicit fairing dab on the surface within `radius` of `at`
    /// ([`crate::surface::fairing`]).
    Smooth {
        /// The centre of the brush.
        at: DVec3,
        /// The brush radius.
        radius: f64,
        /// The dab's diffusion time in units of [`crate::surface::fairing::DIFFUSION`]` · r²`,
        /// `0 < s ≤ 1`.
        strength: f64,
    },
    /// A pressing operation (push, pull, draw a line) with a brush: its falloff and the
    /// fraction of its depth pressed ([`super::brush`]).
    Brushed {
        /// The push, pull or drag.
        op: Box<Op>,
        /// The brush.
        brush: Brush,
    },
    /// Inflate, flatten, pinch or crease: a brush that follows the surface ([`super::sculpt_brush`]).
    Sculpt(SculptBrush),
}

/// The directions of a [`Op::Groove`].
#[derive(Debug, Clone, PartialEq)]
pub enum Dirs {
    /// Each path point presses along the surface's inward normal at the surface point nearest
    /// to it (outward for a negative depth).
    Normal,
    /// One direction per path point (any length but zero).
    Each(Vec<DVec3>),
}

/// Largest angle between the directions of the two ends of one swept strip of a groove; a
/// longer turn is split into strips with interpolated directions.
pub const GROOVE_TURN_DEG: f64 = 5.0;

impl Op {
    /// Checks every number and constraint of the operation without a surface: finite
    /// coordinates, a non-zero direction, a positive radius, a path of two points or more with
    /// one direction per point, `0 < strength ≤ 1`.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] saying what is wrong.
    pub fn validate(&self) -> Result<(), SurfaceError> {
        let bad = |s: &str| Err(SurfaceError::BadOp(s.to_string()));
        let radius_ok = |r: f64| r.is_finite() && r > 0.0;
        match self {
            Op::Sculpt(b) => b.validate(),
            Op::Brushed { op, brush } => {
                brush.validate()?;
                match **op {
                    Op::Push { .. }
                    | Op::PushNormal { .. }
                    | Op::Drag { .. }
                    | Op::Groove { .. } => op.validate(),
                    _ => bad("a brush applies to push, pull and drag only"),
                }
            }
            Op::Push { .. } | Op::Drag { .. } => self.finger().map(|_| ()),
            Op::PushNormal { at, depth, radius } => {
                if !at.is_finite() {
                    return bad("at must be finite");
                }
                if !depth.is_finite() {
                    return bad("depth must be finite");
                }
                if !radius_ok(*radius) {
                    return bad("radius must be a positive finite number");
                }
                Ok(())
            }
            Op::Groove {
                path,
                dirs,
                depth,
                radius,
            } => {
                if path.len() < 2 {
                    return bad("a drag path needs at least two points");
                }
                if path.iter().any(|p| !p.is_finite()) {
                    return bad("every path point must be finite");
                }
                if !depth.is_finite() {
                    return bad("depth must be finite");
                }
                if !radius_ok(*radius) {
                    return bad("radius must be a positive finite number");
                }
                if let Dirs::Each(d) = dirs {
                    if d.len() != path.len() {
                        return bad("dirs needs one direction per path point");
                    }
                    if d.iter().any(|x| !x.is_finite()) {
                        return bad("every direction in dirs must be finite");
                    }
                    if d.iter().any(|x| x.try_normalize().is_none()) {
                        return bad("no direction in dirs may be zero");
                    }
                }
                Ok(())
            }
            Op::Move { at, to, radius } => {
                if !at.is_finite() {
                    return bad("at must be finite");
                }
                if !to.is_finite() {
                    return bad("to must be finite");
                }
                if !radius_ok(*radius) {
                    return bad("radius must be a positive finite number");
                }
                Ok(())
            }
            Op::Smooth {
                at,
                radius,
                strength,
            } => {
                if !at.is_finite() {
                    return bad("at must be finite");
                }
                if !radius_ok(*radius) {
                    return bad("radius must be a positive finite number");
                }
                if !(strength.is_finite() && *strength > 0.0 && *strength <= 1.0) {
                    return bad("strength must be a number with 0 < strength <= 1");
                }
                Ok(())
            }
        }
    }

    /// The finger of an operation that presses (push, pull, draw a line), its directions
    /// along the surface normals of `grid` where the operation asks for them.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for an invalid operation, one that is not a finger (move,
    /// smooth), or a surface point without a normal where one is needed.
    pub fn finger_on(&self, grid: &crate::surface::Grid) -> Result<Finger, SurfaceError> {
        self.validate()?;
        match self {
            Op::Brushed { op, brush } => {
                Ok(op.scaled(brush.strength).finger_on(grid)?.with(*brush))
            }
            Op::PushNormal { at, depth, radius } => {
                let dir = inward_normal(grid, *at)?;
                Op::Push {
                    at: *at,
                    dir,
                    depth: *depth,
                    radius: *radius,
                }
                .finger()
            }
            Op::Groove {
                path,
                dirs: Dirs::Normal,
                depth,
                radius,
            } => {
                let mut dirs = Vec::with_capacity(path.len());
                for p in path {
                    dirs.push(inward_normal(grid, *p)?);
                }
                // Where the normal turns fast, the points between are pressed along their
                // own nearest normals.
                let (mut pts, mut ds) = (vec![path[0]], vec![dirs[0]]);
                for k in 1..path.len() {
                    let pieces = turn_pieces(dirs[k - 1], dirs[k]);
                    for i in 1..pieces {
                        let x = path[k - 1].lerp(path[k], i as f64 / pieces as f64);
                        pts.push(x);
                        ds.push(inward_normal(grid, x)?);
                    }
                    pts.push(path[k]);
                    ds.push(dirs[k]);
                }
                Finger::bent(&pts, &ds, *depth, *radius)
            }
            _ => self.finger(),
        }
    }

    /// The finger the operation describes, after validation.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] when a number is not finite, `dir` is zero, the radius is not
    /// positive, or a drag path has fewer than two points; and for an operation whose finger
    /// depends on the surface (along the normal: see [`Op::finger_on`]) or that is no finger
    /// (move, smooth).
    pub fn finger(&self) -> Result<Finger, SurfaceError> {
        let bad = |s: &str| Err(SurfaceError::BadOp(s.to_string()));
        let (dir, depth, radius) = match self {
            Op::Push {
                dir, depth, radius, ..
            }
            | Op::Drag {
                dir, depth, radius, ..
            } => (*dir, *depth, *radius),
            Op::Groove {
                path,
                dirs: Dirs::Each(dirs),
                depth,
                radius,
            } => {
                self.validate()?;
                let units: Vec<DVec3> = dirs.iter().map(|d| d.normalize()).collect();
                return Finger::bent(path, &units, *depth, *radius);
            }
            Op::PushNormal { .. } | Op::Groove { .. } => {
                return bad("a direction along the normal needs the surface (Op::finger_on)");
            }
            Op::Brushed { op, brush } => {
                self.validate()?;
                return Ok(op.scaled(brush.strength).finger()?.with(*brush));
            }
            Op::Move { .. } | Op::Smooth { .. } | Op::Sculpt(_) => {
                return bad("move, smooth and the surface brushes are not pressing fingers");
            }
        };
        if !dir.is_finite() {
            return bad("dir must be finite");
        }
        let Some(axis) = dir.try_normalize() else {
            return bad("dir must not be zero");
        };
        if !depth.is_finite() {
            return bad("depth must be finite");
        }
        if !(radius.is_finite() && radius > 0.0) {
            return bad("radius must be a positive finite number");
        }
        let press = axis * depth.abs();
        let movement = axis * depth;
        let shape = match self {
            Op::Push { at, .. } => {
                if !at.is_finite() {
                    return bad("at must be finite");
                }
                Reach::HalfLine { tip: *at + press }
            }
            Op::Drag { path, .. } => {
                if path.len() < 2 {
                    return bad("a drag path needs at least two points");
                }
                if path.iter().any(|p| !p.is_finite()) {
                    return bad("every path point must be finite");
                }
                let strips = path
                    .windows(2)
                    .map(|w| Strip::new(w[0] + press, w[1] + press, axis, movement))
                    .collect();
                Reach::Strips(strips)
            }
            _ => return bad("not a pressing finger"),
        };
        Ok(Finger {
            axis,
            movement,
            radius,
            radius_sq: radius * radius,
            shape,
            falloff: Falloff::Finger,
        })
    }
}

/// A validated finger: its reach and the flow it imposes on samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Finger {
    axis: DVec3,
    movement: DVec3,
    radius: f64,
    radius_sq: f64,
    shape: Reach,
    /// The brush profile `w(r²/r_f²)` ([`super::brush`]).
    falloff: Falloff,
}

#[derive(Debug, Clone, PartialEq)]
enum Reach {
    HalfLine {
        tip: DVec3,
    },
    /// Half-strips, each with its own movement (one for a straight drag).
    Strips(Vec<Strip>),
    /// A ball around a grabbed point (`r` = the distance to it).
    Ball {
        centre: DVec3,
    },
}

/// The half-strip swept by the finger between two pressed tips.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Strip {
    t0: DVec3,
    t1: DVec3,
    /// Unit component of `t1 − t0` across the finger (zero when the stroke runs along it).
    across: DVec3,
    /// Unit normal of the strip's plane.
    normal: DVec3,
    /// `|t1 − t0|` across the finger.
    len: f64,
    /// `(t1 − t0)·d̂`: how much deeper the second tip is.
    rise: f64,
    /// `d̂`.
    axis: DVec3,
    /// The movement `depth · d̂` of the clay this strip presses.
    movement: DVec3,
}

impl Strip {
    fn new(t0: DVec3, t1: DVec3, axis: DVec3, movement: DVec3) -> Self {
        let e = t1 - t0;
        let rise = e.dot(axis);
        let perp = e - rise * axis;
        let len = perp.length();
        let scale = t0.abs().max_element().max(t1.abs().max_element()).max(1.0);
        if len > 1e-12 * scale {
            let across = perp / len;
            Strip {
                t0,
                t1,
                across,
                normal: across.cross(axis),
                len,
                rise,
                axis,
                movement,
            }
        } else {
            // The stroke runs along the finger: the sweep is the half-line behind the deeper tip.
            let deeper = if rise > 0.0 { t1 } else { t0 };
            Strip {
                t0: deeper,
                t1: deeper,
                across: DVec3::ZERO,
                normal: DVec3::ZERO,
                len: 0.0,
                rise: 0.0,
                axis,
                movement,
            }
        }
    }

    /// Squared distance from `x` to the half-strip.
    #[inline]
    fn distance_sq(&self, x: DVec3) -> f64 {
        let w = x - self.t0;
        if self.len == 0.0 {
            return half_line_distance_sq(w, self.axis);
        }
        let (px, py, pz) = (w.dot(self.across), w.dot(self.axis), w.dot(self.normal));
        let (l, k) = (self.len, self.rise / self.len);
        // In the strip's plane: the region 0 ≤ x ≤ l, y ≤ k x.
        if (0.0..=l).contains(&px) && py <= k * px {
            return pz * pz;
        }
        // Left ray (0, y ≤ 0), right ray (l, y ≤ k l), top segment (0,0)–(l, k l).
        let left = px * px + sq(py.max(0.0));
        let right = sq(px - l) + sq((py - k * l).max(0.0));
        let s = ((px * l + py * k * l) / (l * l * (1.0 + k * k))).clamp(0.0, 1.0);
        let top = sq(px - s * l) + sq(py - s * k * l);
        left.min(right).min(top) + pz * pz
    }

    /// True when the strip, cut off `depth` behind its tips, may come within `r` of the box.
    fn may_touch(&self, b: &Aabb, r: f64, depth: f64) -> bool {
        let bb = b.inflated(r);
        if self.len == 0.0 {
            return bb.clip_line(self.t0, -self.axis, 0.0, depth).is_some();
        }
        let back = -self.axis * depth;
        let q = [self.t0, self.t1, self.t1 + back, self.t0 + back];
        let (c, h) = (bb.center(), bb.half_extents());
        let e1 = self.t1 - self.t0;
        let mut axes = [DVec3::ZERO; 10];
        axes[0] = DVec3::X;
        axes[1] = DVec3::Y;
        axes[2] = DVec3::Z;
        axes[3] = self.normal;
        for (k, ek) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            axes[4 + 2 * k] = e1.cross(ek);
            axes[5 + 2 * k] = self.axis.cross(ek);
        }
        for a in axes {
            if a.length_squared() < 1e-24 {
                continue;
            }
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for p in q {
                let d = (p - c).dot(a);
                lo = lo.min(d);
                hi = hi.max(d);
            }
            let extent = h.x * a.x.abs() + h.y * a.y.abs() + h.z * a.z.abs();
            if lo > extent || hi < -extent {
                return false;
            }
        }
        true
    }
}

#[inline]
fn sq(x: f64) -> f64 {
    x * x
}

/// Squared distance from the point `tip + w` to the half-line `tip − s·axis`, `s ≥ 0`.
#[inline]
fn half_line_distance_sq(w: DVec3, axis: DVec3) -> f64 {
    let behind = -w.dot(axis);
    let d2 = w.length_squared();
    if behind > 0.0 {
        (d2 - behind * behind).max(0.0)
    } else {
        d2
    }
}

impl Finger {
    /// A draw-a-line finger whose direction varies along the path: `dirs[k]` (unit) at
    /// `path[k]`. Each segment whose end directions turn by more than [`GROOVE_TURN_DEG`] is
    /// split, the directions between interpolated (normalised linear blend); each piece is a
    /// half-strip pressed along the unit mean of its end directions, and a sample moves by
    /// the movement of the nearest strip (`(1 − r²/r_f²)·depth·d̂_k`): for one direction
    /// everywhere this is exactly [`Op::Drag`].
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for a non-finite number, a radius that is not positive, fewer
    /// than two points, a count of directions other than the path's, or two consecutive
    /// directions that are opposite.
    pub fn bent(
        path: &[DVec3],
        dirs: &[DVec3],
        depth: f64,
        radius: f64,
    ) -> Result<Finger, SurfaceError> {
        let bad = |s: &str| Err(SurfaceError::BadOp(s.to_string()));
        if path.len() < 2 || dirs.len() != path.len() {
            return bad("a groove needs two points or more and one direction per point");
        }
        if !(depth.is_finite() && radius.is_finite() && radius > 0.0)
            || path.iter().chain(dirs).any(|x| !x.is_finite())
        {
            return bad("a groove's numbers must be finite and its radius positive");
        }
        let mut strips = Vec::with_capacity(path.len());
        for k in 1..path.len() {
            let (d0, d1) = (dirs[k - 1], dirs[k]);
            let pieces = turn_pieces(d0, d1);
            let at = |i: usize| {
                let t = i as f64 / pieces as f64;
                (path[k - 1].lerp(path[k], t), d0.lerp(d1, t).try_normalize())
            };
            for i in 0..pieces {
                let ((p0, a0), (p1, a1)) = (at(i), at(i + 1));
                let (Some(a0), Some(a1)) = (a0, a1) else {
                    return bad("two consecutive groove directions are opposite");
                };
                let Some(axis) = (a0 + a1).try_normalize() else {
                    return bad("two consecutive groove directions are opposite");
                };
                let press = axis * depth.abs();
                strips.push(Strip::new(p0 + press, p1 + press, axis, axis * depth));
            }
        }
        let first = strips[0];
        Ok(Finger {
            axis: first.axis,
            movement: first.movement,
            radius,
            radius_sq: radius * radius,
            shape: Reach::Strips(strips),
            falloff: Falloff::Finger,
        })
    }

    /// The grab finger of a move: every point within `radius` of `centre` moves by
    /// `(1 − r²/r_f²)·movement`, `r` its distance to `centre`.
    pub(crate) fn ball(centre: DVec3, movement: DVec3, radius: f64) -> Finger {
        Finger {
            axis: movement.try_normalize().unwrap_or(DVec3::Z),
            movement,
            radius,
            radius_sq: radius * radius,
            shape: Reach::Ball { centre },
            falloff: Falloff::Finger,
        }
    }

    /// This finger moving the clay by the brush's falloff (its strength is already in the
    /// depth).
    fn with(mut self, brush: Brush) -> Finger {
        self.falloff = brush.falloff;
        self
    }

    /// The brush profile.
    #[must_use]
    pub fn falloff(&self) -> Falloff {
        self.falloff
    }

    /// The unit finger direction `d̂` (of the first strip for a groove).
    #[must_use]
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// The movement vector `M = depth · d̂` (`L_f` for a drag; the first strip's for a groove).
    #[must_use]
    pub fn movement(&self) -> DVec3 {
        self.movement
    }

    /// The finger radius `r_f`.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Squared distance `r²` from `x` to the finger (the half-line, the swept half-strips, or
    /// the grabbed point).
    #[must_use]
    pub fn distance_sq(&self, x: DVec3) -> f64 {
        match &self.shape {
            Reach::HalfLine { tip } => half_line_distance_sq(x - *tip, self.axis),
            Reach::Strips(strips) => strips
                .iter()
                .map(|s| s.distance_sq(x))
                .fold(f64::INFINITY, f64::min),
            Reach::Ball { centre } => (x - *centre).length_squared(),
        }
    }

    /// The flow vector `F = (1 − r²/r_f²)·M` for `r < r_f`, zero beyond (see the module docs;
    /// `M` is the nearest strip's for a groove).
    #[inline]
    #[must_use]
    pub fn flow(&self, x: DVec3) -> DVec3 {
        match &self.shape {
            Reach::Strips(strips) => self.strip_flow(x, strips, 0..strips.len()),
            _ => self.scaled(self.distance_sq(x), self.movement),
        }
    }

    #[inline]
    fn scaled(&self, r2: f64, movement: DVec3) -> DVec3 {
        if r2 < self.radius_sq {
            movement * self.falloff.weight(r2 / self.radius_sq)
        } else {
            DVec3::ZERO
        }
    }

    /// The flow of the nearest of the listed strips.
    #[inline]
    fn strip_flow(
        &self,
        x: DVec3,
        strips: &[Strip],
        listed: impl IntoIterator<Item = usize>,
    ) -> DVec3 {
        let mut best = (f64::INFINITY, self.movement);
        for k in listed {
            let d = strips[k].distance_sq(x);
            if d < best.0 {
                best = (d, strips[k].movement);
            }
        }
        self.scaled(best.0, best.1)
    }

    /// The point the finger asks `x` to move to: `x + F(x)`.
    #[must_use]
    pub fn ideal(&self, x: DVec3) -> DVec3 {
        x + self.flow(x)
    }

    /// True when some point of the box may lie within `r_f` of the finger. Conservative; the
    /// finger's infinite extent behind its tips is cut off `depth` behind them (callers pass a
    /// depth past which nothing exists).
    #[must_use]
    pub fn may_touch(&self, b: &Aabb, depth: f64) -> bool {
        match &self.shape {
            Reach::HalfLine { tip } => b
                .inflated(self.radius)
                .clip_line(*tip, -self.axis, 0.0, depth)
                .is_some(),
            Reach::Strips(strips) => strips.iter().any(|s| s.may_touch(b, self.radius, depth)),
            Reach::Ball { centre } => {
                let bb = b.inflated(self.radius);
                bb.min.cmple(*centre).all() && centre.cmple(bb.max).all()
            }
        }
    }

    /// How far behind its tips the finger must reach to pass everything in `world` (the
    /// largest distance from a tip to a corner of `world` grown by `r_f`).
    #[must_use]
    pub fn reach_depth(&self, world: &Aabb) -> f64 {
        let w = world.inflated(self.radius);
        let far = |t: DVec3| {
            let mut d = 0.0f64;
            for k in 0..8 {
                let c = DVec3::new(
                    if k & 1 == 0 { w.min.x } else { w.max.x },
                    if k & 2 == 0 { w.min.y } else { w.max.y },
                    if k & 4 == 0 { w.min.z } else { w.max.z },
                );
                d = d.max((c - t).length());
            }
            d
        };
        match &self.shape {
            Reach::HalfLine { tip } => far(*tip),
            Reach::Strips(strips) => strips
                .iter()
                .map(|s| far(s.t0).max(far(s.t1)))
                .fold(0.0, f64::max),
            Reach::Ball { centre } => far(*centre),
        }
    }

    /// A copy of this finger keeping only the drag segments that may touch `b` (the same
    /// finger for a push). Used to cut the work per patch.
    pub(crate) fn restricted_to(&self, b: &Aabb, depth: f64, into: &mut Vec<usize>) -> bool {
        into.clear();
        match &self.shape {
            Reach::HalfLine { .. } | Reach::Ball { .. } => true,
            Reach::Strips(strips) => {
                into.extend(
                    (0..strips.len()).filter(|&k| strips[k].may_touch(b, self.radius, depth)),
                );
                !into.is_empty()
            }
        }
    }

    /// [`Finger::flow`] over the drag segments listed in `segments` only (all of a push).
    #[inline]
    pub(crate) fn flow_over(&self, x: DVec3, segments: &[usize]) -> DVec3 {
        match &self.shape {
            Reach::Strips(strips) => self.strip_flow(x, strips, segments.iter().copied()),
            _ => self.flow(x),
        }
    }
}

/// How many pieces a segment whose end directions are `a` and `b` is split into so that no
/// piece turns by more than [`GROOVE_TURN_DEG`].
fn turn_pieces(a: DVec3, b: DVec3) -> usize {
    let angle = a.angle_between(b).to_degrees();
    if angle.is_finite() && angle > GROOVE_TURN_DEG {
        // At most 180° / 5° = 36 pieces.
        (angle / GROOVE_TURN_DEG).ceil().min(64.0) as usize
    } else {
        1
    }
}

/// The inward unit normal (`−unit(S_u × S_v)`) at the surface point nearest `x`.
fn inward_normal(grid: &crate::surface::Grid, x: DVec3) -> Result<DVec3, SurfaceError> {
    let near = crate::surface::nearest::nearest(grid, x)
        .ok_or_else(|| SurfaceError::BadOp("no surface point near the path".to_string()))?;
    let m = grid.patches_u();
    grid.normal(near.patch % m, near.patch / m, near.u, near.v)
        .map(|n| -n)
        .ok_or_else(|| {
            SurfaceError::BadOp(format!(
                "the surface has no normal at the point nearest {x} (patch {})",
                near.patch
            ))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn push(at: DVec3, depth: f64) -> Finger {
        Op::Push {
            at,
            dir: -DVec3::Z,
            depth,
            radius: 1.25,
        }
        .finger()
        .unwrap()
    }

    #[test]
    fn push_is_a_paraboloid_of_depth_m() {
        let f = push(DVec3::new(0.5, 0.5, 0.0), 0.4);
        assert_eq!(
            f.flow(DVec3::new(0.5, 0.5, 0.0)),
            DVec3::new(0.0, 0.0, -0.4)
        );
        let x = DVec3::new(0.5 + 0.6, 0.5 - 0.3, 0.0);
        let r2 = 0.36 + 0.09;
        assert!((f.flow(x).z + 0.4 * (1.0 - r2 / 1.5625)).abs() < 1e-15);
        assert_eq!(f.flow(DVec3::new(0.5 + 1.25, 0.5, 0.0)), DVec3::ZERO);
        // Below the tip the finger is further away than the tip.
        assert_eq!(f.flow(DVec3::new(0.5, 0.5, -1.7)), DVec3::ZERO);
    }

    #[test]
    fn pull_mirrors_push_bit_for_bit() {
        let p = push(DVec3::new(0.1, -0.2, 0.0), 0.7);
        let q = push(DVec3::new(0.1, -0.2, 0.0), -0.7);
        for k in 0..50 {
            let x = DVec3::new(
                (k as f64 * 0.37).sin(),
                (k as f64 * 0.91).cos(),
                0.05 * k as f64 - 1.0,
            );
            assert_eq!(p.flow(x), -q.flow(x));
        }
    }

    #[test]
    fn strip_distance_matches_brute_force() {
        let axis = DVec3::new(0.2, -0.3, -1.0).normalize();
        let s = Strip::new(
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.5, -0.4),
            axis,
            axis,
        );
        for k in 0..200 {
            let x = DVec3::new(
                (k as f64 * 0.71).sin() * 2.0,
                (k as f64 * 1.3).cos() * 2.0,
                (k as f64 * 0.3).sin(),
            );
            // Brute force over the strip t0 + s e − λ axis.
            let mut best = f64::INFINITY;
            for a in 0..=200 {
                let p = s.t0 + (s.t1 - s.t0) * (a as f64 / 200.0);
                best = best.min(half_line_distance_sq(x - p, axis));
            }
            let got = s.distance_sq(x);
            assert!(got <= best + 1e-12, "{k}: {got} vs {best}");
            assert!(
                (got.sqrt() - best.sqrt()).abs() < 1e-2,
                "{k}: {got} vs {best}"
            );
        }
    }

    #[test]
    fn bad_ops_are_rejected() {
        let ok = Op::Push {
            at: DVec3::ZERO,
            dir: DVec3::Z,
            depth: 0.1,
            radius: 1.0,
        };
        assert!(ok.finger().is_ok());
        for bad in [
            Op::Push {
                at: DVec3::ZERO,
                dir: DVec3::ZERO,
                depth: 0.1,
                radius: 1.0,
            },
            Op::Push {
                at: DVec3::ZERO,
                dir: DVec3::Z,
                depth: f64::NAN,
                radius: 1.0,
            },
            Op::Push {
                at: DVec3::ZERO,
                dir: DVec3::Z,
                depth: 0.1,
                radius: 0.0,
            },
            Op::Push {
                at: DVec3::new(f64::INFINITY, 0.0, 0.0),
                dir: DVec3::Z,
                depth: 0.1,
                radius: 1.0,
            },
            Op::Drag {
                path: vec![DVec3::ZERO],
                dir: DVec3::Z,
                depth: 0.1,
                radius: 1.0,
            },
        ] {
            assert!(
                matches!(bad.finger(), Err(SurfaceError::BadOp(_))),
                "{bad:?}"
            );
        }
    }
}
