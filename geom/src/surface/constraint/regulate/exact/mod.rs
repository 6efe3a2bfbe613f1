//! nendo's default regulation: **exact G1 on every shared edge and a true tangent plane at
//! every pole**, moving the control points as little as possible (least squares) away from
//! where the Bernstein inverse put them — i.e. from the shape the finger asked for.
//!
//! ## Why the paper's construction is not enough
//! Two bicubic patches sharing an edge are G1 along the whole edge when every three-point row
//! of control points crossing it, `(P₋, P₀, P₊)`, is collinear **with one ratio**
//! `P₊ − P₀ = ρ (P₀ − P₋)` for all four rows of the edge (then the cross-boundary derivatives
//! satisfy `D₊(v) = ρ D₋(v)` for every `v`). The four rows of an edge belong to the groups at
//! its two ends; the paper's construction ([`super::g1`]) makes each group's rows collinear
//! with that group's own ratio, so an edge is G1 only where the ratios at its two end vertices
//! happen to agree (the paper's own remark that its constraint "is not optimal").
//!
//! ## The method
//! Each shared grid line has a fixed **reference spacing ratio** ρ, measured once when the
//! grid is built (all 1 on the primitives but at the tube's bottom-to-wall join; see
//! [`crate::surface::grid`]). The G1 conditions are then *linear* in the control points:
//! `ρ P₋ − (1 + ρ) P₀ + P₊ = 0` for every row crossing a grid line. Within a group they say
//! exactly that the group is a bilinear lattice with fixed spacings,
//!
//! ```text
//! P(s, t) = P_O + s̃ a + t̃ b + s̃ t̃ c,   s̃ ∈ {−1, 0, ρ_u},  t̃ ∈ {−1, 0, ρ_v}
//! ```
//!
//! with four free vectors `P_O, a, b, c`. The regulated net is the member of that family
//! nearest to the unregulated net **in the surface's own metric**. The constraints of different groups share no point, so each group
//! *could* be projected on its own (the former default, [`Projection`], kept as the fallback
//! and for comparison: [`super::exact_group_by_group`]); the metric couples them.
//!
//! The touched groups are projected together (`Coupled`, the default; its module doc has
//! the normal equations and their skyline solve): among all nets whose touched groups are such
//! lattices and whose other nodes stay, the one nearest to the unregulated net in
//! `Σ_p ∫|ΔS_p|²` over every patch around the touched groups. A set whose factorisation would
//! cost more than `Coupled`'s limit (hundreds of groups across), or fails, is projected group
//! by group ([`Projection`]: the same least squares with the metric made block-diagonal).
//! Poles are regulated first, onto a fitted tangent plane ([`regulate_pole`]), and their rings
//! are fixed nodes of the solve.
//!
//! Every regulated state satisfies the constraints with the same ratios, so they never drift:
//! G1 holds to rounding (≈10⁻¹²°) along every edge, whatever was touched before.
//!
//! **Why fixed ratios and not the deformed net's own**: ratios re-measured after each
//! deformation would let one stroke shift the spacing along whole grid lines (and need a
//! global solve); with the reference spacing every group is independent and a stroke stays
//! local, as the throwaway study in docs/design.md §12 also found.
//!
//! ## Accuracy and limits
//! On a push into the plane (depth 1, mean / max distance from the ideal dent, side): the
//! coupled projection 0.0140 / 0.1106, within 6 % of the best any net of the family can do
//! (0.0132 / 0.1046) in the mean at every depth; group by group 0.0164 / 0.1201; the
//! unregulated net 0.0065 / 0.1013. The largest deviation lies on the dent's crease `r = r_f`,
//! not at the push point: the ideal dent's slope jumps there, and a G1 net with fixed spacing
//! ratios (on the plane, a C1 bicubic Hermite spline) cannot bend inside a patch, so the max
//! stays above the unregulated net's (1.09 × at r_f 1.25); whether it stays within
//! `unregulated max + 0.01` depends on the finger's radius against the patch size.
//!
//! The figures, the alternatives tried (other objectives, displacement-weighted metrics,
//! fixed metric changes) and the cost measurements are in `docs/regulation-notes.md`.

mod coupled;
mod pole;
mod projection;
mod skyline;
#[cfg(test)]
mod tests;

pub(crate) use coupled::Coupled;
pub use pole::regulate_pole;
pub use projection::{Projection, present, regulate_group};
