//! How far one surface is from another, sample by sample (docs/design.md §14; P2 §6, Fig. 11).
//!
//! Surfaces are compared at the same parameters: `k × k` samples per patch at the cell
//! centres `((i + ½)/k, (j + ½)/k)` (40 × 40 in the paper: 160 000 samples on 100 patches).
//! The ideal surface of an operation is the starting surface with every sample moved by the
//! shape function, `S₀ + F(S₀)` ([`crate::surface::Finger::ideal`]).
//!
//! [`sample_iter`] and [`distance_iter`] stream the samples (memory for a patch or two, however
//! many samples); [`samples`] and [`distances`] hold them all (24 and 8 bytes per sample).

use glam::DVec3;

use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::shape_fn::Finger;

/// The samples of a grid, patch by patch (index order), `k × k` per patch, one at a time:
/// memory for one patch, whatever the grid and `k`.
pub fn sample_iter(grid: &Grid, k: usize) -> impl Iterator<Item = DVec3> + '_ {
    (0..grid.patch_count()).flat_map(move |p| {
        let patch = grid.patch_struct(p);
        (0..k * k).map(move |s| {
            let (i, j) = (s / k, s % k);
            patch.eval((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64)
        })
    })
}

/// The samples of a grid, patch by patch (index order), `k × k` per patch, all in memory
/// (24 bytes each); [`sample_iter`] streams them.
#[must_use]
pub fn samples(grid: &Grid, k: usize) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(grid.patch_count() * k * k);
    out.extend(sample_iter(grid, k));
    out
}

/// The samples of the surface a finger asks for, starting from `before`.
#[must_use]
pub fn ideal_samples(before: &Grid, finger: &Finger, k: usize) -> Vec<DVec3> {
    samples(before, k)
        .into_iter()
        .map(|x| finger.ideal(x))
        .collect()
}

/// Distances between two sets of samples taken at the same parameters.
///
/// # Errors
/// [`SurfaceError::Mismatch`] when the sets differ in length.
pub fn distances(a: &[DVec3], b: &[DVec3]) -> Result<Vec<f64>, SurfaceError> {
    if a.len() != b.len() {
        return Err(SurfaceError::Mismatch);
    }
    Ok(a.iter().zip(b).map(|(x, y)| (*x - *y).length()).collect())
}

/// Distances between two grids with the same number of patches at the same parameters (`k × k`
/// samples per patch, as [`sample_iter`]), one at a time: memory for two patches, whatever the
/// grids and `k`.
///
/// # Errors
/// [`SurfaceError::Mismatch`] when the grids differ in their number of patches.
pub fn distance_iter<'a>(
    a: &'a Grid,
    b: &'a Grid,
    k: usize,
) -> Result<impl Iterator<Item = f64> + 'a, SurfaceError> {
    if a.patch_count() != b.patch_count() {
        return Err(SurfaceError::Mismatch);
    }
    Ok(sample_iter(a, k)
        .zip(sample_iter(b, k))
        .map(|(x, y)| (x - y).length()))
}

/// Statistics of a set of distances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviationStats {
    /// How many distances were counted.
    pub count: usize,
    /// Their mean (0 when none).
    pub mean: f64,
    /// The largest.
    pub max: f64,
    /// The share (0..1) of them at most `within`.
    pub share_within: f64,
}

impl DeviationStats {
    /// Statistics of the distances, with the share of those at most `within`.
    pub fn of(distances: impl IntoIterator<Item = f64>, within: f64) -> Self {
        let (mut count, mut sum, mut max, mut inside) = (0usize, 0.0, 0.0f64, 0usize);
        for d in distances {
            count += 1;
            sum += d;
            max = max.max(d);
            inside += usize::from(d <= within);
        }
        let share_within = if count > 0 {
            inside as f64 / count as f64
        } else {
            0.0
        };
        Self {
            count,
            mean: if count > 0 { sum / count as f64 } else { 0.0 },
            max,
            share_within,
        }
    }
}

/// The largest distance between two grids of the same topology and counts, over `k × k`
/// samples per patch.
///
/// # Errors
/// [`SurfaceError::Mismatch`] when the grids differ in topology or counts.
pub fn max_distance(a: &Grid, b: &Grid, k: usize) -> Result<f64, SurfaceError> {
    if a.topology() != b.topology()
        || a.patches_u() != b.patches_u()
        || a.patches_v() != b.patches_v()
    {
        return Err(SurfaceError::Mismatch);
    }
    Ok(distance_iter(a, b, k)?.fold(0.0, f64::max))
}
