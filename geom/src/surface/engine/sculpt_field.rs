//! The displacement field of a surface brush (inflate, flatten, pinch, crease:
//! [`crate::surface::sculpt_brush`]) on the grid as it was, with its images under a symmetry,
//! run by the [`Sculptor`] through the same steps as a finger (reach, envelope, inverse, then
//! the commit).
//!
//! A sample `x = S(a/3, b/3)` of patch `p` moves by the brush's flow at `x` with the patch's
//! own unit normal there, `n = unit(S_u × S_v)(a/3, b/3)`. The image of the field under an
//! isometry `g` of the symmetry is `g F(g⁻¹ x, g⁻¹ n)` (the isometries are linear: turns about
//! z and mirrors through the origin), the brush pressed at the image of its stroke on a surface
//! that has the symmetry; the flows of the brush and its images meet in the engine's envelope.

use glam::DVec3;

use super::Sculptor;
use super::field::{DisplacementField, Envelope};
use super::sculptor::Touched;
use crate::surface::Isometry;
use crate::surface::bounds::Aabb;
use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::mirror::Symmetry;
use crate::surface::patch::Patch;
use crate::surface::regulate::Regulation;
use crate::surface::sculpt_brush::{SculptBrush, SculptKind};

/// A surface brush on the unchanged grid `base`.
struct SculptField<'a> {
    brush: &'a SculptBrush,
    base: &'a Grid,
    /// The flatten plane `(q, m)` (flatten only).
    plane: Option<(DVec3, DVec3)>,
    /// `(g, g⁻¹)` for every image of the symmetry (empty: none).
    images: Vec<(Isometry, Isometry)>,
}

impl DisplacementField for SculptField<'_> {
    fn may_touch(&self, b: &Aabb) -> bool {
        self.brush.may_touch(b)
            || self
                .images
                .iter()
                .any(|(_, inv)| self.brush.may_touch(&inv.apply_box(b)))
    }

    fn touches(&mut self, _patch: usize, bounds: &Aabb) -> bool {
        self.may_touch(bounds)
    }

    fn flows(&mut self, patch: usize, _bounds: &Aabb, r: &[DVec3; 16]) -> [DVec3; 16] {
        let m = self.base.patches_u();
        let surface = Patch::new(self.base.patch(patch % m, patch / m));
        std::array::from_fn(|k| {
            let (a, b) = (k / 4, k % 4);
            let n = surface.normal(a as f64 / 3.0, b as f64 / 3.0);
            let mut e = Envelope::default();
            e.add(self.brush.flow(r[k], n, self.plane));
            for (g, inv) in &self.images {
                let f = self
                    .brush
                    .flow(inv.apply(r[k]), n.map(|n| inv.apply(n)), self.plane);
                e.add(g.apply(f));
            }
            e.flow()
        })
    }
}

impl Sculptor {
    /// Applies a validated surface brush (with its images under `symmetry`).
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for a flatten with no surface under it; as
    /// [`Sculptor::apply`] for a refused result (the grid is then exactly as it was).
    pub(super) fn apply_sculpt(
        &mut self,
        grid: &mut Grid,
        brush: &SculptBrush,
        regulation: Regulation,
        symmetry: Option<&Symmetry>,
    ) -> Result<Touched, SurfaceError> {
        let plane = match brush.kind {
            SculptKind::Flatten => Some(brush.average_plane(grid)?),
            _ => None,
        };
        let examined = {
            let base: &Grid = grid;
            let mut field = SculptField {
                brush,
                base,
                plane,
                images: symmetry
                    .map_or(&[][..], Symmetry::field_images)
                    .iter()
                    .map(|g| (*g, g.inverse()))
                    .collect(),
            };
            self.gather(base, &mut field, symmetry, None)
        };
        self.commit_updates(grid, regulation, symmetry, None, examined)
    }
}
