//! What a contact wants of the clay: a displacement field over the surface, and the one rule
//! that turns it into control-point updates (P2 §2.1; docs/design.md §11, steps 2–3; the design
//! notes in `docs/design.md`, "The deformation engine").
//!
//! A [`DisplacementField`] says which patches it may move (a box test for the bounding-box
//! pyramid) and, for a patch, the flow `F(r_k)` at its 16 samples `r_k` (`{0, 1/3, 2/3, 1}²`
//! of the surface as it was: the grid being deformed for an operation, the contact's
//! reference for the hand). [`displace`] runs the patches through it:
//!
//! - **Envelope.** Where several fingers (a hand's parts, an operation and its mirror image)
//!   reach one sample, it moves by the strongest flow, `F = argmax_j |F_j|`; where several are
//!   equally strong, by their mean ([`Envelope`]). The rule is symmetric in its arguments, so a
//!   sample on a mirror plane, where a flow and its mirror image are equally strong, moves
//!   within the plane, and the result does not depend on the order the fingers are listed in
//!   (up to the rounding of a sum of three or more equal flows).
//! - **Bernstein inverse.** `ΔP = B₄⁻¹ F B₄⁻ᵀ` per patch ([`control_update`]). Shared control
//!   points get bit-identical updates from every patch holding them: shared samples are
//!   computed from the same nodes the same way and rows 0 and 3 of `B₄⁻¹` are unit rows.
//! - **Poles.** At a pole every patch moves the pole by the flow of the pole sample itself
//!   (the unit row gives it at `i = 0`; the other copies of the collapsed row are made to
//!   agree), so the pole stays one point.
//!
//! A patch whose 16 flows are all zero is left alone, bit for bit.

use glam::DVec3;

use crate::surface::bounds::Aabb;
use crate::surface::grid::Grid;
use crate::surface::inverse::{control_update, samples};
use crate::surface::topology::Topology;

/// The envelope of several flows at one sample: the strongest; the mean of the equally
/// strongest.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Envelope {
    sum: DVec3,
    best_sq: f64,
    count: u32,
}

impl Envelope {
    /// Takes one more flow into the envelope.
    #[inline]
    pub(crate) fn add(&mut self, flow: DVec3) {
        let sq = flow.length_squared();
        if self.count == 0 || sq > self.best_sq {
            self.sum = flow;
            self.best_sq = sq;
            self.count = 1;
        } else if sq == self.best_sq {
            self.sum += flow;
            self.count += 1;
        }
    }

    /// The envelope's flow (zero for no flows).
    #[inline]
    #[must_use]
    pub(crate) fn flow(&self) -> DVec3 {
        match self.count {
            0 => DVec3::ZERO,
            1 => self.sum,
            k => self.sum / f64::from(k),
        }
    }
}

/// What one contact wants of the surface: see the module docs.
pub(crate) trait DisplacementField {
    /// Whether the field may move anything inside the box (a node of the bounding-box
    /// pyramid, or a patch's control-point box). May say `true` too often, never too rarely.
    fn may_touch(&self, bounds: &Aabb) -> bool;

    /// A finer test for one patch whose box passed [`DisplacementField::may_touch`]: `false`
    /// when none of its samples can move (its flows are then not asked for).
    fn touches(&mut self, patch: usize, bounds: &Aabb) -> bool;

    /// The flows at patch `patch`'s 16 samples `r` (row-major, `k = 4 i + j`).
    fn flows(&mut self, patch: usize, bounds: &Aabb, r: &[DVec3; 16]) -> [DVec3; 16];
}

/// Runs the patches `area` of `base` through `field`: for each, `moved(p, Some(ΔP))` with the
/// control-point update of a patch the field moves (poles fixed up), `moved(p, None)` for one
/// it leaves alone.
pub(crate) fn displace(
    base: &Grid,
    area: &[usize],
    field: &mut impl DisplacementField,
    mut moved: impl FnMut(usize, Option<[DVec3; 16]>),
) {
    let (m, n) = (base.patches_u(), base.patches_v());
    let topology = base.topology();
    for &p in area {
        let bounds = base.patch_bounds(p);
        if !field.touches(p, &bounds) {
            moved(p, None);
            continue;
        }
        let r = samples(&base.patch_at(p));
        let flows = field.flows(p, &bounds, &r);
        if flows.iter().all(|f| *f == DVec3::ZERO) {
            moved(p, None);
            continue;
        }
        moved(p, Some(patch_update(&flows, p / m, n, topology)));
    }
}

/// `ΔP = B₄⁻¹ F B₄⁻ᵀ` for the flows `F` at a patch's 16 samples, the patch in row `iv` of `n`:
/// at a pole every copy of the collapsed row moves by the pole sample's own flow.
#[must_use]
pub(crate) fn patch_update(
    flows: &[DVec3; 16],
    iv: usize,
    n: usize,
    topology: Topology,
) -> [DVec3; 16] {
    let mut delta = control_update(flows);
    for (at_pole, j) in [
        (iv == 0 && topology.pole_at_start(), 0),
        (iv + 1 == n && topology.pole_at_end(), 3),
    ] {
        if at_pole {
            for i in 1..4 {
                delta[4 * i + j] = delta[j];
            }
        }
    }
    delta
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_envelope_is_the_strongest_and_the_mean_of_ties_in_any_order() {
        let a = DVec3::new(0.0, 0.0, -0.3);
        let b = DVec3::new(0.1, 0.0, -0.1);
        let c = DVec3::new(0.0, 0.3, 0.0);
        let of = |flows: &[DVec3]| {
            let mut e = Envelope::default();
            flows.iter().for_each(|f| e.add(*f));
            e.flow()
        };
        assert_eq!(of(&[]), DVec3::ZERO);
        assert_eq!(of(&[b]), b);
        assert_eq!(of(&[a, b]), a);
        assert_eq!(of(&[b, a]), a);
        assert_eq!(of(&[a, c]), (a + c) * 0.5);
        assert_eq!(of(&[c, a]), of(&[a, c]));
        assert_eq!(of(&[a, b, c, DVec3::ZERO]), of(&[DVec3::ZERO, c, b, a]));
        // A flow and its mirror image across x = 0 at a sample on the plane: the mean lies in
        // the plane.
        let f = DVec3::new(0.2, -0.1, -0.4);
        let mirrored = DVec3::new(-0.2, -0.1, -0.4);
        assert_eq!(of(&[f, mirrored]).x, 0.0);
    }
}
