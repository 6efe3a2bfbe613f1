//! The iso-surface `F = T` of a metaball shape as a closed triangle mesh, by marching
//! tetrahedra.
//!
//! * The density is sampled on a cubic lattice of side `h` covering the supports of the
//!   positive balls and one cell more on every side (so the lattice's boundary is outside:
//!   `F = 0 < T` there and the surface is closed). Each ball adds `q f(|X − C|² / R²)` to the
//!   lattice points within its radius only.
//! * Every cube is cut into six tetrahedra around its main diagonal (Kuhn's, or Freudenthal's,
//!   triangulation: tetrahedron `π` runs `0 → e_{π0} → e_{π0} + e_{π1} → (1,1,1)` for each
//!   permutation `π` of the axes). Neighbouring cubes cut their shared faces along the same
//!   diagonal, so the tetrahedra fill space face to face and no case is ambiguous — unlike
//!   marching cubes' saddles, which need extra rules to stay crack-free.
//! * A lattice point is inside when `F ≥ T`. A tetrahedron with one corner on the other side
//!   gives one triangle, with two on each side a quadrilateral (two triangles), cut on its
//!   edges that cross. The vertex on an edge from inside corner `a` to outside corner `b` is
//!   the root of `g(t) = F(a + t (b − a)) − T` on `[0, 1]`, found on the exact density (not the
//!   lattice's linear interpolation) by the Illinois variant of regula falsi, bracketed by the
//!   lattice values, so it stays on its edge and the mesh's topology is the lattice's. Each
//!   crossing edge makes exactly one vertex, shared by every tetrahedron around it: the mesh is
//!   closed and every edge has two triangles.
//! * Triangles are oriented counter-clockwise seen from outside: for a tetrahedron of positive
//!   volume `(v_i, v_j, v_k, v_l)` with `i` alone on its side, the triangle `(e_ij, e_ik, e_il)`
//!   faces away from `v_i` (reversed when `v_i` is the lone outside corner); with `i, j` inside
//!   and `k, l` outside, the quadrilateral `(e_ik, e_il, e_jl, e_jk)` faces outward.
//! * Normals are the density's gradient, `n = −∇F / |∇F|` (outward, since `F` falls across the
//!   boundary), exact at every vertex.
//!
//! [`TriMesh::error_bound`] receives the largest first-order distance `|F − T| / |∇F|` at the
//! triangles' centroids: an estimate of how far the flat triangles sag from the surface, not a
//! bound.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use super::error::FigureError;
use super::metaball::Shape;
use crate::mesh::TriMesh;

/// How finely the iso-surface is meshed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshOptions {
    /// Lattice cells along the longest side of the shape's bounds (2..=256).
    pub resolution: usize,
    /// Root-finding steps per vertex along its edge (0: linear interpolation of the lattice
    /// values).
    pub refine: usize,
}

impl Default for MeshOptions {
    fn default() -> Self {
        Self {
            resolution: 64,
            refine: 8,
        }
    }
}

/// The corners of the six tetrahedra of a unit cube (offsets), each of positive volume.
fn tetrahedra() -> [[[usize; 3]; 4]; 6] {
    const PERMUTATIONS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    PERMUTATIONS.map(|p| {
        let mut c = [[0usize; 3]; 4];
        let mut at = [0usize; 3];
        for (step, &axis) in p.iter().enumerate() {
            at[axis] = 1;
            c[step + 1] = at;
        }
        // Odd permutations give negative volume: swap the middle corners.
        let inversions =
            usize::from(p[0] > p[1]) + usize::from(p[0] > p[2]) + usize::from(p[1] > p[2]);
        if inversions % 2 == 1 {
            c.swap(1, 2);
        }
        c
    })
}

/// `first` followed by the other corners of `0..4`, as an even permutation.
fn even_completion(first: &[usize]) -> [usize; 4] {
    let mut order = [0usize; 4];
    let mut n = 0;
    for &f in first {
        order[n] = f;
        n += 1;
    }
    for c in 0..4 {
        if !first.contains(&c) {
            order[n] = c;
            n += 1;
        }
    }
    let mut inversions = 0;
    for a in 0..4 {
        for b in a + 1..4 {
            if order[a] > order[b] {
                inversions += 1;
            }
        }
    }
    if inversions % 2 == 1 {
        order.swap(2, 3);
    }
    order
}

/// The lattice: origin, step, points per axis, and the density at every point.
struct Lattice {
    origin: DVec3,
    step: f64,
    dims: [usize; 3],
    values: Vec<f64>,
}

impl Lattice {
    fn index(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.dims[1] + j) * self.dims[0] + i
    }

    fn point(&self, index: usize) -> DVec3 {
        let i = index % self.dims[0];
        let j = (index / self.dims[0]) % self.dims[1];
        let k = index / (self.dims[0] * self.dims[1]);
        self.origin + DVec3::new(i as f64, j as f64, k as f64) * self.step
    }

    fn sample(shape: &Shape, options: &MeshOptions) -> Result<Self, FigureError> {
        let (lo, hi) = shape.bounds().ok_or_else(|| {
            FigureError::Empty("the shape has no metaball of positive density and radius".into())
        })?;
        let step = (hi - lo).max_element() / options.resolution as f64;
        if !(step.is_finite() && step > 0.0) {
            return Err(FigureError::Option(format!(
                "cannot mesh a shape of extent {}",
                hi - lo
            )));
        }
        let origin = lo - DVec3::splat(step);
        let span = hi + DVec3::splat(step) - origin;
        let dims = [span.x, span.y, span.z].map(|s| (s / step).ceil() as usize + 1);
        let mut lattice = Self {
            origin,
            step,
            dims,
            values: vec![0.0; dims[0] * dims[1] * dims[2]],
        };
        for b in shape.balls.iter().filter(|b| b.radius > 0.0) {
            let r2 = b.radius * b.radius;
            let range = |axis: usize| {
                let c = b.centre[axis] - origin[axis];
                let a = ((c - b.radius) / step).ceil().max(0.0) as usize;
                let z = (((c + b.radius) / step).floor().max(-1.0) + 1.0) as usize;
                a..z.min(dims[axis])
            };
            for k in range(2) {
                for j in range(1) {
                    for i in range(0) {
                        let x = origin + DVec3::new(i as f64, j as f64, k as f64) * step;
                        let s = (x - b.centre).length_squared() / r2;
                        let at = lattice.index(i, j, k);
                        lattice.values[at] += b.density * super::falloff::density(s);
                    }
                }
            }
        }
        Ok(lattice)
    }
}

/// Builds the mesh vertex by vertex.
struct Builder<'a> {
    shape: &'a Shape,
    lattice: &'a Lattice,
    refine: usize,
    vertices: HashMap<(usize, usize), u32>,
    positions: Vec<DVec3>,
    indices: Vec<u32>,
}

impl Builder<'_> {
    /// The vertex on the edge from inside lattice point `a` to outside point `b`.
    fn vertex(&mut self, a: usize, b: usize) -> u32 {
        let key = (a.min(b), a.max(b));
        if let Some(&v) = self.vertices.get(&key) {
            return v;
        }
        let t = self.shape.threshold;
        let (pa, pb) = (self.lattice.point(a), self.lattice.point(b));
        let (mut t0, mut g0) = (0.0, self.lattice.values[a] - t);
        let (mut t1, mut g1) = (1.0, self.lattice.values[b] - t);
        // Illinois regula falsi on g(t) = F(a + t (b − a)) − T, g0 ≥ 0 > g1.
        let mut x = g0 / (g0 - g1);
        let mut side = 0i8;
        for _ in 0..self.refine {
            let g = self.shape.field(pa.lerp(pb, x)) - t;
            if g >= 0.0 {
                t0 = x;
                g0 = g;
                if side == 1 {
                    g1 *= 0.5;
                }
                side = 1;
            } else {
                t1 = x;
                g1 = g;
                if side == -1 {
                    g0 *= 0.5;
                }
                side = -1;
            }
            let denom = g0 - g1;
            if denom.is_nan() || denom <= 0.0 || t1 - t0 <= 1e-12 {
                break;
            }
            x = t0 + (t1 - t0) * g0 / denom;
        }
        let id = self.positions.len() as u32;
        self.positions.push(pa.lerp(pb, x.clamp(0.0, 1.0)));
        self.vertices.insert(key, id);
        id
    }

    /// Triangles of one tetrahedron of positive volume with lattice corners `v`.
    fn tetrahedron(&mut self, v: [usize; 4]) {
        let t = self.shape.threshold;
        let inside: [bool; 4] = v.map(|c| self.lattice.values[c] >= t);
        let ins: Vec<usize> = (0..4).filter(|&c| inside[c]).collect();
        match ins.len() {
            1 => {
                let [i, j, k, l] = even_completion(&ins);
                let a = self.vertex(v[i], v[j]);
                let b = self.vertex(v[i], v[k]);
                let c = self.vertex(v[i], v[l]);
                self.indices.extend([a, b, c]);
            }
            3 => {
                let out: Vec<usize> = (0..4).filter(|&c| !inside[c]).collect();
                let [o, j, k, l] = even_completion(&out);
                let a = self.vertex(v[j], v[o]);
                let b = self.vertex(v[k], v[o]);
                let c = self.vertex(v[l], v[o]);
                self.indices.extend([a, c, b]);
            }
            2 => {
                let [i, j, k, l] = even_completion(&ins);
                let ik = self.vertex(v[i], v[k]);
                let il = self.vertex(v[i], v[l]);
                let jl = self.vertex(v[j], v[l]);
                let jk = self.vertex(v[j], v[k]);
                self.indices.extend([ik, il, jl, ik, jl, jk]);
            }
            _ => {}
        }
    }
}

/// The closed, outward-oriented triangle mesh of the shape's iso-surface (see the module docs).
///
/// ```
/// use glam::DVec3;
/// use nendo::figure::marching::{MeshOptions, iso_surface};
/// use nendo::figure::{Metaball, Shape};
/// // A lone ball: the sphere of radius R/2 = 1.
/// let shape = Shape::new(vec![Metaball::new(DVec3::ZERO, 2.0, 1.0)]);
/// let mesh = iso_surface(&shape, &MeshOptions::default())?;
/// assert!(mesh.positions.iter().all(|p| (p.length() - 1.0).abs() < 1e-4));
/// # Ok::<(), nendo::figure::FigureError>(())
/// ```
///
/// # Errors
/// [`FigureError::Option`] for a resolution outside 2..=256, [`FigureError::Empty`] for a shape
/// without a ball of positive density and radius, and the validation errors of the shape.
pub fn iso_surface(shape: &Shape, options: &MeshOptions) -> Result<TriMesh, FigureError> {
    shape.validate()?;
    if !(2..=256).contains(&options.resolution) {
        return Err(FigureError::Option(format!(
            "mesh resolution must be 2 to 256 cells, got {}",
            options.resolution
        )));
    }
    let lattice = Lattice::sample(shape, options)?;
    let mut builder = Builder {
        shape,
        lattice: &lattice,
        refine: options.refine,
        vertices: HashMap::new(),
        positions: Vec::new(),
        indices: Vec::new(),
    };
    let tets = tetrahedra();
    let t = shape.threshold;
    let [nx, ny, nz] = lattice.dims;
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let corner = |o: [usize; 3]| lattice.index(i + o[0], j + o[1], k + o[2]);
                let mut any_in = false;
                let mut any_out = false;
                for o in 0..8 {
                    let c = corner([o & 1, (o >> 1) & 1, o >> 2]);
                    if lattice.values[c] >= t {
                        any_in = true;
                    } else {
                        any_out = true;
                    }
                }
                if !(any_in && any_out) {
                    continue;
                }
                for tet in &tets {
                    builder.tetrahedron(tet.map(corner));
                }
            }
        }
    }
    let Builder {
        positions, indices, ..
    } = builder;
    // Normals from the gradient; where it vanishes, the sum of the faces' normals.
    let mut face_sum = vec![DVec3::ZERO; positions.len()];
    let mut sag = 0.0f64;
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|v| positions[v as usize]);
        let n = (b - a).cross(c - a);
        for &v in tri {
            face_sum[v as usize] += n;
        }
        let (f, g) = shape.field_and_gradient((a + b + c) / 3.0);
        let gl = g.length();
        if gl > 0.0 {
            sag = sag.max((f - t).abs() / gl);
        }
    }
    let normals = positions
        .iter()
        .zip(&face_sum)
        .map(|(&p, &fs)| {
            let (_, g) = shape.field_and_gradient(p);
            let n = (-g).try_normalize().or_else(|| fs.try_normalize());
            n.unwrap_or(DVec3::Z).as_vec3()
        })
        .collect();
    Ok(TriMesh {
        positions: positions.iter().map(|p| p.as_vec3()).collect::<Vec<Vec3>>(),
        normals,
        indices,
        blocks: Vec::new(),
        error_bound: sag,
    })
}

/// Whether every edge of the mesh is shared by exactly two triangles that run along it in
/// opposite directions (a closed, consistently oriented surface).
#[must_use]
pub fn is_closed(mesh: &TriMesh) -> bool {
    let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::with_capacity(mesh.indices.len());
    for t in mesh.triangles() {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
    }
    !edges.is_empty() && edges.values().all(|&(n, balance)| n == 2 && balance == 0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::Metaball;

    #[test]
    fn the_tetrahedra_fill_the_cube_with_positive_volumes() {
        let mut total = 0.0;
        for t in tetrahedra() {
            let p = t.map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64));
            let v = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) / 6.0;
            assert!(v > 0.0);
            total += v;
        }
        assert!((total - 1.0).abs() < 1e-15);
    }

    #[test]
    fn completions_are_even() {
        for first in [
            vec![0],
            vec![1],
            vec![2],
            vec![3],
            vec![0, 1],
            vec![1, 3],
            vec![3, 2],
        ] {
            let o = even_completion(&first);
            assert_eq!(&o[..first.len()], &first[..]);
            let mut sorted = o;
            sorted.sort_unstable();
            assert_eq!(sorted, [0, 1, 2, 3]);
            let inv: usize = (0..4)
                .flat_map(|a| (a + 1..4).map(move |b| (a, b)))
                .filter(|&(a, b)| o[a] > o[b])
                .count();
            assert_eq!(inv % 2, 0, "{o:?}");
        }
    }

    #[test]
    fn two_balls_make_one_closed_outward_surface() {
        let shape = Shape::new(vec![
            Metaball::new(DVec3::new(-0.7, 0.0, 0.0), 2.0, 1.0),
            Metaball::new(DVec3::new(0.7, 0.1, 0.2), 1.6, 1.0),
        ]);
        let mesh = iso_surface(
            &shape,
            &MeshOptions {
                resolution: 24,
                refine: 8,
            },
        )
        .unwrap();
        let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::new();
        let mut volume = 0.0;
        for t in mesh.triangles() {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let e = edges.entry((a.min(b), a.max(b))).or_default();
                e.0 += 1;
                e.1 += if a < b { 1 } else { -1 };
            }
            let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
            volume += a.dot(b.cross(c)) / 6.0;
        }
        // Every edge is used by two triangles, once in each direction.
        assert!(edges.values().all(|&(n, balance)| n == 2 && balance == 0));
        assert!(is_closed(&mesh));
        // Outward: positive enclosed volume, normals along the faces.
        assert!(volume > 0.0);
        for p in &mesh.positions {
            assert!((shape.field(p.as_dvec3()) - 0.5).abs() < 1e-5);
        }
        assert!(iso_surface(&Shape::default(), &MeshOptions::default()).is_err());
        let bad = MeshOptions {
            resolution: 1,
            refine: 0,
        };
        assert!(iso_surface(&shape, &bad).is_err());
    }
}
