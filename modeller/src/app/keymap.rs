//! Every key and mouse binding of the window, in one table: the shortcuts are read from it,
//! the help overlay (F1 or `?`) lists it, and the README's "Using the window" section is the
//! table [`markdown`] prints (a test compares them), so none of them can drift.
//!
//! The keys follow Blender's sculpt mode where they do not clash: F then a move sets the
//! finger radius, Shift+F the depth, Ctrl inverts a stroke, Shift smooths, X toggles
//! symmetry, G picks Move, I Inflate, Shift+T Flatten, P Pinch, Shift+C Crease, Home frames
//! the model, number keys pick tools, numpad 5 toggles the orthographic view. The orbit button
//! is a setting ([`OrbitButton`]): the right button (nendo's
//! default) or the middle one (Blender's). Each key gives the modeller a [`Command`]
//! ([`KeyAction::command`]).
//!
//! egui names keys by what they type, so numpad 5 and the main 5 are one `Key::Num5`; keys
//! that must be told apart by where they are ([`physical_keys`]) are read from winit's
//! physical key code by the window (`app::window`) before egui sees them, and only while no
//! text field has the keyboard.

use egui::{Key, Modifiers};

use crate::editor::command::{Command, DialogPurpose};
use crate::editor::input::OrbitButton;
use crate::editor::tools::Tool;

/// What a key does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyAction {
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Save the model.
    Save,
    /// Open a model file.
    Open,
    /// Frame the whole model.
    FrameAll,
    /// Open or close the help overlay.
    Help,
    /// Cancel the stroke or the adjustment in progress, or close the help or the dialog.
    Cancel,
    /// Set the finger radius by moving the mouse (click to keep, Esc to restore).
    AdjustRadius,
    /// Set the depth by moving the mouse (click to keep, Esc to restore).
    AdjustDepth,
    /// Turn symmetry (the mirror across x = 0) on or off.
    ToggleSymmetry,
    /// Radial symmetry about the z axis: off → N-fold → lathe → off.
    ToggleRadial,
    /// Show the surface in the next display mode.
    CycleSurfaceMode,
    /// Switch the view between perspective and orthographic.
    ToggleProjection,
    /// Pick a tool.
    Tool(Tool),
}

impl KeyAction {
    /// The command the key gives the modeller.
    #[must_use]
    pub fn command(self) -> Command {
        match self {
            KeyAction::Undo => Command::Undo,
            KeyAction::Redo => Command::Redo,
            KeyAction::Save => Command::Save,
            KeyAction::Open => Command::ShowDialog(DialogPurpose::OpenModel),
            KeyAction::FrameAll => Command::FrameAll,
            KeyAction::Help => Command::ToggleHelp,
            KeyAction::Cancel => Command::Cancel,
            KeyAction::AdjustRadius => Command::AdjustRadius,
            KeyAction::AdjustDepth => Command::AdjustDepth,
            KeyAction::ToggleSymmetry => Command::ToggleSymmetry,
            KeyAction::ToggleRadial => Command::ToggleRadial,
            KeyAction::CycleSurfaceMode => Command::CycleSurfaceMode,
            KeyAction::ToggleProjection => Command::ToggleProjection,
            KeyAction::Tool(tool) => Command::SelectTool(tool),
        }
    }

    /// What the action does, in plain words (the help overlay and the README).
    #[must_use]
    pub fn describe(self) -> String {
        match self {
            KeyAction::Undo => "undo".into(),
            KeyAction::Redo => "redo".into(),
            KeyAction::Save => "save".into(),
            KeyAction::Open => "open a model".into(),
            KeyAction::FrameAll => "frame the model".into(),
            KeyAction::Help => "this help".into(),
            KeyAction::Cancel => {
                "cancel the stroke (the surface comes back exactly) or the radius / depth change; close the help or the file dialog".into()
            }
            KeyAction::AdjustRadius => {
                "finger radius: move the mouse right to grow it, left to shrink it; click to keep, Esc or right click to restore".into()
            }
            KeyAction::AdjustDepth => {
                "depth (a click's push, a line's groove): move the mouse; click to keep, Esc or right click to restore".into()
            }
            KeyAction::ToggleSymmetry => {
                "symmetry on / off: every stroke mirrored across x = 0 (offered for a model symmetric about it)".into()
            }
            KeyAction::ToggleRadial => {
                "radial symmetry: off → N-fold about the z axis (every stroke repeated N times; N in the tool panel, dividing the patch columns) → lathe (every stroke all the way round) → off; offered for a rotational model".into()
            }
            KeyAction::CycleSurfaceMode => {
                "surface display: clay → zebra stripes → curvature map → isophotes (from the patches' exact derivatives, per pixel)".into()
            }
            KeyAction::ToggleProjection => {
                "view: perspective ↔ orthographic (parallel rays; the framing at the orbit target kept), as in Blender".into()
            }
            KeyAction::Tool(tool) => format!("tool: {}", tool.label()),
        }
    }
}

/// One key binding.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyBinding {
    /// The key.
    pub key: Key,
    /// The modifiers (Ctrl is egui's `COMMAND`).
    pub modifiers: Modifiers,
    /// What it does.
    pub action: KeyAction,
}

impl KeyBinding {
    const fn new(modifiers: Modifiers, key: Key, action: KeyAction) -> Self {
        Self {
            key,
            modifiers,
            action,
        }
    }

    /// The keys as written in the help: `Ctrl+Shift+Z`.
    #[must_use]
    pub fn keys(&self) -> String {
        let mut s = String::new();
        if self.modifiers.command || self.modifiers.ctrl {
            s.push_str("Ctrl+");
        }
        if self.modifiers.alt {
            s.push_str("Alt+");
        }
        if self.modifiers.shift {
            s.push_str("Shift+");
        }
        s.push_str(match self.key {
            Key::Questionmark => "?",
            Key::Escape => "Esc",
            k => k.name(),
        });
        s
    }
}

/// The number keys, for the tools in panel order.
const NUMBER_KEYS: [Key; 9] = [
    Key::Num1,
    Key::Num2,
    Key::Num3,
    Key::Num4,
    Key::Num5,
    Key::Num6,
    Key::Num7,
    Key::Num8,
    Key::Num9,
];

/// Every key binding, in the order they are matched: a binding with more modifiers comes
/// before the same key with fewer (egui matches Shift loosely: `F` would take Shift+F).
#[must_use]
pub fn keys() -> Vec<KeyBinding> {
    let cmd = Modifiers::COMMAND;
    let mut keys = vec![
        KeyBinding::new(cmd | Modifiers::SHIFT, Key::Z, KeyAction::Redo),
        KeyBinding::new(cmd, Key::Y, KeyAction::Redo),
        KeyBinding::new(cmd, Key::Z, KeyAction::Undo),
        KeyBinding::new(cmd, Key::S, KeyAction::Save),
        KeyBinding::new(cmd, Key::O, KeyAction::Open),
        KeyBinding::new(Modifiers::SHIFT, Key::F, KeyAction::AdjustDepth),
        KeyBinding::new(Modifiers::NONE, Key::F, KeyAction::AdjustRadius),
        KeyBinding::new(Modifiers::NONE, Key::Home, KeyAction::FrameAll),
        KeyBinding::new(Modifiers::NONE, Key::F1, KeyAction::Help),
        KeyBinding::new(Modifiers::NONE, Key::Questionmark, KeyAction::Help),
        KeyBinding::new(Modifiers::NONE, Key::Escape, KeyAction::Cancel),
        KeyBinding::new(Modifiers::SHIFT, Key::X, KeyAction::ToggleRadial),
        KeyBinding::new(Modifiers::NONE, Key::X, KeyAction::ToggleSymmetry),
        KeyBinding::new(Modifiers::NONE, Key::E, KeyAction::CycleSurfaceMode),
        KeyBinding::new(Modifiers::NONE, Key::G, KeyAction::Tool(Tool::Move)),
        KeyBinding::new(Modifiers::NONE, Key::I, KeyAction::Tool(Tool::Inflate)),
        KeyBinding::new(Modifiers::SHIFT, Key::T, KeyAction::Tool(Tool::Flatten)),
        KeyBinding::new(Modifiers::NONE, Key::P, KeyAction::Tool(Tool::Pinch)),
        KeyBinding::new(Modifiers::SHIFT, Key::C, KeyAction::Tool(Tool::Crease)),
    ];
    keys.extend(
        Tool::ALL
            .iter()
            .zip(NUMBER_KEYS)
            .map(|(tool, key)| KeyBinding::new(Modifiers::NONE, key, KeyAction::Tool(*tool))),
    );
    keys
}

/// A key read by where it is on the keyboard (winit's physical key code), not by what it
/// types: what egui cannot tell apart (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PhysicalBinding {
    /// The key's position.
    pub code: winit::keyboard::KeyCode,
    /// The key as written in the help.
    pub label: &'static str,
    /// What it does.
    pub action: KeyAction,
}

/// The keys read by position: numpad 5 toggles the orthographic view (Blender's key), while
/// the main 5 keeps picking its tool.
#[must_use]
pub fn physical_keys() -> Vec<PhysicalBinding> {
    vec![PhysicalBinding {
        code: winit::keyboard::KeyCode::Numpad5,
        label: "Numpad 5",
        action: KeyAction::ToggleProjection,
    }]
}

/// The action of the key at `code`, if it is one of [`physical_keys`].
#[must_use]
pub fn physical_action(code: winit::keyboard::KeyCode) -> Option<KeyAction> {
    physical_keys()
        .into_iter()
        .find(|b| b.code == code)
        .map(|b| b.action)
}

/// The actions of the keys pressed this frame, in the order they were pressed (each press
/// once, matched against the table in order; the matched key events are taken out of the
/// input).
#[must_use]
pub fn pressed(input: &mut egui::InputState) -> Vec<KeyAction> {
    let table = keys();
    let mut actions = Vec::new();
    input.events.retain(|event| {
        if let egui::Event::Key {
            key,
            pressed: true,
            modifiers,
            ..
        } = event
            && let Some(binding) = table
                .iter()
                .find(|b| b.key == *key && modifiers.matches_logically(b.modifiers))
        {
            actions.push(binding.action);
            return false;
        }
        true
    });
    actions
}

/// The mouse bindings under an orbit setting: `(input, what it does)`.
#[must_use]
pub fn mouse(orbit: OrbitButton) -> Vec<(&'static str, &'static str)> {
    let mut rows = vec![
        (
            "Left drag",
            "the active tool (Push / Pull / Draw a line / Move / Smooth / Inflate / Flatten / Pinch / Crease deform live while held)",
        ),
        (
            "Ctrl + Left drag",
            "the tool inverted: Push pulls, Pull pushes, a groove becomes a ridge, Inflate deflates, a crease becomes a ridge",
        ),
        (
            "Shift + Left drag",
            "with Push, Pull or Draw a line: smooth (as the Smooth tool)",
        ),
        (
            "Wheel while pressing",
            "the stroke's depth (Move and the curve grab: nearer / farther)",
        ),
        ("Right click while pressing", "cancel the stroke"),
    ];
    rows.extend(match orbit {
        OrbitButton::Right => [
            ("Right drag", "orbit"),
            ("Middle drag, Shift + Right drag", "pan"),
        ],
        OrbitButton::Middle => [
            ("Middle drag", "orbit"),
            ("Shift + Middle drag, Right drag", "pan"),
        ],
    });
    rows.push(("Wheel", "zoom toward the point under the cursor"));
    rows
}

/// The clutch key: held, a glove's hand (a device session, a replay) moves without touching
/// the clay. Space, free in the key map; held rather than pressed, as the clutch of a 3D
/// mouse or a VR sculpting controller's grip, and as Blender's held keys (Ctrl, Shift) that
/// change what a stroke does while they are down.
pub const CLUTCH_KEY: Key = Key::Space;

/// The keys that act while held: `(keys, what they do)` (the help and the README list them
/// after the shortcuts).
#[must_use]
pub fn held() -> Vec<(&'static str, &'static str)> {
    vec![(
        "Space (held)",
        "the clutch: the glove's hand moves without touching the clay (a fist does the same: index, middle, ring and little finger each bent past 1.3 rad)",
    )]
}

/// Takes the clutch key's events out of the frame's input (the key is read as held, with
/// `key_down`): a button with the keyboard focus would otherwise take Space for a click.
pub fn take_clutch_events(input: &mut egui::InputState) {
    input
        .events
        .retain(|e| !matches!(e, egui::Event::Key { key, .. } if *key == CLUTCH_KEY));
}

/// The keys and the mouse as a Markdown table (the README's, for the default orbit button).
#[must_use]
pub fn markdown(orbit: OrbitButton) -> String {
    let mut s = String::from("| input | does |\n|---|---|\n");
    for (input, does) in mouse(orbit) {
        s.push_str(&format!("| {input} | {does} |\n"));
    }
    let keys = keys();
    let mut seen: Vec<KeyAction> = Vec::new();
    for binding in &keys {
        if seen.contains(&binding.action) {
            continue;
        }
        seen.push(binding.action);
        let all: Vec<String> = keys
            .iter()
            .filter(|k| k.action == binding.action)
            .map(KeyBinding::keys)
            .collect();
        s.push_str(&format!(
            "| {} | {} |\n",
            all.join(", "),
            binding.action.describe()
        ));
    }
    for binding in physical_keys() {
        s.push_str(&format!(
            "| {} | {} |\n",
            binding.label,
            binding.action.describe()
        ));
    }
    for (keys, does) in held() {
        s.push_str(&format!("| {keys} | {does} |\n"));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The README's table is this module's: the help cannot drift from the keys.
    #[test]
    fn the_readme_lists_the_keymap() {
        let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md"))
            .expect("README.md");
        let table = markdown(OrbitButton::Right);
        assert!(
            readme.contains(&table),
            "README.md's \"Using the window\" table must be keymap::markdown's:\n{table}"
        );
    }

    /// No two bindings share a key and modifiers, every tool has a key, and a
    /// shifted binding comes before the same key unshifted (egui matches Shift loosely).
    #[test]
    fn bindings_are_distinct_and_ordered() {
        let keys = keys();
        for (i, a) in keys.iter().enumerate() {
            for b in &keys[i + 1..] {
                assert!(
                    !(a.key == b.key && a.modifiers == b.modifiers),
                    "{} twice",
                    a.keys()
                );
                if a.key == b.key {
                    assert!(
                        !b.modifiers.shift || a.modifiers.shift,
                        "{} after {}",
                        b.keys(),
                        a.keys()
                    );
                }
            }
        }
        for tool in Tool::ALL {
            assert!(keys.iter().any(|k| k.action == KeyAction::Tool(tool)));
        }
        assert!(
            keys.iter().all(|k| k.key != CLUTCH_KEY),
            "the clutch key is held, never a shortcut"
        );
        // Numpad 5 is read by position; the main 5 keeps its tool.
        assert_eq!(
            physical_action(winit::keyboard::KeyCode::Numpad5),
            Some(KeyAction::ToggleProjection)
        );
        assert_eq!(physical_action(winit::keyboard::KeyCode::Digit5), None);
        assert!(
            keys.iter()
                .any(|k| k.key == Key::Num5 && matches!(k.action, KeyAction::Tool(_))),
            "5 picks a tool"
        );
        assert_eq!(
            keys.iter()
                .find(|k| k.action == KeyAction::Redo)
                .map(KeyBinding::keys),
            Some("Ctrl+Shift+Z".to_string())
        );
    }

    /// Keys pressed within one frame all count, in order; Shift+F is the depth, not the radius.
    #[test]
    fn every_key_press_of_a_frame_counts() {
        let ctx = egui::Context::default();
        let press = |key, modifiers| egui::Event::Key {
            key,
            physical_key: None,
            pressed: true,
            repeat: false,
            modifiers,
        };
        let raw = egui::RawInput {
            events: vec![
                press(Key::Num3, Modifiers::NONE),
                press(Key::F, Modifiers::SHIFT),
                press(Key::Z, Modifiers::COMMAND),
                press(Key::Z, Modifiers::COMMAND),
            ],
            ..egui::RawInput::default()
        };
        let mut got = Vec::new();
        let _ = ctx.run_ui(raw, |ui| got = ui.input_mut(pressed));
        assert_eq!(
            got,
            vec![
                KeyAction::Tool(Tool::ALL[2]),
                KeyAction::AdjustDepth,
                KeyAction::Undo,
                KeyAction::Undo,
            ]
        );
    }
}
