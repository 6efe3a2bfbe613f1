//! The paper's baseline, its "former method" (P2 §1, ref. 15; compared in §6 and
//! Fig. 10): tangent continuity enforced as **C1** between patches, which over-constrains the
//! surface and deforms it more.
//!
//! The reference describing it is not among the papers (docs/design.md §2), so it is rebuilt here as the C1
//! counterpart of the paper's own construction ([`super::g1`]): the same steps, but the two
//! edge points on either side of `P_O` are put at their *mean* distance, so every row and
//! column of a group is collinear **and equally spaced** (`P(+1) − P(0) = P(0) − P(−1)`): the
//! cross-boundary derivatives of neighbouring patches are equal, C1 in the grid's own
//! parametrisation. At a pole the opposite meridians are made point-symmetric through the
//! pole (`v₁ = v₂`), with equally spaced ring triples. Where the net's own spacing is not
//! uniform (the join of the tube's bottom and walls) this pulls the surface away from its
//! shape — the over-constraint the paper describes.

use super::g1::{Spacing, construct_group, construct_pole};
use super::{GroupPoints, PolePoints};

/// Regulates one non-degenerate group to C1; `false` when it had to be left as it is.
pub fn regulate_group(p: &mut GroupPoints) -> bool {
    construct_group(p, Spacing::Equal)
}

/// Regulates a pole to point symmetry; `false` when no pair could be regulated.
pub fn regulate_pole(p: &mut PolePoints) -> bool {
    construct_pole(p, Spacing::Equal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn rows_and_columns_become_equally_spaced() {
        let mut p: GroupPoints = [[None; 3]; 3];
        for s in 0..3 {
            for t in 0..3 {
                let (x, y) = (s as f64 * (0.3 + 0.1 * t as f64), t as f64 * 0.4);
                p[s][t] = Some(DVec3::new(
                    x + 0.05 * (s * t) as f64,
                    y,
                    0.1 * (s as f64 - t as f64).powi(2),
                ));
            }
        }
        assert!(regulate_group(&mut p));
        let g = |s: usize, t: usize| p[s][t].unwrap();
        for k in 0..3 {
            assert!(((g(2, k) - g(1, k)) - (g(1, k) - g(0, k))).length() < 1e-14);
            assert!(((g(k, 2) - g(k, 1)) - (g(k, 1) - g(k, 0))).length() < 1e-14);
        }
    }
}
