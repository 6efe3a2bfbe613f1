//! The deformation engine: one pipeline for every change the fingers make to the clay
//! (P2 §2.1, Fig. 1; `docs/design.md`, "The deformation engine").
//!
//! 1. **Reach.** The patches whose control-point boxes a [`field::DisplacementField`] may
//!    reach are found in the bounding-box pyramid ([`crate::surface::bounds`]), so the cost
//!    follows the touched area, not the patch count (the paper's own future work).
//! 2. **Flow.** Each such patch is sampled at `{0, 1/3, 2/3, 1}²` and every sample gets the
//!    envelope of the field's flows there (the strongest; the mean of the equally strongest).
//!    A patch whose 16 flows are all zero is left alone, bit for bit.
//! 3. **Inverse.** `ΔP = B₄⁻¹ F B₄⁻ᵀ` per patch ([`crate::surface::inverse`]), the pole moved
//!    by its own sample's flow ([`field::displace`]).
//! 4. **Regulation** ([`crate::surface::regulate`]) of the groups around the corners of the
//!    moved patches (and of a pole one of them touches), with the chosen method; groups are
//!    disjoint, so this is local too.
//! 5. **Mirror, verification, rollback** ([`commit::Commit`]): a mirror makes the result
//!    exactly symmetric (a mirror made for another grid is an error); the result is verified
//!    ([`crate::surface::verify()`]); a refusal puts the grid back bit for bit.
//!
//! Two drivers share it: [`Sculptor`] applies one shape-function operation (a finger on the
//! current grid, or a surface brush — inflate, flatten, pinch, crease — whose field reads the
//! grid's normals: `sculpt_field`), [`Presser`] one contact of the hand (a memoised envelope of placements on
//! the contact's reference grid, re-applied incrementally frame by frame); [`LiveOperation`]
//! shows one operation live (a pinch, a stroke), re-applied to its start each time it changes. Everything runs in
//! a fixed order on plain `f64` arithmetic: the same operation applied to the same grid gives
//! bit-identical results, and an operation and the same contact give the same grid.

mod commit;
mod field;
mod live;

mod presser;
mod sculpt_field;
mod sculptor;

pub use live::LiveOperation;

pub use presser::{Placement, Presser, Stroke, describe};
pub use sculptor::{Sculptor, Touched, deform};
