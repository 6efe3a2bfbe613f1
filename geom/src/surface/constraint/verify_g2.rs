//! The G2 part of the verification of an operation's result under
//! [`Regulation::G2`](crate::surface::Regulation::G2) (see [`crate::surface::verify()`]).

use glam::DVec3;

use crate::surface::curvature::seam_mismatch;
use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::limits::{G2_FLAT, G2_TOLERANCE};
use crate::surface::marks::Marks;
use crate::surface::verify::shared_edges;

/// Points per edge at which [`verify_g2`] compares the normal curvatures of the two sides
/// (inside the edge: its ends may be a pole).
const G2_SAMPLES: usize = 7;

/// Under [`Regulation::G2`]: every shared edge of `patches` one of whose two patches has a
/// changed control point (marked in `marks`) has its normal curvatures across the edge agree within
/// [`G2_TOLERANCE`] relative, unless their absolute difference is below [`G2_FLAT`] / the
/// model's size, or the edge was not G2 before the operation either (measured with the old
/// positions of `before` put back, as for G1).
pub(crate) fn verify_g2(
    grid: &mut Grid,
    patches: &[usize],
    before: &[(usize, DVec3)],
    marks: &Marks,
) -> Result<(), SurfaceError> {
    let m = grid.patches_u();
    let shape = grid.shape();
    let bounds = grid.bounds();
    let size = (bounds.max - bounds.min).length().max(f64::MIN_POSITIVE);
    let flat = G2_FLAT / size;
    let measure = |grid: &Grid, a: usize, b: usize, along_u: bool| {
        let (pa, pb) = (grid.patch_struct(a), grid.patch_struct(b));
        seam_mismatch(&pa, &pb, along_u, G2_SAMPLES, flat)
    };
    let fails = |(rel, abs): (f64, f64)| rel.is_nan() || (rel > G2_TOLERANCE && abs > flat);
    let mut jumps = Vec::new();
    shared_edges(grid, patches, |pa, pb, along_u| {
        // The curvature across an edge depends on every node of both patches.
        let changed = |p: (usize, usize)| shape.patch_ids(p.0, p.1).iter().any(|&id| marks.get(id));
        if !changed(pa) && !changed(pb) {
            return;
        }
        let (a, b) = (pa.1 * m + pa.0, pb.1 * m + pb.0);
        let got = measure(grid, a, b, along_u);
        if fails(got) {
            jumps.push((a, b, along_u, got));
        }
    });
    if jumps.is_empty() {
        return Ok(());
    }
    let after: Vec<DVec3> = before.iter().map(|&(id, _)| grid.nodes()[id]).collect();
    {
        let nodes = grid.nodes_mut();
        for &(id, x) in before.iter().rev() {
            nodes[id] = x;
        }
    }
    jumps.retain(|&(a, b, along_u, _)| !fails(measure(grid, a, b, along_u)));
    {
        let nodes = grid.nodes_mut();
        for (&(id, _), &x) in before.iter().zip(&after) {
            nodes[id] = x;
        }
    }
    match jumps.iter().max_by(|x, y| {
        x.3.0
            .partial_cmp(&y.3.0)
            .unwrap_or(std::cmp::Ordering::Greater)
    }) {
        None => Ok(()),
        Some(&(patch, other, _, (relative, absolute))) => Err(SurfaceError::NotG2 {
            patch,
            other,
            relative,
            absolute,
            tolerance: G2_TOLERANCE,
        }),
    }
}
