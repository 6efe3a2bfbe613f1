//! What the window derives from the document and keeps until the document changes: the
//! patches' control points, the tessellated surface, the continuity measure.
//!
//! Limits: the continuity measure waits while a gesture or a replay is in progress (it is
//! throttled to the end of a burst of edits on big grids).

use std::time::Instant;

use super::document::Document;
use super::scene::SurfaceDisplay;
use crate::mesh::{PatchPoints, Tessellation};
use crate::surface::continuity::{self, ContinuityReport};

/// The document's derived display data, rebuilt when its revision changes.
#[derive(Debug, Default)]
pub struct DisplayCache {
    /// The control points of every patch, at [`DisplayCache::revision`].
    patches: Vec<PatchPoints>,
    /// The tessellated surface.
    display: SurfaceDisplay,
    /// The document revision the display shows (`None`: rebuild).
    revision: Option<u64>,
    /// Counts display rebuilds across documents (a new document starts at revision 0 again).
    generation: u64,
    /// The continuity measure and the revision it is of.
    continuity: Option<ContinuityReport>,
    continuity_revision: Option<u64>,
    /// Time the last continuity measure took, ms.
    continuity_ms: f64,
}

impl DisplayCache {
    /// Forgets everything (a new document): the next [`DisplayCache::refresh`] rebuilds.
    pub fn invalidate(&mut self) {
        self.revision = None;
        self.continuity_revision = None;
    }

    /// Brings the patches and tessellation up to `doc`'s revision, and the continuity measure
    /// too unless `busy` (a gesture or replay in progress). True when the surface was rebuilt.
    pub fn refresh(&mut self, doc: &Document, busy: bool) -> bool {
        let revision = doc.revision();
        let rebuilt = self.revision != Some(revision);
        if rebuilt {
            self.patches = doc.model().surface.patches();
            self.display = SurfaceDisplay::new(&self.patches, &Tessellation::DISPLAY);
            self.revision = Some(revision);
            self.generation += 1;
        }
        // The continuity measure (33 points per shared edge) is cheap for the paper's sizes.
        if self.continuity_revision != Some(revision) && !busy {
            let start = Instant::now();
            self.continuity = Some(continuity::report(
                &doc.model().surface,
                continuity::MIN_SAMPLES_PER_EDGE,
            ));
            self.continuity_ms = start.elapsed().as_secs_f64() * 1e3;
            self.continuity_revision = Some(revision);
        }
        rebuilt
    }

    /// The patches' control points.
    #[must_use]
    pub fn patches(&self) -> &[PatchPoints] {
        &self.patches
    }

    /// The tessellated surface.
    #[must_use]
    pub fn display(&self) -> &SurfaceDisplay {
        &self.display
    }

    /// Changes whenever [`DisplayCache::display`] does (also across documents).
    #[must_use]
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The last continuity measure and how long it took (ms).
    #[must_use]
    pub fn continuity(&self) -> (Option<&ContinuityReport>, f64) {
        (self.continuity.as_ref(), self.continuity_ms)
    }
}
