//! One bicubic Bezier patch: `S(u,v) = Σ_i Σ_j B_i³(u) B_j³(v) P[4i + j]`, `i` along `u`, `j`
//! along `v`, `(u, v) ∈ [0,1]²`: the one evaluator of points, derivatives and normals that the
//! surface code and the mesher ([`crate::mesh`]) share.
//!
//! ## The normal, and where there is none
//! The normal is `unit(S_u × S_v)`. Where a boundary row is collapsed into one point (a pole)
//! `S_u` vanishes along it, and the normal there is the limit from inside the patch: near a
//! collapsed row `v = v₀`, `S_u(u,v) ≈ (v − v₀) S_uv(u,v₀)`, so the normal is
//! `± unit(S_uv × S_v)` with the sign of `v − v₀` (and likewise for a collapsed column).
//!
//! One degeneracy rule decides which case a point is ([`Patch::normal`]), with `size` the
//! diagonal of the control points' bounding box:
//!
//! 1. a derivative **vanishes** when its length is at most `1e-9 · size`;
//! 2. two vectors `a, b` **span a plane** when `|a × b| > 1e-10 |a| |b|` (they are more than
//!    10⁻¹⁰ rad from parallel);
//! 3. neither `S_u` nor `S_v` vanishes and they span a plane: the tangent plane is defined,
//!    the normal is `unit(S_u × S_v)`;
//! 4. exactly one of them vanishes (a collapsed row or column, a pole): the limit normal
//!    above, if `S_uv` and the other derivative span a plane;
//! 5. otherwise (both vanish, they are parallel, or no limit exists): the normal of the point
//!    moved `10⁻⁶` towards the patch centre in `u` and `v`, if its derivatives span a plane;
//! 6. otherwise there is no normal: `None`. A caller that needs a vector anyway (a mesh
//!    vertex) chooses its fallback itself, where it calls.

use glam::DVec3;

use crate::surface::bounds::Aabb;

/// The control points of a bicubic patch, `P[4*i + j]`, `i` along `u`, `j` along `v`.
pub type PatchPoints = [DVec3; 16];

/// A bicubic Bezier patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// The control points, `P[4*i + j]`, `i` along `u`, `j` along `v`.
    pub points: PatchPoints,
}

/// A point of a patch with its first derivatives and the mixed second derivative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchFrame {
    /// `S(u,v)`.
    pub point: DVec3,
    /// `∂S/∂u`.
    pub du: DVec3,
    /// `∂S/∂v`.
    pub dv: DVec3,
    /// `∂²S/∂u∂v`.
    pub duv: DVec3,
}

/// A patch restricted to one parameter line `v`: the control points
/// `R_i(v) = Σ_j B_j³(v) P[4i + j]` of the cubic `u ↦ S(u, v)` and those of `u ↦ S_v(u, v)`.
/// Points along the line share this half of the work ([`Patch::v_line`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct VLine {
    rows: [DVec3; 4],
    rows_dv: [DVec3; 4],
}

impl VLine {
    /// `(S, S_u, S_v)` at the `u` whose basis values are `bu` and `du`: [`VLine::frame`]
    /// without the mixed derivative, the same bits.
    #[must_use]
    pub(crate) fn tangents(&self, bu: &[f64; 4], du: &[f64; 4]) -> (DVec3, DVec3, DVec3) {
        (
            combine(self.rows, *bu, true),
            combine(self.rows, *du, false),
            combine(self.rows_dv, *bu, true),
        )
    }

    /// The frame at the `u` whose basis values are `bu = cubic_basis(u)` and
    /// `du = cubic_basis_derivative(u)`: `Σ_i B_i(u) R_i`, `Σ_i B_i'(u) R_i`, `Σ_i B_i(u) R_i'`,
    /// `Σ_i B_i'(u) R_i'`.
    #[must_use]
    pub(crate) fn frame(&self, bu: &[f64; 4], du: &[f64; 4]) -> PatchFrame {
        PatchFrame {
            point: combine(self.rows, *bu, true),
            du: combine(self.rows, *du, false),
            dv: combine(self.rows_dv, *bu, true),
            duv: combine(self.rows_dv, *du, false),
        }
    }
}

/// Cubic Bernstein values `B_0..B_3` at `t`.
#[inline]
#[must_use]
pub fn cubic_basis(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

/// Derivatives of the cubic Bernstein basis at `t`.
#[inline]
#[must_use]
pub fn cubic_basis_derivative(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * t * s,
        6.0 * t * s - 3.0 * t * t,
        3.0 * t * t,
    ]
}

/// `Σ_k w_k x_k` for weights that sum to one (`partition`) or to zero, exact when the four
/// points are equal (a collapsed row at a pole evaluates to the pole itself, and its
/// derivative along the row to zero).
#[inline]
fn combine(x: [DVec3; 4], w: [f64; 4], partition: bool) -> DVec3 {
    if x[0] == x[1] && x[1] == x[2] && x[2] == x[3] {
        return if partition { x[0] } else { DVec3::ZERO };
    }
    x[0] * w[0] + x[1] * w[1] + x[2] * w[2] + x[3] * w[3]
}

/// `a × b` when `a` and `b` (of lengths `la`, `lb`) span a plane, `|a × b| > 1e-10 |a| |b|`
/// (rule 2 of the module docs).
#[inline]
fn spanned(a: DVec3, b: DVec3, la: f64, lb: f64) -> Option<DVec3> {
    let n = a.cross(b);
    (n.length() > 1e-10 * la * lb).then_some(n)
}

/// Rule 3 of the module docs alone, for a caller that evaluates many points of one patch (the
/// mesher): from the derivatives `S_u`, `S_v` at a point and the patch's [`Patch::size`],
/// `unit(S_u × S_v)` where the tangent plane is defined — the bits [`Patch::normal`] returns
/// there — and `None` where the rest of the rule must decide: ask [`Patch::normal`].
#[inline]
#[must_use]
pub(crate) fn regular_normal(du: DVec3, dv: DVec3, size: f64) -> Option<DVec3> {
    let tiny = 1e-9 * size;
    let (lu, lv) = (du.length(), dv.length());
    if lu > tiny && lv > tiny {
        spanned(du, dv, lu, lv)?.try_normalize()
    } else {
        None
    }
}

impl Patch {
    /// A patch from its 16 control points.
    #[must_use]
    pub fn new(points: PatchPoints) -> Self {
        Self { points }
    }

    /// Control point `P[4*i + j]`.
    ///
    /// # Panics
    /// If `i > 3` or `j > 3`.
    #[inline]
    #[must_use]
    pub fn point(&self, i: usize, j: usize) -> DVec3 {
        assert!(i < 4 && j < 4, "control point ({i}, {j}) out of range");
        self.points[4 * i + j]
    }

    /// `S(u, v)`.
    #[must_use]
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        let bu = cubic_basis(u);
        let bv = cubic_basis(v);
        let mut rows = [DVec3::ZERO; 4];
        for (i, r) in rows.iter_mut().enumerate() {
            *r = combine(self.row(i), bv, true);
        }
        combine(rows, bu, true)
    }

    /// The point, `S_u`, `S_v` and `S_uv` at `(u, v)`.
    #[must_use]
    pub fn frame(&self, u: f64, v: f64) -> PatchFrame {
        self.v_line(v)
            .frame(&cubic_basis(u), &cubic_basis_derivative(u))
    }

    /// The patch restricted to the parameter line `v`, for evaluating many points on it
    /// ([`VLine::frame`] gives the same bits as [`Patch::frame`]).
    #[must_use]
    pub(crate) fn v_line(&self, v: f64) -> VLine {
        let bv = cubic_basis(v);
        let dv = cubic_basis_derivative(v);
        let mut rows = [DVec3::ZERO; 4];
        let mut rows_dv = [DVec3::ZERO; 4];
        for i in 0..4 {
            rows[i] = combine(self.row(i), bv, true);
            rows_dv[i] = combine(self.row(i), dv, false);
        }
        VLine { rows, rows_dv }
    }

    #[inline]
    fn row(&self, i: usize) -> [DVec3; 4] {
        [
            self.points[4 * i],
            self.points[4 * i + 1],
            self.points[4 * i + 2],
            self.points[4 * i + 3],
        ]
    }

    /// The unit normal `unit(S_u × S_v)` at `(u, v)`, with the limit taken along collapsed
    /// rows and columns; `None` where the surface has no tangent plane. The module docs state
    /// the rule.
    #[must_use]
    pub fn normal(&self, u: f64, v: f64) -> Option<DVec3> {
        let f = self.frame(u, v);
        let size = self.size();
        if size.is_nan() || size <= 0.0 {
            return None;
        }
        let tiny = 1e-9 * size;
        let lu = f.du.length();
        let lv = f.dv.length();
        if lu > tiny && lv > tiny {
            if let Some(n) = spanned(f.du, f.dv, lu, lv) {
                return n.try_normalize();
            }
        } else if lu <= tiny && lv > tiny {
            // Collapsed row: S_u ≈ (v − v₀) S_uv.
            let sign = if v < 0.5 { 1.0 } else { -1.0 };
            if let Some(n) = spanned(f.duv, f.dv, f.duv.length(), lv) {
                return (n * sign).try_normalize();
            }
        } else if lv <= tiny && lu > tiny {
            // Collapsed column: S_v ≈ (u − u₀) S_uv.
            let sign = if u < 0.5 { 1.0 } else { -1.0 };
            if let Some(n) = spanned(f.du, f.duv, lu, f.duv.length()) {
                return (n * sign).try_normalize();
            }
        }
        // A singular point that is not a collapsed boundary: step a little towards the centre.
        let step = 1e-6;
        let (u2, v2) = (u + step * (0.5 - u).signum(), v + step * (0.5 - v).signum());
        let g = self.frame(u2, v2);
        spanned(g.du, g.dv, g.du.length(), g.dv.length()).and_then(DVec3::try_normalize)
    }

    /// Diagonal of the control points' bounding box: the scale of the patch.
    #[must_use]
    pub fn size(&self) -> f64 {
        let b = self.bounds();
        (b.max - b.min).length()
    }

    /// Bounding box of the control points, which holds the patch (convex hull property).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        Aabb::of_points(&self.points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy() -> Patch {
        let mut p = [DVec3::ZERO; 16];
        for i in 0..4 {
            for j in 0..4 {
                let (x, y) = (i as f64 / 3.0, j as f64 / 3.0);
                p[4 * i + j] = DVec3::new(x + 0.1 * y * y, y, 0.3 * (x * 3.0).sin() * y);
            }
        }
        Patch::new(p)
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let p = wavy();
        let h = 1e-6;
        for &(u, v) in &[(0.2, 0.7), (0.5, 0.5), (0.9, 0.1)] {
            let f = p.frame(u, v);
            assert!((f.point - p.eval(u, v)).length() < 1e-15);
            let du = (p.eval(u + h, v) - p.eval(u - h, v)) / (2.0 * h);
            let dv = (p.eval(u, v + h) - p.eval(u, v - h)) / (2.0 * h);
            let duv = (p.frame(u, v + h).du - p.frame(u, v - h).du) / (2.0 * h);
            assert!((f.du - du).length() < 1e-8);
            assert!((f.dv - dv).length() < 1e-8);
            assert!((f.duv - duv).length() < 1e-8);
        }
    }

    #[test]
    fn normal_at_a_collapsed_row_is_the_limit() {
        // A cone-like patch: row v = 0 collapsed to the apex.
        let mut pts = [DVec3::ZERO; 16];
        for i in 0..4 {
            let a = i as f64 / 3.0;
            for j in 0..4 {
                let r = j as f64 / 3.0;
                pts[4 * i + j] = DVec3::new(r * (1.0 - a * 0.5), r * a, -0.2 * r * r);
            }
        }
        let p = Patch::new(pts);
        let at = p.normal(0.4, 0.0).expect("limit normal");
        let near = p.normal(0.4, 1e-7).expect("normal");
        assert!(at.angle_between(near) < 1e-5);
    }
}
