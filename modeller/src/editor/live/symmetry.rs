//! The symmetry group a device session presses with.
//!
//! - **A live session that does not record** (a glove and tracker, a skeleton source such as
//!   VMC) follows the window's symmetry as the mouse hand does: before every frame that finds
//!   the hand free (between contacts) the window's group is looked for on the surface as it is
//!   then ([`Symmetry::group`]: wanted, and the model has it) and taken up; a contact keeps the
//!   group it began with ([`HandDriver::set_mirror`]).
//! - **A recording session** presses with the window's symmetry as it was at Connect, until the
//!   recording stops (Disconnect, or the stream's end), whatever the toggle says meanwhile: the
//!   trace's scene is written once, in its header, and names that group (`mirror`, `radial`,
//!   `lathe`: [`crate::hand::scene`]), and `nendo replay` presses every contact of the trace
//!   with that one group — so the window and the replay agree bit for bit. While the recording
//!   runs the Tool panel (under the symmetry checkbox), the Devices panel's session line and,
//!   when the toggle changes, the status line say so ([`LiveInput::symmetry_note`]). A
//!   lathe kept over `N`-fold radial symmetry (`N` not the patch columns) has no scene member
//!   (`nendo replay` has no such option): Connect refuses to record it, saying why.
//! - **A replayed trace** (the panel's Replay, a replay profile) presses with its scene's group
//!   (none when its scene names none, or it has no scene), whatever the window's toggle says:
//!   bit for bit with `nendo replay` of the same trace is the contract. A model that does not
//!   have the scene's group is refused at the start with the reason, as `nendo replay` refuses
//!   it.
//!
//! A session with a fixed group starts as `nendo replay` does (`cli::symmetry_args`): the group
//! `G` of the scene's spec (read back from the scene, so its planes are in the scene's order)
//! is found on the document's surface as it is at the start, and the whole surface is made
//! exactly invariant under it — each orbit of control points replaced by the images of its mean,
//! `x̄ = (1/|G|) Σ_g g⁻¹ x_σ_g(n)`, `x'_σ_g(n) = g x̄` ([`Symmetry::enforce_all`]). That is one
//! undoable edit (`symmetry`) when it changes a bit of the model, none otherwise. A recording
//! embeds the model from before it, which the replay makes invariant by the same computation,
//! so both start from the same bits and press with the same group.

use crate::editor::document::Document;
use crate::editor::hand_input::HandDriver;
use crate::hand::scene::Scene;
use crate::surface::{Regulation, Symmetry, SymmetrySpec};

use super::LiveInput;

/// Why a session's group is fixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum FixedBy {
    /// The session records: its trace's scene names the group.
    Recording,
    /// The session replays a trace: its scene names the group.
    Replay,
}

/// The group the device hand presses with (see the module docs).
#[derive(Debug, Clone, Default)]
pub(super) struct PressingSymmetry {
    /// The symmetry the window asks for (`None`: off), set by the window every frame.
    window: Option<SymmetrySpec>,
    /// The window's group looked for on the surface at a document revision.
    found: Option<(u64, SymmetrySpec, Option<Symmetry>)>,
    /// The running session's fixed group (`None`: the session follows the window).
    fixed: Option<(FixedBy, Option<Symmetry>)>,
}

impl PressingSymmetry {
    /// The group a contact begun now on `doc` presses with: the session's fixed one, else the
    /// window's when it is wanted and the model has it (`None`: one-sided).
    pub(super) fn for_contact(&mut self, doc: &Document) -> Option<&Symmetry> {
        let grid = &doc.model().surface;
        if let Some((_, fixed)) = &self.fixed {
            return fixed.as_ref().filter(|s| s.fits(grid));
        }
        let spec = self.window.as_ref()?;
        let revision = doc.revision();
        let known = matches!(&self.found, Some((r, s, _)) if *r == revision && s == spec);
        if !known {
            self.found = Some((revision, spec.clone(), Symmetry::group(grid, spec).ok()));
        }
        self.found
            .as_ref()
            .and_then(|(_, _, s)| s.as_ref())
            .filter(|s| s.fits(grid))
    }

    /// The window's symmetry as a session starting now on `doc` would take it: asked for and
    /// the model has it.
    fn window_active(&mut self, doc: &Document) -> Option<SymmetrySpec> {
        let fixed = self.fixed.take();
        let spec = self.for_contact(doc).map(|s| s.spec().clone());
        self.fixed = fixed;
        spec
    }

    /// Takes up the group for the next frame (the hand free: between contacts).
    pub(super) fn take_up(&mut self, driver: &mut HandDriver, doc: &Document) {
        if driver.hand_loop().touch() == crate::hand::Touch::Free {
            driver.set_mirror(self.for_contact(doc));
        }
    }
}

/// A fixed group planned for a session about to start: why, and the scene members naming it.
#[derive(Debug, Clone)]
pub(super) struct FixedPlan {
    by: FixedBy,
    mirror: Vec<crate::surface::Plane>,
    radial: Option<u32>,
    lathe: bool,
}

impl FixedPlan {
    /// The group as a scene with these members reads back (`Scene::symmetry`, and `nendo
    /// replay`'s `--mirror` with `--radial` / `--lathe`): the planes sorted, radial `N` or 0.
    fn spec(&self) -> SymmetrySpec {
        let mut spec = SymmetrySpec {
            radial: self.radial.unwrap_or(0),
            lathe: self.lathe,
            ..SymmetrySpec::default()
        };
        for &p in &self.mirror {
            spec.add_plane(p);
        }
        spec
    }

    /// Names the group in the recording's `scene`.
    pub(super) fn name_in(&self, scene: &mut Scene) {
        scene.mirror.clone_from(&self.mirror);
        scene.radial = self.radial;
        scene.lathe = self.lathe;
    }
}

/// The members of a trace's scene naming `spec` on a grid of `columns` patch columns:
/// mirrors, radial `N` (`None`: none) and the lathe.
///
/// # Errors
/// A lathe over `N`-fold radial symmetry, `N` not the patch columns, which a scene cannot name.
fn scene_members(
    spec: &SymmetrySpec,
    columns: usize,
) -> Result<(Vec<crate::surface::Plane>, Option<u32>, bool), String> {
    if spec.lathe {
        if spec.radial > 1 && spec.radial as usize != columns {
            return Err(format!(
                "cannot record the {spec}: a trace's scene (and nendo replay) names a lathe or radial symmetry, not a lathe kept {}-fold; record with the lathe proper, radial symmetry, or without symmetry",
                spec.radial
            ));
        }
        return Ok((spec.planes.clone(), None, true));
    }
    Ok((
        spec.planes.clone(),
        (spec.radial > 1).then_some(spec.radial),
        false,
    ))
}

/// The group of `spec` found on `doc`'s surface and the whole surface made invariant under it,
/// as `nendo replay` starts (see the module docs); `None` when `spec` asks for nothing.
///
/// # Errors
/// The model does not have the group: the reason.
fn start_fixed(doc: &mut Document, spec: &SymmetrySpec) -> Result<Option<Symmetry>, String> {
    if spec.is_none() {
        return Ok(None);
    }
    let s = Symmetry::group(&doc.model().surface, spec)
        .map_err(|e| format!("the model does not have the {spec}: {e}"))?;
    let mut model = doc.model().clone();
    let poles = model.regulation != Regulation::None;
    s.enforce_all(&mut model.surface, poles)
        .map_err(|e| format!("{spec}: {e}"))?;
    // A bit changed (a −0 made +0 counts: `==` on the models would not see it).
    let bits = |p: &glam::DVec3| p.to_array().map(f64::to_bits);
    let moved = (model.surface.nodes().iter())
        .zip(doc.model().surface.nodes())
        .any(|(a, b)| bits(a) != bits(b));
    if moved || &model != doc.model() {
        doc.replace("symmetry", model);
    }
    Ok(Some(s))
}

impl LiveInput {
    /// The symmetry the window asks for (`None`: off): device sessions that follow the window
    /// take it up between contacts, and a recording starts with it (see the `symmetry` module
    /// docs). The window sets it every frame.
    pub fn set_window_symmetry(&mut self, spec: Option<SymmetrySpec>) {
        self.symmetry.window = spec;
    }

    /// Forgets the group found on the surface (another document: its revisions start again).
    pub fn forget_symmetry(&mut self) {
        self.symmetry.found = None;
    }

    /// What the window's symmetry toggle does not govern now, for the symmetry panel and the
    /// status line: a recording's group kept until it stops, a replayed trace's scene's group;
    /// `None` when the device hand follows the window (or no session runs).
    #[must_use]
    pub fn symmetry_note(&self) -> Option<String> {
        self.session.as_ref()?;
        let (by, s) = self.symmetry.fixed.as_ref()?;
        let group = s
            .as_ref()
            .map_or_else(|| "no symmetry".to_string(), |s| s.spec().to_string());
        Some(match by {
            FixedBy::Recording => {
                format!("the recording device session presses with {group} until it stops")
            }
            FixedBy::Replay => format!("the replayed trace presses with its scene's {group}"),
        })
    }

    /// The fixed group of a session about to start on `doc` (see the module docs): a replay's
    /// (`trace`: the replayed trace's header) from its scene, else, when `recording`, the
    /// window's now; `None` for a session that follows the window. Nothing changes yet
    /// ([`LiveInput::fix_symmetry`] once the session has started).
    ///
    /// # Errors
    /// Why the session cannot start: the trace's scene does not read, the model does not have
    /// the group, or a scene cannot name it.
    pub(super) fn plan_symmetry(
        &mut self,
        doc: &Document,
        trace: Option<&nendo_devices::TraceHeader>,
        recording: bool,
    ) -> Result<Option<FixedPlan>, String> {
        let (by, spec) = match trace {
            Some(h) => {
                let scene = Scene::of_trace(h)
                    .map_err(|e| format!("cannot replay: the trace's scene: {e}"))?;
                (
                    FixedBy::Replay,
                    scene.map(|s| s.symmetry()).unwrap_or_default(),
                )
            }
            None if recording => (
                FixedBy::Recording,
                self.symmetry.window_active(doc).unwrap_or_default(),
            ),
            None => return Ok(None),
        };
        let (mirror, radial, lathe) = scene_members(&spec, doc.model().surface.patches_u())?;
        let plan = FixedPlan {
            by,
            mirror,
            radial,
            lathe,
        };
        let spec = plan.spec();
        if !spec.is_none() {
            Symmetry::group(&doc.model().surface, &spec).map_err(|e| match by {
                FixedBy::Replay => format!(
                    "cannot replay: the trace's scene presses with the {spec}, which the model does not have: {e}"
                ),
                FixedBy::Recording => format!("cannot record with the {spec}: {e}"),
            })?;
        }
        Ok(Some(plan))
    }

    /// Fixes the planned group for the session just started on `doc` (see the module docs: the
    /// surface made invariant under it, as `nendo replay` starts); `None` leaves the hand
    /// following the window.
    ///
    /// # Errors
    /// The model does not have the group (it changed since the plan).
    pub(super) fn fix_symmetry(
        &mut self,
        doc: &mut Document,
        plan: Option<FixedPlan>,
    ) -> Result<(), String> {
        self.symmetry.fixed = None;
        let Some(plan) = plan else {
            return Ok(());
        };
        let group = start_fixed(doc, &plan.spec())?;
        self.symmetry.fixed = Some((plan.by, group));
        Ok(())
    }

    /// The session ended: the device hand follows the window again.
    pub(super) fn release_symmetry(&mut self) {
        self.symmetry.fixed = None;
    }
}
