//! The window's settings remembered between runs: a small JSON file,
//! `$XDG_CONFIG_HOME/nendo/settings.json` (`~/.config/nendo/settings.json` without
//! `XDG_CONFIG_HOME`), and the user's profile folder beside it (`…/nendo/profiles/`).
//!
//! ```json
//! {"format":"nendo-settings","version":1,"profile":"/home/me/.config/nendo/profiles/mine.json",
//!  "ports":{"mine":{"glove":"/dev/ttyUSB1","tracker":"/dev/ttyUSB0"}},
//!  "record":true,"record_folder":"/home/me/traces","trace_folder":"/home/me/traces",
//!  "orbit":"right","finger_radius":null,"devices_open":true,"pressing":"index,middle",
//!  "matcap":"red-wax",
//!  "fitted":["cyberglove2-18-fastrak","/home/me/.config/nendo/profiles/cyberglove2-18-fastrak-mine.json"],
//!  "brush":{"push":{"radius":1.25,"depth":0.3,"strength":1.0,"falloff":"soft","smooth_strength":0.5,"ridge":false},
//!           "smooth":{"radius":2.0,"depth":0.3,"strength":1.0,"falloff":"finger","smooth_strength":0.8,"ridge":false}}}
//! ```
//!
//! `matcap` is the clay's matcap (`clay`, `red-wax`, `soft-grey`; [`crate::render::matcap`]),
//! `null` or missing for the lit shading (a name not known is the lit shading too).
//!
//! `brush` holds the sculpting tools' panel per tool (`push` for Push and Pull, `line`,
//! `smooth`, `move`, `hand`, `inflate`, `flatten`, `pinch`, `crease`; [`Brushes`]): finger radius, depth, brush strength and falloff
//! (`finger`, `soft`, `flat`; [`crate::surface::brush`]), smoothing strength and ridges. Each
//! tool is restored with its own when picked; a tool not in the file takes the panel as it is.
//! A file from before the per-tool brushes, with one `brush` for every tool
//! (`"brush":{"radius":1.25,…}`), is read as that brush for each of them.
//!
//! Every member is optional (a missing one takes its default); unknown members are ignored,
//! so an older nendo reads a newer file. A file that cannot be parsed (a syntax error, another
//! format) is first kept as `settings.json.bad` (`settings.json.bad.2`, `.3`, … when that is
//! taken), then the defaults are used and written at the next change; the warning names the
//! kept copy. A file that cannot be read, or kept, is never written over: the window then
//! remembers nothing this session. Writes go through the one atomic writer (`nendo_file`).

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::editor::tools::{DEPTH_RANGE, RADIUS_RANGE, STRENGTH_RANGE, Tool, ToolSettings};
use crate::surface::Falloff;

/// The format name the file carries.
pub const SETTINGS_FORMAT: &str = "nendo-settings";

/// The ports chosen for one profile's devices.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct DevicePorts {
    /// The glove's serial port.
    pub glove: Option<String>,
    /// The tracker's serial port, or a skeleton source's listening address (a VMC
    /// receiver's `ADDR:PORT`).
    pub tracker: Option<String>,
}

/// The remembered settings (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Always [`SETTINGS_FORMAT`].
    pub format: String,
    /// 1.
    pub version: u32,
    /// The profile last selected: a shipped profile's name or a profile file's path.
    pub profile: Option<String>,
    /// Ports per profile (keyed like `profile`).
    pub ports: BTreeMap<String, DevicePorts>,
    /// Record a trace of every device session.
    pub record: bool,
    /// Where recordings go.
    pub record_folder: Option<PathBuf>,
    /// Where the last replayed trace was.
    pub trace_folder: Option<PathBuf>,
    /// The mouse button that orbits: `right` or `middle`.
    pub orbit: Option<String>,
    /// The finger radius of device hands, when set by hand (`None`: it follows the hand).
    pub finger_radius: Option<f64>,
    /// The Devices panel is shown.
    pub devices_open: bool,
    /// The parts of the hand that press in device sessions, as `--finger` writes them
    /// (`all`, `index,middle`, `thumb,index,palm`, …); `None`: every finger.
    pub pressing: Option<String>,
    /// The profiles (keyed like `profile`) whose hand has been fitted to the model: their
    /// next connects keep the profile's scale instead of fitting it again.
    pub fitted: Vec<String>,
    /// The clay's matcap by name (`None`: the lit shading).
    pub matcap: Option<String>,
    /// The sculpting tools' brushes, per tool (a file without them gives the defaults).
    pub brush: Brushes,
}

/// The brush of each sculpting tool, keyed by [`Brushes::key`] (see the module docs).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(from = "BrushesDoc", into = "BTreeMap<String, BrushSettings>")]
pub struct Brushes {
    /// Per tool key.
    pub tools: BTreeMap<String, BrushSettings>,
}

/// How `brush` reads: per tool, or (older files) one brush for every tool.
#[derive(Deserialize)]
#[serde(untagged)]
enum BrushesDoc {
    PerTool(BTreeMap<String, BrushSettings>),
    Single(BrushSettings),
}

impl From<BrushesDoc> for Brushes {
    fn from(doc: BrushesDoc) -> Self {
        match doc {
            BrushesDoc::PerTool(tools) => Brushes { tools },
            BrushesDoc::Single(one) => Brushes {
                tools: Brushes::KEYS
                    .iter()
                    .map(|k| ((*k).to_string(), one.clone()))
                    .collect(),
            },
        }
    }
}

impl From<Brushes> for BTreeMap<String, BrushSettings> {
    fn from(b: Brushes) -> Self {
        b.tools
    }
}

impl Brushes {
    /// Every tool key.
    pub const KEYS: [&'static str; 9] = [
        "push", "line", "smooth", "move", "hand", "inflate", "flatten", "pinch", "crease",
    ];

    /// The key `tool`'s brush is kept under (`None`: a curve tool, which has no brush).
    #[must_use]
    pub fn key(tool: Tool) -> Option<&'static str> {
        match tool {
            Tool::Push | Tool::Pull => Some("push"),
            Tool::DrawLine => Some("line"),
            Tool::Smooth => Some("smooth"),
            Tool::Move => Some("move"),
            Tool::Hand => Some("hand"),
            Tool::Inflate => Some("inflate"),
            Tool::Flatten => Some("flatten"),
            Tool::Pinch => Some("pinch"),
            Tool::Crease => Some("crease"),
            Tool::GrabCurve | Tool::SplitCurve | Tool::Tangent => None,
        }
    }

    /// Keeps the panel's brush `t` as `tool`'s.
    pub fn store(&mut self, tool: Tool, t: &ToolSettings) {
        if let Some(k) = Self::key(tool) {
            self.tools
                .insert(k.to_string(), BrushSettings::from_tools(t));
        }
    }

    /// Sets the panel's brush `t` to `tool`'s, when it has one remembered.
    pub fn restore(&self, tool: Tool, t: &mut ToolSettings) {
        if let Some(b) = Self::key(tool).and_then(|k| self.tools.get(k)) {
            b.apply_to(t);
        }
    }
}

/// The brush settings of the sculpting tools (see the module docs; every member optional).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BrushSettings {
    /// The finger radius (side).
    pub radius: f64,
    /// The depth of a click and of a drawn line (side).
    pub depth: f64,
    /// The fraction of the depth push, pull and draw a line press.
    pub strength: f64,
    /// The falloff's name (`finger`, `soft`, `flat`).
    pub falloff: String,
    /// The smoothing strength.
    pub smooth_strength: f64,
    /// Draw ridges instead of grooves.
    pub ridge: bool,
}

impl Default for BrushSettings {
    fn default() -> Self {
        BrushSettings::from_tools(&ToolSettings::default())
    }
}

impl BrushSettings {
    /// The brush members of the tools' settings.
    #[must_use]
    pub fn from_tools(t: &ToolSettings) -> Self {
        BrushSettings {
            radius: t.radius,
            depth: t.depth,
            strength: t.press_strength,
            falloff: t.falloff.name().to_string(),
            smooth_strength: t.strength,
            ridge: t.ridge,
        }
    }

    /// Sets the tools' brush members from these, each clamped into the panel's range (a
    /// number that is not finite or a falloff not known keeps the tool's value).
    pub fn apply_to(&self, t: &mut ToolSettings) {
        let set = |x: f64, range: &std::ops::RangeInclusive<f64>, into: &mut f64| {
            if x.is_finite() {
                *into = x.clamp(*range.start(), *range.end());
            }
        };
        set(self.radius, &RADIUS_RANGE, &mut t.radius);
        set(self.depth, &DEPTH_RANGE, &mut t.depth);
        set(self.strength, &STRENGTH_RANGE, &mut t.press_strength);
        set(self.smooth_strength, &STRENGTH_RANGE, &mut t.strength);
        if let Some(f) = Falloff::from_name(&self.falloff) {
            t.falloff = f;
        }
        t.ridge = self.ridge;
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            format: SETTINGS_FORMAT.into(),
            version: 1,
            profile: None,
            ports: BTreeMap::new(),
            record: false,
            record_folder: None,
            trace_folder: None,
            orbit: None,
            finger_radius: None,
            devices_open: false,
            pressing: None,
            fitted: Vec::new(),
            matcap: None,
            brush: Brushes::default(),
        }
    }
}

/// Why the settings could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write the settings {}: {reason}", path.display())]
pub struct SettingsError {
    path: PathBuf,
    reason: String,
}

/// `$XDG_CONFIG_HOME/nendo` (or `~/.config/nendo`), if either variable is set.
#[must_use]
pub fn config_dir() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .filter(|p| p.is_absolute())
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
    Some(base.join("nendo"))
}

/// The settings file's default path.
#[must_use]
pub fn default_path() -> Option<PathBuf> {
    config_dir().map(|d| d.join("settings.json"))
}

/// The user's profile folder.
#[must_use]
pub fn profile_dir() -> Option<PathBuf> {
    config_dir().map(|d| d.join("profiles"))
}

/// The settings as read by [`Settings::load_keeping`].
#[derive(Debug, Clone, PartialEq)]
pub struct SettingsLoad {
    /// The settings (the defaults when the file was unusable).
    pub settings: Settings,
    /// What was wrong with the file, and where it was kept.
    pub warning: Option<String>,
    /// The file may be written: it was missing, read, or kept aside.
    pub writable: bool,
}

/// The first of `PATH.bad`, `PATH.bad.2`, `PATH.bad.3`, … that does not exist.
fn free_bad_path(path: &Path) -> Option<PathBuf> {
    let mut name = path.file_name()?.to_os_string();
    name.push(".bad");
    let first = path.with_file_name(&name);
    std::iter::once(first)
        .chain((2..1000).map(|k| {
            let mut n = name.clone();
            n.push(format!(".{k}"));
            path.with_file_name(n)
        }))
        .find(|p| std::fs::symlink_metadata(p).is_err())
}

/// Largest settings file read: 4 MB (the remembered settings are a few kB).
pub const MAX_SETTINGS_BYTES: u64 = 4 << 20;

impl Settings {
    /// Reads `path` as [`Settings::load`] does, first keeping an unusable file as
    /// `PATH.bad` (see the module docs).
    #[must_use]
    pub fn load_keeping(path: &Path) -> SettingsLoad {
        let (settings, warning) = Self::load(path);
        let Some(warning) = warning else {
            return SettingsLoad {
                settings,
                warning: None,
                writable: true,
            };
        };
        // Read but unusable: keep it aside before anything is written there.
        let readable = std::fs::File::open(path)
            .and_then(|mut f| std::io::Read::read(&mut f, &mut [0u8; 1]))
            .is_ok();
        if !readable {
            return SettingsLoad {
                settings,
                warning: Some(format!("{warning}; it is not written this session")),
                writable: false,
            };
        }
        let kept = free_bad_path(path)
            .ok_or_else(|| "no free name".to_string())
            .and_then(|bad| {
                std::fs::rename(path, &bad)
                    .map(|()| bad)
                    .map_err(|e| e.to_string())
            });
        match kept {
            Ok(bad) => SettingsLoad {
                settings,
                warning: Some(format!("{warning}; the file is kept as {}", bad.display())),
                writable: true,
            },
            Err(e) => SettingsLoad {
                settings,
                warning: Some(format!(
                    "{warning}; it could not be kept aside ({e}), so it is not written this session"
                )),
                writable: false,
            },
        }
    }

    /// Reads `path`: the settings and, when the file was there but unusable, a warning (the
    /// defaults are returned then). A missing file is no warning. Nothing is moved (see
    /// [`Settings::load_keeping`]).
    #[must_use]
    pub fn load(path: &Path) -> (Settings, Option<String>) {
        // At most `MAX_SETTINGS_BYTES` is read: a runaway file is unusable, not a hang.
        let text = match nendo_file::read_text_limited(path, MAX_SETTINGS_BYTES, "settings file") {
            Ok(t) => t,
            Err(nendo_file::ReadError::Io { error, .. })
                if error.kind() == std::io::ErrorKind::NotFound =>
            {
                return (Settings::default(), None);
            }
            Err(e) => {
                return (
                    Settings::default(),
                    Some(format!("settings {e}; using the defaults")),
                );
            }
        };
        match serde_json::from_str::<Settings>(&text) {
            Ok(s) if s.format == SETTINGS_FORMAT => (s, None),
            Ok(s) => (
                Settings::default(),
                Some(format!(
                    "settings {}: format {:?} is not {SETTINGS_FORMAT:?}; using the defaults",
                    path.display(),
                    s.format
                )),
            ),
            Err(e) => (
                Settings::default(),
                Some(format!(
                    "settings {}: {e}; using the defaults",
                    path.display()
                )),
            ),
        }
    }

    /// Writes the settings to `path` atomically, creating its folder.
    ///
    /// # Errors
    /// [`SettingsError`] when the folder or the file cannot be written.
    pub fn save(&self, path: &Path) -> Result<(), SettingsError> {
        let fail = |reason: String| SettingsError {
            path: path.to_path_buf(),
            reason,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| fail(e.to_string()))?;
        }
        let mut text = serde_json::to_string_pretty(self).map_err(|e| fail(e.to_string()))?;
        text.push('\n');
        nendo_file::write_bytes(path, text.as_bytes()).map_err(|e| fail(e.reason()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("nendo-settings-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn settings_round_trip_and_a_missing_file_is_the_defaults() {
        let dir = temp("round");
        let path = dir.join("nendo").join("settings.json");
        assert_eq!(Settings::load(&path), (Settings::default(), None));
        let mut s = Settings {
            profile: Some("/p/mine.json".into()),
            record: true,
            record_folder: Some("/traces".into()),
            orbit: Some("middle".into()),
            finger_radius: Some(0.5),
            devices_open: true,
            pressing: Some("index,middle,palm".into()),
            fitted: vec!["cyberglove2-18-fastrak".into()],
            matcap: Some("red-wax".into()),
            ..Settings::default()
        };
        s.ports.insert(
            "/p/mine.json".into(),
            DevicePorts {
                glove: Some("/dev/ttyUSB1".into()),
                tracker: None,
            },
        );
        s.save(&path).expect("saved");
        assert_eq!(Settings::load(&path), (s, None));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_corrupt_file_warns_and_gives_the_defaults() {
        let dir = temp("corrupt");
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("settings.json");
        for text in [
            "{\"profile\": 3",
            "[1,2]",
            "{\"format\":\"other\"}",
            "\u{0}",
        ] {
            std::fs::write(&path, text).expect("written");
            let (s, warning) = Settings::load(&path);
            assert_eq!(s, Settings::default(), "{text:?}");
            let warning = warning.expect("a warning");
            assert!(warning.contains("using the defaults"), "{warning}");
        }
        // Unknown members and missing ones are fine.
        std::fs::write(
            &path,
            r#"{"format":"nendo-settings","later":1,"record":true}"#,
        )
        .expect("written");
        let (s, warning) = Settings::load(&path);
        assert!(warning.is_none() && s.record);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A file with a syntax error is kept as `.bad` (then `.bad.2`) before anything is
    /// written over it; the warning names the copy.
    #[test]
    fn a_corrupt_file_is_kept_as_bad_before_the_defaults() {
        let dir = temp("keep");
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("settings.json");
        let broken =
            "{\"format\":\"nendo-settings\",\"profile\":\"/p/mine.json\",\"record\":true,}";
        std::fs::write(&path, broken).expect("written");
        let loaded = Settings::load_keeping(&path);
        assert_eq!(loaded.settings, Settings::default());
        assert!(loaded.writable);
        let bad = dir.join("settings.json.bad");
        let warning = loaded.warning.expect("a warning");
        assert!(warning.contains(&bad.display().to_string()), "{warning}");
        assert_eq!(std::fs::read_to_string(&bad).expect("kept"), broken);
        assert!(!path.exists(), "moved aside");
        Settings::default().save(&path).expect("defaults written");
        std::fs::write(&path, "[").expect("written");
        let again = Settings::load_keeping(&path);
        assert!(again.writable);
        assert_eq!(std::fs::read_to_string(&bad).expect("first kept"), broken);
        assert_eq!(
            std::fs::read_to_string(dir.join("settings.json.bad.2")).expect("second kept"),
            "["
        );
        // A good file and a missing one move nothing.
        assert_eq!(Settings::load_keeping(&path).warning, None);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
