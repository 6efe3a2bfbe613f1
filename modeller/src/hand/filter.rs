//! The hand loop's filter: every frame [`HandLoop::frame`] takes goes first through a
//! plausibility gate and a One-Euro filter ([`nendo_devices::filter`], where the rules, the
//! formulas and the defaults are), so that a glitch of the tracker or the glove never reaches
//! the clay and jitter is smoothed before contact is decided.
//!
//! It runs inside the loop — the one place the window ([`crate::editor`]'s hand driver),
//! `nendo replay` and [`super::HandSession`] all feed frames through — on the frames' own
//! timestamps, so a replay reproduces the window exactly: same raw frames in, same filtered
//! frames, same rejections. Traces keep the raw samples; the settings travel with a recording
//! in its scene ([`super::scene::Scene::filter`]), and the recorders (the window's, `nendo
//! record`) run the same gate with those settings as they write, marking the samples it held
//! (trace version 4, [`nendo_devices::trace::HeldMarks`]), which `nendo replay` checks against
//! its own gate.
//!
//! Which settings a loop uses:
//! - a new loop: [`default_for`] its finger — the defaults for a glove's hand, **off for the
//!   mouse's view ray** ([`FingerModel::Ray`]): its frames are computed from the pointer,
//!   exact and without glitches, and its depth follows the wheel step by step;
//! - the window's device session: the profile's `filter` ([`nendo_devices::Profile::filter`]);
//! - `nendo replay`: `--no-filter`, else the trace's scene's `filter`, else `--profile`'s,
//!   else [`default_for`] the finger.

use nendo_devices::TraceHeader;
use nendo_devices::filter::{FilterSettings, FilterStats, FrameFilter};

use super::hand_loop::HandLoop;
use super::parts::FingerModel;

/// The filter a hand loop starts with: the defaults ([`FilterSettings::default`]) for the
/// kinematic hand, off for the mouse's view ray.
#[must_use]
pub fn default_for(finger: FingerModel) -> FilterSettings {
    match finger {
        FingerModel::Ray => FilterSettings::off(),
        FingerModel::Hand(_) => FilterSettings::default(),
    }
}

/// The filter a recorded trace was made with: its scene's `filter`, else [`default_for`] the
/// finger (a scene that does not read says nothing).
#[must_use]
pub fn for_trace(header: &TraceHeader, finger: FingerModel) -> FilterSettings {
    super::scene::Scene::of_trace(header)
        .ok()
        .flatten()
        .and_then(|s| s.filter)
        .unwrap_or_else(|| default_for(finger))
}

impl HandLoop {
    /// Gates and filters the frames from now on with `settings`, starting afresh (the next
    /// sample of each source passes through as it is). Check them first
    /// ([`FilterSettings::validate`]): a loop takes them as they are.
    pub fn set_filter(&mut self, settings: FilterSettings) {
        self.filter = FrameFilter::new(settings);
    }

    /// The gate and filter: settings, counters, what the last frame had held.
    #[must_use]
    pub fn filter(&self) -> &FrameFilter {
        &self.filter
    }
}

/// The gate's counters for people, as `nendo replay` prints them: `"gate: nothing held"`,
/// or the values held per channel, e.g. `"gate held 3 tracker positions, 1 orientation and
/// 5 joint angles in 8 frames (2 out of range, 6 too fast or sudden)"`.
#[must_use]
pub fn describe(stats: &FilterStats) -> String {
    if stats.rejected() == 0 {
        return "gate: nothing held".into();
    }
    let plural = |n: u64, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let mut parts = Vec::new();
    for (n, one, many) in [
        (
            stats.position.total(),
            "tracker position",
            "tracker positions",
        ),
        (stats.orientation.total(), "orientation", "orientations"),
        (stats.joints.total(), "joint angle", "joint angles"),
        (
            stats.skeleton_positions.total(),
            "skeleton joint position",
            "skeleton joint positions",
        ),
        (
            stats.skeleton_orientations.total(),
            "skeleton joint orientation",
            "skeleton joint orientations",
        ),
    ] {
        if n > 0 {
            parts.push(plural(n, one, many));
        }
    }
    let list = match parts.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    };
    let range = stats.position.out_of_range
        + stats.orientation.out_of_range
        + stats.joints.out_of_range
        + stats.skeleton_positions.out_of_range
        + stats.skeleton_orientations.out_of_range;
    let kinematic = stats.rejected() - range;
    let resyncs = if stats.resyncs > 0 {
        format!(
            ", {}",
            plural(stats.resyncs, "lasting jump taken", "lasting jumps taken")
        )
    } else {
        String::new()
    };
    format!(
        "gate held {list} in {} ({range} out of range, {kinematic} too fast or sudden{resyncs})",
        plural(stats.frames_held, "frame", "frames")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_names_what_was_held() {
        let mut s = FilterStats::default();
        assert_eq!(describe(&s), "gate: nothing held");
        s.position.too_fast = 2;
        s.position.out_of_range = 1;
        s.joints.too_sudden = 5;
        s.orientation.too_sudden = 1;
        s.frames_held = 8;
        assert_eq!(
            describe(&s),
            "gate held 3 tracker positions, 1 orientation and 5 joint angles in 8 frames (1 out of range, 8 too fast or sudden)"
        );
        s.orientation.too_sudden = 0;
        s.joints.too_sudden = 0;
        s.resyncs = 1;
        assert_eq!(
            describe(&s),
            "gate held 3 tracker positions in 8 frames (1 out of range, 2 too fast or sudden, 1 lasting jump taken)"
        );
    }

    #[test]
    fn the_mouse_is_not_filtered() {
        assert!(!default_for(FingerModel::Ray).enabled);
        assert!(default_for(FingerModel::default()).enabled);
    }
}
