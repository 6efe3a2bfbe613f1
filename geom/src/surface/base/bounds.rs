//! Bounding boxes of patches and a hierarchy over the patch grid, so that the patches a finger
//! can reach are found in time that follows the reach, not the patch count.
//!
//! The hierarchy is a pyramid over patch indices: level 0 holds one box per patch, and each box
//! of level `L + 1` holds the (up to) 2 × 2 boxes of level `L` below it, up to a single root.
//! A query descends from the root into the boxes a predicate accepts; a refit after a
//! deformation recomputes only the boxes above the patches that changed.

use glam::DVec3;

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: DVec3,
    /// Largest corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (the identity of [`Aabb::union`]).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The smallest box holding the points.
    #[must_use]
    pub fn of_points(points: &[DVec3]) -> Self {
        let mut b = Self::EMPTY;
        for &p in points {
            b.min = b.min.min(p);
            b.max = b.max.max(p);
        }
        b
    }

    /// The smallest box holding both.
    #[must_use]
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The box grown by `r` on every side.
    #[must_use]
    pub fn inflated(self, r: f64) -> Aabb {
        Aabb {
            min: self.min - DVec3::splat(r),
            max: self.max + DVec3::splat(r),
        }
    }

    /// Centre of the box.
    #[must_use]
    pub fn center(self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the extents.
    #[must_use]
    pub fn half_extents(self) -> DVec3 {
        0.5 * (self.max - self.min)
    }

    /// True when the box holds nothing.
    #[must_use]
    pub fn is_empty(self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    /// The parameter interval `[t0, t1]` (clipped to `[lo, hi]`) where the segment
    /// `origin + t·dir` lies inside the box (slab test); `None` when it misses.
    #[must_use]
    pub fn clip_line(self, origin: DVec3, dir: DVec3, lo: f64, hi: f64) -> Option<(f64, f64)> {
        let (mut t0, mut t1) = (lo, hi);
        for k in 0..3 {
            let (o, d) = (origin[k], dir[k]);
            if d.abs() < 1e-300 {
                if o < self.min[k] || o > self.max[k] {
                    return None;
                }
            } else {
                let inv = 1.0 / d;
                let (mut a, mut b) = ((self.min[k] - o) * inv, (self.max[k] - o) * inv);
                if a > b {
                    std::mem::swap(&mut a, &mut b);
                }
                if a > t0 {
                    t0 = a;
                }
                if b < t1 {
                    t1 = b;
                }
                if t0 > t1 {
                    return None;
                }
            }
        }
        Some((t0, t1))
    }
}

/// The pyramid of patch boxes over an `M × N` patch grid.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Hierarchy {
    /// `dims[L] = (width, height)` of level `L`.
    dims: Vec<(usize, usize)>,
    /// `levels[L][y * width + x]`.
    levels: Vec<Vec<Aabb>>,
}

impl Hierarchy {
    /// Builds the pyramid from one box per patch (`leaves[iv * m + iu]`).
    pub(crate) fn new(m: usize, n: usize, leaves: Vec<Aabb>) -> Self {
        debug_assert_eq!(leaves.len(), m * n);
        let mut dims = vec![(m, n)];
        let mut levels = vec![leaves];
        while dims.last().is_some_and(|&(w, h)| w > 1 || h > 1) {
            let (w, h) = dims[dims.len() - 1];
            let (pw, ph) = (w.div_ceil(2), h.div_ceil(2));
            let below = &levels[levels.len() - 1];
            let mut up = vec![Aabb::EMPTY; pw * ph];
            for y in 0..h {
                for x in 0..w {
                    let b = &mut up[(y / 2) * pw + x / 2];
                    *b = b.union(below[y * w + x]);
                }
            }
            dims.push((pw, ph));
            levels.push(up);
        }
        Self { dims, levels }
    }

    /// The box of everything.
    pub(crate) fn root(&self) -> Aabb {
        self.levels
            .last()
            .and_then(|l| l.first().copied())
            .unwrap_or(Aabb::EMPTY)
    }

    /// The box of one patch.
    pub(crate) fn leaf(&self, index: usize) -> Aabb {
        self.levels[0][index]
    }

    /// Replaces the boxes of the given patches and refits the boxes above them. `changed` is
    /// a list of `(patch index, new box)`.
    pub(crate) fn refit(&mut self, changed: &[(usize, Aabb)], scratch: &mut Vec<usize>) {
        scratch.clear();
        for &(i, b) in changed {
            self.levels[0][i] = b;
            scratch.push(i);
        }
        for l in 1..self.levels.len() {
            let (w, h) = self.dims[l - 1];
            let pw = self.dims[l].0;
            // Parents of the cells changed at level l − 1 (deduplicated).
            for c in scratch.iter_mut() {
                let (x, y) = (*c % w, *c / w);
                *c = (y / 2) * pw + x / 2;
            }
            scratch.sort_unstable();
            scratch.dedup();
            for &p in scratch.iter() {
                let (px, py) = (p % pw, p / pw);
                let mut b = Aabb::EMPTY;
                for y in 2 * py..(2 * py + 2).min(h) {
                    for x in 2 * px..(2 * px + 2).min(w) {
                        b = b.union(self.levels[l - 1][y * w + x]);
                    }
                }
                self.levels[l][p] = b;
            }
        }
    }

    /// Appends to `out` the index of every patch whose box the predicate accepts and whose
    /// ancestors' boxes it accepts too, in a fixed (deterministic) order.
    pub fn query(&self, accept: &impl Fn(&Aabb) -> bool, out: &mut Vec<usize>) {
        let top = self.levels.len() - 1;
        self.descend(top, 0, 0, accept, out);
    }

    fn descend(
        &self,
        l: usize,
        x: usize,
        y: usize,
        accept: &impl Fn(&Aabb) -> bool,
        out: &mut Vec<usize>,
    ) {
        let (w, _) = self.dims[l];
        let b = &self.levels[l][y * w + x];
        if b.is_empty() || !accept(b) {
            return;
        }
        if l == 0 {
            out.push(y * w + x);
            return;
        }
        let (cw, ch) = self.dims[l - 1];
        for cy in 2 * y..(2 * y + 2).min(ch) {
            for cx in 2 * x..(2 * x + 2).min(cw) {
                self.descend(l - 1, cx, cy, accept, out);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(x: f64, y: f64) -> Aabb {
        Aabb {
            min: DVec3::new(x, y, 0.0),
            max: DVec3::new(x + 1.0, y + 1.0, 0.0),
        }
    }

    #[test]
    fn query_finds_exactly_the_accepted_leaves() {
        let (m, n) = (7, 5);
        let leaves = (0..m * n)
            .map(|k| unit_box((k % m) as f64, (k / m) as f64))
            .collect();
        let h = Hierarchy::new(m, n, leaves);
        let probe = Aabb {
            min: DVec3::new(2.5, 1.5, -1.0),
            max: DVec3::new(4.2, 2.2, 1.0),
        };
        let overlaps = |b: &Aabb| {
            b.min.x <= probe.max.x
                && b.max.x >= probe.min.x
                && b.min.y <= probe.max.y
                && b.max.y >= probe.min.y
                && b.min.z <= probe.max.z
                && b.max.z >= probe.min.z
        };
        let mut got = Vec::new();
        h.query(&overlaps, &mut got);
        got.sort_unstable();
        let want: Vec<usize> = (0..m * n).filter(|&k| overlaps(&h.leaf(k))).collect();
        assert_eq!(got, want);
        assert_eq!(
            h.root(),
            Aabb {
                min: DVec3::ZERO,
                max: DVec3::new(7.0, 5.0, 0.0)
            }
        );
    }

    #[test]
    fn refit_updates_ancestors() {
        let (m, n) = (5, 3);
        let leaves = (0..m * n)
            .map(|k| unit_box((k % m) as f64, (k / m) as f64))
            .collect();
        let mut h = Hierarchy::new(m, n, leaves);
        let moved = Aabb {
            min: DVec3::new(4.0, 2.0, 0.0),
            max: DVec3::new(5.0, 3.0, 9.0),
        };
        let mut scratch = Vec::new();
        h.refit(&[(14, moved)], &mut scratch);
        assert_eq!(h.root().max.z, 9.0);
        let rebuilt = Hierarchy::new(m, n, (0..m * n).map(|k| h.leaf(k)).collect());
        assert_eq!(rebuilt, h);
    }

    #[test]
    fn slab_test_clips_segments() {
        let b = Aabb {
            min: DVec3::ZERO,
            max: DVec3::ONE,
        };
        let hit = b.clip_line(DVec3::new(-1.0, 0.5, 0.5), DVec3::X, 0.0, 10.0);
        assert_eq!(hit, Some((1.0, 2.0)));
        assert_eq!(
            b.clip_line(DVec3::new(-1.0, 2.0, 0.5), DVec3::X, 0.0, 10.0),
            None
        );
        assert_eq!(
            b.clip_line(DVec3::new(-1.0, 0.5, 0.5), DVec3::X, 0.0, 0.5),
            None
        );
    }
}
