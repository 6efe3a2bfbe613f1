//! `nendo emulate`: a device emulator on a pseudo-terminal, for trying glove mode without
//! hardware (and for CI).
//!
//! ```text
//! nendo emulate fastrak --motion press            # prints the port path, then streams
//! nendo record --profile fastrak --port /tmp/nendo-emulator-…/tty --out t.trace
//! ```
//!
//! Runs one of `nendo_devices::emulator`'s byte-exact device models (Fastrak, CyberGlove,
//! Flock of Birds, 5DT Data Glove 5) on a new pty, prints the path to open on the first line
//! of standard output (flushed at once), and answers the host's handshake and streams records
//! like the real device. The hand moves through a named [`Gesture`] over the default plane,
//! looped: tracker poses through the profile's tracker-to-world transform (so the fingertip
//! does the gesture over the model the host's profile shows), glove sensors as the raw values
//! the profile's calibration reads back as the gesture's angles. It ends after `--seconds`, or
//! on SIGINT / SIGTERM / SIGHUP (the binary's one handler, deferred while it runs), removing
//! the pty's link.
//!
//! With `--link PATH` the first line is PATH, a symbolic link to the pty's own link, so a
//! profile can name a fixed port and a restarted emulator is the device plugged back in.
//! Only an emulator's own link is ever replaced there: a symbolic link whose target is a pty
//! link an emulator made, `TMPDIR/nendo-emulator-PID-N/tty`, with no nendo process `PID`
//! alive (`/proc/PID/comm` absent or another program's: the emulator was killed). Anything else at PATH — a file, a
//! directory, the user's own symbolic link, or the link of an emulator still running — is
//! refused, and left as it was.
//!
//! Limits: serial devices only — the 5DT Data Glove Ultra is USB HID, and emulating it needs a
//! virtual HID device (`/dev/uhid`, root), which nendo does not create; one pty per process
//! (run one emulator per device: a tracker and a glove are two processes); the Flock's
//! positions are kept within its scale, so a gesture beyond it is clipped.

use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{Args as ClapArgs, ValueEnum};
use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{
    CyberGloveModel, DeviceModel, FastrakModel, FlockModel, Glove5Model, PtyEmulator, Script,
};
use nendo_devices::fastrak::DataFormat;
use nendo_devices::profile::{self, GloveProfile, SensorCalibration, TrackerProfile};
use nendo_devices::{HandFrame, Profile, TrackerPose, buttons};

use crate::hand::script::Gesture;

/// The longest emulation `--seconds` accepts: a day.
const MAX_SECONDS: f64 = 86_400.0;

/// The rate the gestures are scripted at; each device samples them at its own period.
pub const GESTURE_RATE_HZ: f64 = 240.0;

/// The devices `nendo emulate` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EmulatedDevice {
    /// Polhemus Fastrak (tracker; profile `fastrak`).
    Fastrak,
    /// CyberGlove II (glove; profile `cyberglove2-18`, or `cyberglove2-22` with `--format 22`).
    Cyberglove,
    /// Ascension Flock of Birds, one bird (tracker; profile `flock`).
    Flock,
    /// 5DT Data Glove 5, serial (glove; profile `5dt-glove5-serial`).
    #[value(name = "5dt-glove5")]
    FiveDtGlove5,
    /// A VMC performer: the hand's bones as OSC bundles over UDP to `--to` (profile `vmc`;
    /// see `super::emulate_vmc`).
    Vmc,
}

/// Arguments of `nendo emulate`.
#[derive(Debug, ClapArgs)]
pub struct EmulateArgs {
    /// The device to emulate.
    pub device: EmulatedDevice,
    /// The device's variant: fastrak `ascii` (default) or `binary` (its power-on record
    /// format; the host may switch it); cyberglove `18` (default) or `22` sensors; flock its
    /// scale in inches, `36` (default), `72` or `144`.
    #[arg(long)]
    pub format: Option<String>,
    /// Stop after this many seconds (default: run until SIGINT / SIGTERM).
    #[arg(long, allow_hyphen_values = true)]
    pub seconds: Option<f64>,
    /// Flip one bit in each streamed record with this probability (0 to 1; fixed seed).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub corrupt: f64,
    /// The hand's gesture, looped: press, wave or pinch.
    #[arg(long, default_value = "press", value_parser = parse_motion)]
    pub motion: Gesture,
    /// The profile whose calibration and tracker-to-world transform the gesture is encoded
    /// with (default: the device's shipped profile); give the host the same one.
    #[arg(long)]
    pub profile: Option<String>,
    /// Also make PATH a symbolic link to the port (replacing a link left there, never a file),
    /// removed again at the end: a host profile can name a fixed path, and an emulator started
    /// again with the same `--link` is the same device plugged back in. The first line printed
    /// is then PATH.
    #[arg(long, value_name = "PATH")]
    pub link: Option<std::path::PathBuf>,
    /// Where `vmc` sends its bundles (default 127.0.0.1:39539, the `vmc` profile's).
    #[arg(long, value_name = "ADDR:PORT")]
    pub to: Option<String>,
}

/// A symbolic link `--link` made to the emulator's port; removed on drop if it still points
/// there.
struct UserLink {
    path: std::path::PathBuf,
    target: String,
}

impl UserLink {
    /// Points `path` at `target`: a new link, or in place of a stale link of a killed
    /// emulator ([`emulator_link_owner`], its process gone); anything else at `path` is refused.
    fn make(path: &std::path::Path, target: &str) -> anyhow::Result<UserLink> {
        if let Ok(meta) = std::fs::symlink_metadata(path) {
            if !meta.file_type().is_symlink() {
                anyhow::bail!(
                    "--link {}: something other than a symbolic link is there; not replacing it",
                    path.display()
                );
            }
            let to = std::fs::read_link(path).unwrap_or_default();
            match emulator_link_owner(&to) {
                None => anyhow::bail!(
                    "--link {}: a symbolic link to {} is there, not one an emulator made; not replacing it (remove it, or give another path)",
                    path.display(),
                    to.display()
                ),
                Some(pid) if emulator_alive(pid) => {
                    anyhow::bail!(
                        "--link {}: the link of an emulator still running (process {pid}); not replacing it",
                        path.display()
                    )
                }
                Some(_) => {}
            }
        }
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(format!(".new-{}", std::process::id()));
        let tmp = std::path::PathBuf::from(tmp);
        let _ = std::fs::remove_file(&tmp);
        std::os::unix::fs::symlink(target, &tmp)
            .and_then(|()| std::fs::rename(&tmp, path))
            .map_err(|e| anyhow::anyhow!("--link {}: {e}", path.display()))?;
        Ok(UserLink {
            path: path.to_path_buf(),
            target: target.to_string(),
        })
    }
}

/// The process id of the emulator that made the pty link `target` points at:
/// `TMPDIR/nendo-emulator-PID-N/tty` (the directory's name is what identifies it, wherever the
/// temporary directory was), or `None` for any other target.
fn emulator_link_owner(target: &std::path::Path) -> Option<u32> {
    if target.file_name()? != "tty" {
        return None;
    }
    let dir = target.parent()?.file_name()?.to_str()?;
    let (pid, n) = dir.strip_prefix("nendo-emulator-")?.split_once('-')?;
    n.parse::<u64>().ok()?;
    pid.parse().ok()
}

/// Whether process `pid` is alive and a nendo (`/proc/PID/comm`): a killed emulator's id
/// reused by another program does not keep its stale link.
fn emulator_alive(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/comm"))
        .is_ok_and(|c| c.trim().starts_with("nendo"))
}

impl Drop for UserLink {
    fn drop(&mut self) {
        // Only our own link: another emulator may have taken the path over since.
        if std::fs::read_link(&self.path)
            .is_ok_and(|t| t.as_os_str() == std::ffi::OsStr::new(&self.target))
        {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

fn parse_motion(s: &str) -> Result<Gesture, String> {
    Gesture::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Gesture::ALL.iter().map(|g| g.name()).collect();
        format!("unknown motion {s:?}: expected {}", names.join(", "))
    })
}

/// Runs `nendo emulate`.
pub fn run(args: EmulateArgs) -> ExitCode {
    match emulate(&args) {
        Ok(summary) => {
            eprintln!("nendo emulate: {summary}");
            ExitCode::SUCCESS
        }
        Err(e) => super::output::failed("nendo emulate", &e),
    }
}

/// The gesture sampled at record `k` of a device with this period.
pub fn frame_at(frames: &[HandFrame], period: Duration, k: u64) -> &HandFrame {
    let i = (k as f64 * period.as_secs_f64() * GESTURE_RATE_HZ).round() as u64;
    // `frames` is never empty (checked by the caller).
    &frames[(i % frames.len() as u64) as usize]
}

/// The raw sensor values a calibration table reads back as the frame's angles
/// (`raw = offset + angle / gain`, rounded into `lo..=255`); a sensor without a joint, or
/// a joint the frame lacks, reads its offset.
pub fn raw_values(table: &[SensorCalibration], frame: &HandFrame, lo: u8) -> Vec<u8> {
    table
        .iter()
        .map(|c| {
            let angle = c
                .joint
                .and_then(|j| frame.joints.as_ref().and_then(|a| a.get(j)))
                .unwrap_or(0.0);
            let raw = if c.gain != 0.0 {
                c.offset + angle / c.gain
            } else {
                c.offset
            };
            raw.round().clamp(f64::from(lo), 255.0) as u8
        })
        .collect()
}

fn default_profile(device: EmulatedDevice, format: Option<&str>) -> &'static str {
    match device {
        EmulatedDevice::Fastrak => "fastrak",
        EmulatedDevice::Cyberglove if format == Some("22") => "cyberglove2-22",
        EmulatedDevice::Cyberglove => "cyberglove2-18",
        EmulatedDevice::Flock => "flock",
        EmulatedDevice::FiveDtGlove5 => "5dt-glove5-serial",
        EmulatedDevice::Vmc => "vmc",
    }
}

/// Checks that `profile` has the emulated device: its tracker for a tracker, its glove for a
/// glove, of the same protocol. Otherwise the host told to "connect with --profile P" would
/// open a profile without that device (or read it with another protocol).
fn check_profile_device(profile: &Profile, device: EmulatedDevice) -> anyhow::Result<()> {
    let (fits, what) = match device {
        EmulatedDevice::Fastrak => (
            matches!(profile.tracker(), Some(TrackerProfile::Fastrak { .. })),
            "a Fastrak tracker",
        ),
        EmulatedDevice::Flock => (
            matches!(profile.tracker(), Some(TrackerProfile::Flock { .. })),
            "a Flock of Birds tracker",
        ),
        EmulatedDevice::Cyberglove => (
            matches!(profile.glove(), Some(GloveProfile::CyberGlove { .. })),
            "a CyberGlove",
        ),
        EmulatedDevice::FiveDtGlove5 => (
            matches!(profile.glove(), Some(GloveProfile::FiveDtGlove5 { .. })),
            "a 5DT Data Glove 5",
        ),
        EmulatedDevice::Vmc => (
            matches!(profile.input, nendo_devices::profile::Input::Skeleton(_)),
            "a VMC receiver",
        ),
    };
    if fits {
        Ok(())
    } else {
        anyhow::bail!(
            "profile {} does not have {what}: give a profile with the emulated device (the default is {})",
            profile.name,
            default_profile(device, None)
        )
    }
}

fn glove_table(profile: &Profile, want: usize) -> anyhow::Result<Vec<SensorCalibration>> {
    let table = profile
        .glove()
        .map(|g| g.calibration().to_vec())
        .ok_or_else(|| anyhow::anyhow!("profile {} has no glove", profile.name))?;
    if table.len() != want {
        anyhow::bail!(
            "profile {} calibrates {} glove sensors; this glove has {want}",
            profile.name,
            table.len()
        );
    }
    Ok(table)
}

fn emulate(args: &EmulateArgs) -> anyhow::Result<String> {
    if let Some(s) = args.seconds
        && !(s.is_finite() && s > 0.0 && s <= MAX_SECONDS)
    {
        anyhow::bail!("--seconds must be a positive number of at most {MAX_SECONDS} (a day)");
    }
    if !(args.corrupt.is_finite() && (0.0..=1.0).contains(&args.corrupt)) {
        anyhow::bail!("--corrupt must be a probability from 0 to 1");
    }
    if args.device == EmulatedDevice::Vmc {
        if args.format.is_some() || args.link.is_some() || args.corrupt != 0.0 {
            anyhow::bail!("--format, --link and --corrupt are for the serial emulators, not vmc");
        }
        return super::emulate_vmc::emulate_vmc(args);
    }
    if args.to.is_some() {
        anyhow::bail!("--to is for the vmc emulator (a serial emulator prints its port)");
    }
    let format = args.format.as_deref();
    let name = args
        .profile
        .clone()
        .unwrap_or_else(|| default_profile(args.device, format).to_string());
    let profile = profile::resolve(&name)?;
    check_profile_device(&profile, args.device)?;
    let trace = args
        .motion
        .trace(profile.world_from_tracker, GESTURE_RATE_HZ)?;
    let frames: Arc<Vec<HandFrame>> = Arc::new(trace.frames);
    if frames.is_empty() {
        anyhow::bail!("motion {} has no frames", args.motion.name());
    }
    let pose_script = |period: Duration| {
        let frames = Arc::clone(&frames);
        Script::new(move |k| {
            frame_at(&frames, period, k)
                .pose
                .unwrap_or(TrackerPose::IDENTITY)
        })
    };
    let bad_format = |f: &str, expected: &str| {
        anyhow::anyhow!(
            "--format {f} does not apply to {:?}: expected {expected}",
            args.device
        )
    };
    let (emulator, what) = match args.device {
        EmulatedDevice::Fastrak => {
            let data = match format {
                None | Some("ascii") => DataFormat::Ascii,
                Some("binary") => DataFormat::Binary,
                Some(f) => return Err(bad_format(f, "ascii or binary")),
            };
            let model = FastrakModel::new().with_format(data);
            let model = model.clone().with_path(pose_script(model.period()));
            (PtyEmulator::spawn(model)?, format!("Fastrak ({data:?})"))
        }
        EmulatedDevice::Flock => {
            let scale = match format {
                None => 36.0,
                Some(f) => f
                    .parse::<f64>()
                    .ok()
                    .filter(|s| nendo_devices::flock::SCALES_INCHES.contains(s))
                    .ok_or_else(|| bad_format(f, "36, 72 or 144 (inches)"))?,
            };
            let model = FlockModel::new().with_scale(scale);
            let model = model.clone().with_path(pose_script(model.period()));
            (
                PtyEmulator::spawn(model)?,
                format!("Flock of Birds ({scale} in scale)"),
            )
        }
        EmulatedDevice::Cyberglove => {
            let sensors = match format {
                None | Some("18") => SensorCount::Eighteen,
                Some("22") => SensorCount::TwentyTwo,
                Some(f) => return Err(bad_format(f, "18 or 22 (sensors)")),
            };
            let table = glove_table(&profile, sensors.count())?;
            let model = CyberGloveModel::new(sensors);
            let period = model.period();
            let values = {
                let frames = Arc::clone(&frames);
                Script::new(move |k| raw_values(&table, frame_at(&frames, period, k), 1))
            };
            let switch = {
                let frames = Arc::clone(&frames);
                Script::new(move |k| frame_at(&frames, period, k).buttons & buttons::PRIMARY != 0)
            };
            let model = model.with_values(values).with_switch(switch);
            (
                PtyEmulator::spawn(model)?,
                format!("CyberGlove ({} sensors)", sensors.count()),
            )
        }
        EmulatedDevice::FiveDtGlove5 => {
            if let Some(f) = format {
                return Err(bad_format(f, "no --format"));
            }
            let table = glove_table(&profile, 5)?;
            let model = Glove5Model::new();
            let period = model.period();
            let values = {
                let frames = Arc::clone(&frames);
                Script::new(move |k| {
                    let v = raw_values(&table, frame_at(&frames, period, k), 0);
                    std::array::from_fn(|i| v.get(i).copied().unwrap_or(0))
                })
            };
            (
                PtyEmulator::spawn(model.with_values(values))?,
                "5DT Data Glove 5".to_string(),
            )
        }
        // Sent over UDP above, never on a pty.
        EmulatedDevice::Vmc => {
            anyhow::bail!("the vmc emulator sends over UDP (--to), not on a pty")
        }
    };
    if args.corrupt > 0.0 {
        emulator.corrupt_randomly(Some(args.corrupt), 0x006e_656e_646f);
    }
    // From here on a stop signal ends the loop below (the binary's handler defers to it), so
    // the emulator is dropped and its link removed.
    let stop = super::signal::DeferredStop::new();
    let user_link = match &args.link {
        Some(path) => Some(UserLink::make(path, &emulator.port())?),
        None => None,
    };
    let port = user_link
        .as_ref()
        .map_or_else(|| emulator.port(), |l| l.path.display().to_string());
    super::output::println(&port)?;
    eprintln!(
        "nendo emulate: {what} on {port}, motion {} (profile {}); connect with --profile {} and this port; stop with Ctrl-C",
        args.motion.name(),
        profile.name,
        profile.name
    );
    let started = Instant::now();
    let end = args.seconds.map(|s| started + Duration::from_secs_f64(s));
    let why = loop {
        if stop.requested() {
            break " (stopped by a signal)";
        }
        if end.is_some_and(|end| Instant::now() >= end) {
            break "";
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let records = emulator.records_sent();
    let dropped = emulator.dropped_bytes();
    drop(user_link);
    drop(emulator);
    Ok(format!(
        "{what}: {records} records streamed in {:.1} s{why}, {dropped} bytes the host did not take",
        started.elapsed().as_secs_f64()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn only_an_emulators_pty_link_is_recognised_as_one() {
        assert_eq!(
            emulator_link_owner(Path::new("/tmp/nendo-emulator-4242-0/tty")),
            Some(4242)
        );
        assert_eq!(
            emulator_link_owner(Path::new("/var/tmp/x/nendo-emulator-7-12/tty")),
            Some(7)
        );
        for other in [
            "/dev/pts/3",
            "/home/me/notes.txt",
            "/tmp/nendo-emulator-4242-0/ttyS0",
            "/tmp/nendo-emulator-x-0/tty",
            "/tmp/nendo-emulator-4242/tty",
            "tty",
        ] {
            assert_eq!(emulator_link_owner(Path::new(other)), None, "{other}");
        }
    }
}
