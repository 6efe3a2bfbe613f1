//! The profiles the Devices panel lists — shipped ones, the user's profile folder, files
//! opened — the one selected, the ports chosen per profile and remembered in the settings, and
//! the panel's file dialogs.

use std::path::{Path, PathBuf};

use nendo_devices::profile::{Input, MouseProfile};
use nendo_devices::{DeviceError, Profile, profile};

use crate::editor::command::DialogPurpose;
use crate::editor::settings::{DevicePorts, Settings};

use super::*;

/// Where a listed profile comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum ProfileSource {
    /// Shipped with nendo (read-only: changes go to a user copy).
    Builtin,
    /// A profile file (the user's folder, or opened).
    File(PathBuf),
}

/// A profile in the panel's list.
#[derive(Debug, Clone)]
pub(crate) struct ProfileEntry {
    pub(crate) profile: Profile,
    pub(crate) source: ProfileSource,
}

impl ProfileEntry {
    /// How settings name it: a shipped profile's name, or the file's path.
    pub(crate) fn key(&self) -> String {
        match &self.source {
            ProfileSource::Builtin => self.profile.name.clone(),
            ProfileSource::File(p) => p.display().to_string(),
        }
    }

    /// How the picker lists it.
    pub(crate) fn label(&self) -> String {
        match &self.source {
            ProfileSource::Builtin => format!("{} (built-in)", self.profile.name),
            ProfileSource::File(p) => format!(
                "{} ({})",
                self.profile.name,
                p.file_name()
                    .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
            ),
        }
    }
}

impl LiveInput {
    /// A panel listing the shipped profiles and those in `profile_dir` (the user's folder,
    /// where user copies of changed shipped profiles go), writing its status file when the
    /// environment asks ([`STATUS_FILE_ENV`]).
    #[must_use]
    pub fn with_profile_dir(profile_dir: Option<PathBuf>) -> Self {
        let mut live = LiveInput {
            profile_dir,
            status_file: std::env::var_os(STATUS_FILE_ENV).map(PathBuf::from),
            ..LiveInput::default()
        };
        live.rescan();
        live
    }

    /// Lists the shipped profiles, the user's folder and the files opened before (kept).
    pub(crate) fn rescan(&mut self) {
        let key = self.entries.get(self.selected).map(ProfileEntry::key);
        let opened: Vec<ProfileEntry> = self
            .entries
            .iter()
            .filter(|e| match &e.source {
                ProfileSource::File(p) => self
                    .profile_dir
                    .as_deref()
                    .is_none_or(|d| p.parent() != Some(d)),
                ProfileSource::Builtin => false,
            })
            .cloned()
            .collect();
        let mut entries: Vec<ProfileEntry> = profile::builtin()
            .into_iter()
            .map(|profile| ProfileEntry {
                profile,
                source: ProfileSource::Builtin,
            })
            .collect();
        let mut problems = Vec::new();
        if let Some(dir) = &self.profile_dir
            && let Ok(read) = std::fs::read_dir(dir)
        {
            let mut files: Vec<PathBuf> = read
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|e| e == "json"))
                .collect();
            files.sort();
            for path in files {
                match Profile::load(&path) {
                    Ok(profile) => entries.push(ProfileEntry {
                        profile,
                        source: ProfileSource::File(path),
                    }),
                    Err(e) => problems.push(e.to_string()),
                }
            }
        }
        entries.extend(opened);
        self.entries = entries;
        if !problems.is_empty() {
            self.message = Some(problems.join("; "));
        }
        let found = key.and_then(|k| self.entries.iter().position(|e| e.key() == k));
        self.select(found.unwrap_or(self.selected.min(self.entries.len().saturating_sub(1))));
    }

    /// Selects an entry (keeping the ports typed for the one selected before); its ports are
    /// the remembered ones, or the profile's own.
    pub(crate) fn select(&mut self, index: usize) {
        self.remember_ports();
        self.show_entry(index);
    }

    /// Selects an entry with its remembered ports, or the profile's own.
    pub(super) fn show_entry(&mut self, index: usize) {
        self.selected = index;
        let Some(entry) = self.entries.get(index) else {
            return;
        };
        let remembered = self.ports.get(&entry.key()).cloned().unwrap_or_default();
        self.glove_port = remembered
            .glove
            .or_else(|| {
                entry
                    .profile
                    .glove()
                    .and_then(|g| g.port())
                    .map(String::from)
            })
            .unwrap_or_default();
        self.tracker_port = remembered
            .tracker
            .or_else(|| own_tracker(&entry.profile).map(String::from))
            .unwrap_or_default();
        self.hand_edit = None;
    }

    /// Keeps the selected profile's ports, when they differ from the profile's own.
    pub(super) fn remember_ports(&mut self) {
        if let Some(entry) = self.entries.get(self.selected) {
            note_ports(&mut self.ports, entry, &self.glove_port, &self.tracker_port);
        }
    }

    /// Adds (or finds) a profile file in the list and selects it.
    pub(crate) fn open_profile_file(&mut self, path: &Path) -> Result<(), DeviceError> {
        let profile = Profile::load(path)?;
        let path = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        let source = ProfileSource::File(path);
        let index = match self.entries.iter().position(|e| e.source == source) {
            Some(k) => {
                self.entries[k].profile = profile;
                k
            }
            None => {
                self.entries.push(ProfileEntry { profile, source });
                self.entries.len() - 1
            }
        };
        self.select(index);
        Ok(())
    }

    /// Selects a profile by shipped name or file path (`nendo --profile`), with the profile's
    /// own ports (not remembered ones).
    ///
    /// # Errors
    /// When it is neither a shipped profile nor a readable profile file.
    pub fn select_profile(&mut self, name_or_path: &str) -> Result<(), DeviceError> {
        if profile::is_builtin(name_or_path) {
            let k = self
                .entries
                .iter()
                .position(|e| e.source == ProfileSource::Builtin && e.profile.name == name_or_path);
            if let Some(k) = k {
                self.ports.remove(name_or_path);
                self.select(k);
                return Ok(());
            }
        }
        // Through `resolve` for its error message on a name that is neither.
        profile::resolve(name_or_path)?;
        let path = Path::new(name_or_path);
        let key = path
            .canonicalize()
            .unwrap_or_else(|_| path.to_path_buf())
            .display()
            .to_string();
        self.ports.remove(&key);
        self.open_profile_file(path)
    }

    /// The remembered part of the panel, into `settings`.
    pub fn store_settings(&self, settings: &mut Settings) {
        let mut ports = self.ports.clone();
        if let Some(entry) = self.entries.get(self.selected) {
            note_ports(&mut ports, entry, &self.glove_port, &self.tracker_port);
            settings.profile = Some(entry.key());
        }
        settings.ports = ports;
        settings.record = self.record;
        settings.record_folder = Path::new(self.record_to.trim())
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf);
        settings.trace_folder = Path::new(self.trace_path.trim())
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf);
        settings.finger_radius = self.radius_set;
        self.store_desk(settings);
    }

    /// Takes the remembered settings (before the first frame).
    pub fn apply_settings(&mut self, settings: &Settings) {
        self.ports = settings.ports.clone();
        self.record = settings.record;
        if let Some(dir) = &settings.record_folder {
            self.record_to = dir.join("session.trace").display().to_string();
        }
        if let Some(dir) = &settings.trace_folder {
            self.trace_path = dir.display().to_string();
        }
        self.radius_set = settings.finger_radius.filter(|r| r.is_finite() && *r > 0.0);
        self.apply_desk(settings);
        let wanted = settings.profile.as_deref();
        let found = wanted.and_then(|k| self.entries.iter().position(|e| e.key() == k));
        // The ports shown so far are the defaults, not the user's: nothing to keep.
        match (found, wanted) {
            (Some(k), _) => self.show_entry(k),
            (None, Some(path)) if Path::new(path).is_file() => {
                self.show_entry(self.selected);
                if let Err(e) = self.open_profile_file(Path::new(path)) {
                    self.message = Some(format!("the remembered profile: {e}"));
                }
            }
            _ => self.show_entry(self.selected),
        }
    }

    /// The selected profile, with the ports of the panel.
    #[must_use]
    pub(crate) fn selected_profile(&self) -> Option<Profile> {
        let mut p = self.entries.get(self.selected)?.profile.clone();
        if let Some(g) = p.glove_mut()
            && !self.glove_port.trim().is_empty()
        {
            g.set_port(self.glove_port.trim());
        }
        if let Some(t) = p.tracker_mut()
            && !self.tracker_port.trim().is_empty()
        {
            t.set_port(self.tracker_port.trim());
        }
        if let Input::Skeleton(s) = &mut p.input
            && !self.tracker_port.trim().is_empty()
        {
            s.set_listen(self.tracker_port.trim());
        }
        Some(p)
    }

    /// What is wrong with the VMC listening address typed for the selected skeleton profile
    /// (`ADDR:PORT`, an IP address), if anything; `None` for other profiles or a good one.
    #[must_use]
    pub fn listen_error(&self) -> Option<String> {
        let entry = self.entries.get(self.selected)?;
        if !matches!(entry.profile.input, Input::Skeleton(_)) {
            return None;
        }
        let typed = self.tracker_port.trim();
        if typed.is_empty() {
            return None;
        }
        nendo_devices::vmc::parse_listen(typed)
            .err()
            .map(|e| e.to_string())
    }

    /// The selected profile's mouse settings, when it is the mouse (driven by the window's
    /// Hand tool rather than opened as a stream).
    pub(crate) fn selected_mouse(&self) -> Option<MouseProfile> {
        match self.entries.get(self.selected)?.profile.input {
            Input::Mouse(m) => Some(m),
            _ => None,
        }
    }

    /// Where a file dialog for the panel's purposes opens: the file it starts beside (when its
    /// folder exists) and the name it offers; `None` for a purpose not the panel's.
    #[must_use]
    pub fn dialog_start(&self, purpose: DialogPurpose) -> Option<(Option<PathBuf>, &'static str)> {
        let (current, default) = match purpose {
            DialogPurpose::OpenProfile => (
                self.entries
                    .get(self.selected)
                    .and_then(|e| match &e.source {
                        ProfileSource::File(p) => Some(p.clone()),
                        ProfileSource::Builtin => None,
                    })
                    .or_else(|| self.profile_dir.as_ref().map(|d| d.join("profile.json"))),
                "profile.json",
            ),
            DialogPurpose::RecordTrace => (
                Some(PathBuf::from(self.record_to.trim())).filter(|p| !p.as_os_str().is_empty()),
                "session.trace",
            ),
            DialogPurpose::ReplayTrace => {
                let t = PathBuf::from(self.trace_path.trim());
                let inside = if t.is_dir() { t.join("x.trace") } else { t };
                (Some(inside).filter(|p| !p.as_os_str().is_empty()), "")
            }
            _ => return None,
        };
        let current = current.filter(|p| p.parent().is_some_and(Path::is_dir));
        Some((current, default))
    }

    /// A file dialog of the panel picked `path`.
    pub fn dialog_chosen(&mut self, purpose: DialogPurpose, path: &Path) {
        match purpose {
            DialogPurpose::OpenProfile => {
                if let Err(e) = self.open_profile_file(path) {
                    self.message = Some(e.to_string());
                }
            }
            DialogPurpose::RecordTrace => {
                let mut path = path.to_path_buf();
                if path.extension().is_none() {
                    path.set_extension("trace");
                }
                self.record_to = path.display().to_string();
                self.record = true;
            }
            DialogPurpose::ReplayTrace => self.trace_path = path.display().to_string(),
            _ => {}
        }
    }
}

/// Notes in `ports` the ports typed for `entry`, where they differ from the profile's own
/// (none noted: the entry is dropped).
pub(super) fn note_ports(
    ports: &mut std::collections::BTreeMap<String, DevicePorts>,
    entry: &ProfileEntry,
    glove: &str,
    tracker: &str,
) {
    let own_glove = entry.profile.glove().and_then(|g| g.port());
    let own_tracker = own_tracker(&entry.profile);
    let differs = |typed: &str, own: Option<&str>| {
        let typed = typed.trim();
        (!typed.is_empty() && Some(typed) != own).then(|| typed.to_string())
    };
    let noted = DevicePorts {
        glove: differs(glove, own_glove),
        tracker: differs(tracker, own_tracker),
    };
    if noted == DevicePorts::default() {
        ports.remove(&entry.key());
    } else {
        ports.insert(entry.key(), noted);
    }
}

/// A profile's own tracker slot: its tracker's serial port, or its skeleton source's
/// listening address (a VMC receiver's `ADDR:PORT`) — what the panel's tracker field edits.
pub(super) fn own_tracker(profile: &Profile) -> Option<&str> {
    match &profile.input {
        Input::Skeleton(s) => Some(s.listen()),
        _ => profile.tracker().map(|t| t.port()),
    }
}
