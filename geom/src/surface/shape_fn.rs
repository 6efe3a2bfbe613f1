//! Shape functions: the ideal shape a finger asks for (seed 002 §5; SPEC §7).
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

use super::bounds::Aabb;
use super::error::SurfaceError;

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
}

impl Op {
    /// The finger the operation describes, after validation.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] when a number is not finite, `dir` is zero, the radius is not
    /// positive, or a drag path has fewer than two points.
    pub fn finger(&self) -> Result<Finger, SurfaceError> {
        let bad = |s: &str| Err(SurfaceError::BadOp(s.to_string()));
        let (dir, depth, radius) = match self {
            Op::Push {
                dir, depth, radius, ..
            }
            | Op::Drag {
                dir, depth, radius, ..
            } => (*dir, *depth, *radius),
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
                    .map(|w| Strip::new(w[0] + press, w[1] + press, axis))
                    .collect();
                Reach::Strips(strips)
            }
        };
        Ok(Finger {
            axis,
            movement: axis * depth,
            radius,
            radius_sq: radius * radius,
            shape,
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
}

#[derive(Debug, Clone, PartialEq)]
enum Reach {
    HalfLine { tip: DVec3 },
    Strips(Vec<Strip>),
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
}

impl Strip {
    fn new(t0: DVec3, t1: DVec3, axis: DVec3) -> Self {
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
    /// The unit finger direction `d̂`.
    #[must_use]
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// The movement vector `M = depth · d̂` (`L_f` for a drag).
    #[must_use]
    pub fn movement(&self) -> DVec3 {
        self.movement
    }

    /// The finger radius `r_f`.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Squared distance `r²` from `x` to the finger (the half-line, or the swept half-strips).
    #[must_use]
    pub fn distance_sq(&self, x: DVec3) -> f64 {
        match &self.shape {
            Reach::HalfLine { tip } => half_line_distance_sq(x - *tip, self.axis),
            Reach::Strips(strips) => strips
                .iter()
                .map(|s| s.distance_sq(x))
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// The flow vector `F = (1 − r²/r_f²)·M` for `r < r_f`, zero beyond (see the module docs).
    #[inline]
    #[must_use]
    pub fn flow(&self, x: DVec3) -> DVec3 {
        let r2 = self.distance_sq(x);
        if r2 < self.radius_sq {
            self.movement * (1.0 - r2 / self.radius_sq)
        } else {
            DVec3::ZERO
        }
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
        }
    }

    /// A copy of this finger keeping only the drag segments that may touch `b` (the same
    /// finger for a push). Used to cut the work per patch.
    pub(crate) fn restricted_to(&self, b: &Aabb, depth: f64, into: &mut Vec<usize>) -> bool {
        into.clear();
        match &self.shape {
            Reach::HalfLine { .. } => true,
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
        let r2 = match &self.shape {
            Reach::HalfLine { tip } => half_line_distance_sq(x - *tip, self.axis),
            Reach::Strips(strips) => segments
                .iter()
                .map(|&k| strips[k].distance_sq(x))
                .fold(f64::INFINITY, f64::min),
        };
        if r2 < self.radius_sq {
            self.movement * (1.0 - r2 / self.radius_sq)
        } else {
            DVec3::ZERO
        }
    }
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
        let s = Strip::new(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 0.5, -0.4), axis);
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
