//! `nendo record`: records live devices (or a replayed trace) into a trace file.
//!
//! **A recording survives whatever ends it.** The trace grows under the `--out` name from the
//! start ([`nendo_devices::TraceRecorder`]): its header is placed whole and synced first, each
//! frame line is handed to the kernel as it comes (one `write` per frame), the file is synced
//! (`fdatasync`) at most a second after a frame ([`nendo_devices::trace::SYNC_INTERVAL`]; the
//! loop below checks it every 20 ms while it waits), and the `end N` line comes last. So:
//! - after `--seconds`, the end of a replayed trace, or SIGINT (Ctrl-C), SIGTERM or SIGHUP, the
//!   frames so far are written and the trace is finished with its `end` line;
//! - a SIGKILL (or a crash) loses only the frames still on their way from the devices (at most
//!   one 20 ms poll), a power cut at most about the last second: the file is an interrupted
//!   trace, which `nendo replay` reads up to its last complete frame, saying how many it
//!   recovered;
//! - a full disk (or any failed write) stops the recording at once with an error naming the
//!   file and the frames it keeps (exit status 1); the torn line is taken back, so the file
//!   reads up to the last frame written. Nothing is retried: a recording with a silent hole in
//!   time would replay as a jump.
//!
//! **An existing `--out` is refused** (before any device opens): a recording is a session that
//! cannot be made again, so a new one never replaces an earlier one by surprise — the user
//! names another file, or says `--replace`. With `--replace` the old file stays whole until the
//! new recording's header is in place. (Recordings of older nendo versions, written atomically,
//! left a killed session in a hidden `.NAME.nendo-tmp-XXXXXX` beside the target; nothing here
//! removes it, and `nendo replay` reads it.)
//!
//! The scene of the session (trace version 2, [`crate::hand::scene`]): `--primitive` (with
//! `--patches`, `--radius`, `--height`, `--minor-radius`) or `--model` names the surface the
//! recording is made on — a model is embedded in the trace, or with `--reference` named by its
//! path (relative to the trace's directory when it is inside it, else absolute) and the
//! SHA-256 of its bytes — and `--regulation`, `--finger`, `--finger-radius`, `--mirror` (planes
//! combined as `x,y`, with `--radial N` or `--lathe`: the symmetry group `nendo sculpt` and
//! `nendo replay` take, [`super::symmetry_args`]), `--auto-refine` the session's settings, and the profile's gate and filter settings go with
//! them (the scene's `filter`); `nendo replay TRACE --out M.json` then needs nothing else. Without `--primitive` or `--model` the trace says it has no scene (`scene none`; a
//! replayed trace keeps its own), and the settings options are refused.
//!
//! **The gate's marks** (trace version 4): the recording runs the plausibility gate over the
//! frames it writes and marks those where it held something (`held=`, see
//! [`nendo_devices::trace::HeldMarks`]), with the settings `nendo replay` filters the trace
//! with by default: the scene's `filter` (the profile's, or a replayed trace's own scene's),
//! else, for a trace without a scene, the profile's. So the marks are what a replay's gate
//! holds, and `nendo replay` says whether it agrees. A profile whose filter is off
//! (`"filter": {"enabled": false}`) records no marks (and no `marks` header line). The summary
//! counts the marked frames.
//!
//! Devices start as in the window's Connect ([`HandStream::connect`]): whatever is present
//! records from the start, a device absent or mute at start is retried every 250 ms and joins
//! when it answers (a warning says so); with no device answering, the command fails naming
//! each device's error and writes nothing.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// The longest recording `--seconds` accepts: a day.
const MAX_SECONDS: f64 = 86_400.0;

use clap::Args as ClapArgs;
use nendo_devices::profile::{self, Input};
use nendo_devices::trace::Existing;
use nendo_devices::{
    DeviceError, HandStream, SceneText, SourceState, StreamOptions, TraceRecorder,
};

use super::arg_error::{parse_primitive, parse_regulation};
use super::primitive_args::ShapeArgs;
use crate::hand::scene::{Scene, Start, sha256_hex};
use crate::model::Model;
use crate::surface::{Plane, Primitive, Regulation};

/// Arguments of `nendo record`.
#[derive(Debug, ClapArgs)]
pub struct RecordArgs {
    /// Device profile: a shipped name (see `nendo devices`) or a path to a profile JSON file.
    #[arg(long)]
    pub profile: String,
    /// The trace file to write: it grows as frames come, and ends with its `end` line when the
    /// recording does. An existing file is refused (see --replace).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace an existing --out (it stays whole until the new recording has begun).
    #[arg(long)]
    pub replace: bool,
    /// How long to record, in seconds (at most a day).
    #[arg(long, default_value_t = 10.0, allow_hyphen_values = true)]
    pub seconds: f64,
    /// Serial port replacing the profile's, for a profile with a single serial device.
    #[arg(long, conflicts_with_all = ["glove_port", "tracker_port"])]
    pub port: Option<String>,
    /// Serial port replacing the profile glove's.
    #[arg(long)]
    pub glove_port: Option<String>,
    /// Serial port replacing the profile tracker's.
    #[arg(long)]
    pub tracker_port: Option<String>,
    /// The address and port the VMC receiver listens on (`ADDR:PORT`), replacing the
    /// profile's: for a profile with a VMC source (`--profile vmc`).
    #[arg(long, value_name = "ADDR:PORT")]
    pub vmc_listen: Option<String>,
    /// The scene's start surface: a primitive (plane, cylinder, hemisphere, sphere, torus or
    /// tube).
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_primitive), conflicts_with = "model")]
    pub primitive: Option<Primitive>,
    /// The primitive's shape.
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// The scene's start surface: this model file, embedded in the trace.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Name the `--model` by its path and SHA-256 instead of embedding it.
    #[arg(long, requires = "model")]
    pub reference: bool,
    /// The scene's regulation method.
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_regulation))]
    pub regulation: Option<Regulation>,
    /// The scene's touching finger (as `nendo replay --finger`).
    #[arg(long, value_parser = clap::builder::ValueParser::new(finger_text))]
    pub finger: Option<String>,
    /// The scene's finger radius r_f in sides.
    #[arg(long, allow_hyphen_values = true)]
    pub finger_radius: Option<f64>,
    /// The scene's mirror planes: x, y or z (`x,y` or the option repeated: every combination
    /// of the mirrors), as `nendo sculpt --mirror`.
    #[arg(long, value_delimiter = ',', value_parser = clap::builder::ValueParser::new(super::sculpt::parse_plane))]
    pub mirror: Vec<Plane>,
    /// The scene's `--radial N`, `--lathe` (with its mirrors).
    #[command(flatten)]
    pub turns: super::symmetry_args::TurnArgs,
    /// The scene refines the grid before each contact. Not with a symmetry.
    #[arg(long, conflicts_with_all = ["mirror", "radial", "lathe"])]
    pub auto_refine: bool,
}

/// A `--finger` value, checked by `nendo replay`'s parser and kept as given.
fn finger_text(s: &str) -> Result<String, super::arg_error::ArgError> {
    super::replay::parse_finger(s).map(|_| s.trim().to_owned())
}

/// `model` as the trace at `out` names it: relative to the trace's directory when it lies
/// inside it, else absolute.
fn reference_path(model: &Path, out: &Path) -> anyhow::Result<PathBuf> {
    let absolute =
        std::fs::canonicalize(model).map_err(|e| anyhow::anyhow!("{}: {e}", model.display()))?;
    let dir = out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    Ok(match std::fs::canonicalize(dir) {
        Ok(dir) => absolute
            .strip_prefix(&dir)
            .map(Path::to_path_buf)
            .unwrap_or(absolute.clone()),
        Err(_) => absolute,
    })
}

/// The scene the options name, checked (the model read, the primitive's parameters
/// resolved); `None` without `--primitive` or `--model`.
fn scene(args: &RecordArgs) -> anyhow::Result<Option<SceneText>> {
    let shape = args.shape.given();
    let settings = args.regulation.is_some()
        || args.finger.is_some()
        || args.finger_radius.is_some()
        || !args.mirror.is_empty()
        || args.turns.given()
        || args.auto_refine;
    let mut scene = match (&args.model, args.primitive) {
        (Some(path), _) => {
            if shape {
                return Err(ShapeArgs::not_for_a_model());
            }
            // Bounded as `Model::read` is: a device or runaway file is refused at the limit.
            let text =
                nendo_file::read_text_limited(path, crate::model::MAX_FILE_BYTES, "model file")?;
            let model = Model::from_json_str(&text)
                .map_err(|e| anyhow::anyhow!("{}", e.in_file(path)))?
                .model;
            Scene::new(if args.reference {
                Start::ModelFile {
                    path: reference_path(path, &args.out)?,
                    sha256: sha256_hex(text.as_bytes()),
                }
            } else {
                Start::Model(Box::new(model))
            })
        }
        (None, Some(p)) => {
            args.shape.check_applies(p)?;
            let params = args.shape.params();
            Scene::primitive(p, &params)?
        }
        (None, None) => {
            if shape || settings {
                anyhow::bail!(
                    "the scene's settings and a primitive's shape need its start surface: give --primitive or --model"
                );
            }
            return Ok(None);
        }
    };
    scene.regulation = args.regulation;
    scene.finger.clone_from(&args.finger);
    scene.finger_radius = args.finger_radius;
    scene.mirror.clone_from(&args.mirror);
    scene.radial = args.turns.radial.filter(|&n| n > 1);
    scene.lathe = args.turns.lathe;
    scene.auto_refine = args.auto_refine;
    // The profile's gate and filter, so that a replay filters the frames the same way.
    scene.filter = Some(profile::resolve(&args.profile)?.filter);
    Ok(Some(scene.to_text()?))
}

/// Why an existing `--out` is not recorded over.
fn exists_message(out: &Path) -> String {
    format!(
        "{}: a file is already there (an earlier recording?): nendo record does not replace it; give another --out, or --replace to replace it",
        out.display()
    )
}

/// What ended a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ending {
    /// `--seconds` passed.
    Time,
    /// SIGINT, SIGTERM or SIGHUP.
    Signal,
    /// A replayed trace played to its end.
    ReplayEnded,
}

/// Runs `nendo record`.
pub fn run(args: RecordArgs) -> ExitCode {
    match record(args) {
        Ok(summary) => super::output::exit_after("nendo record", super::output::println(summary)),
        Err(e) => super::output::failed("nendo record", &e),
    }
}

fn record(args: RecordArgs) -> anyhow::Result<String> {
    if !(args.seconds.is_finite() && args.seconds > 0.0 && args.seconds <= MAX_SECONDS) {
        anyhow::bail!("--seconds must be a positive number of at most {MAX_SECONDS} (a day)");
    }
    super::paths::check(
        &[("--out", Some(&args.out))],
        &[
            ("profile", Some(Path::new(&args.profile))),
            ("--model", args.model.as_deref()),
        ],
    )?;
    // The scene is checked before any device opens: a bad one records nothing.
    let scene = scene(&args)?;
    // So is an existing trace, which may be an earlier session: refused unless --replace.
    let existing = if args.replace {
        Existing::Replace
    } else {
        if std::fs::symlink_metadata(&args.out).is_ok() {
            anyhow::bail!("{}", exists_message(&args.out));
        }
        Existing::Refuse
    };
    let profile = profile::resolve(&args.profile)?;
    let mut options = StreamOptions {
        glove_port: args.glove_port,
        tracker_port: args.tracker_port,
        vmc_listen: args.vmc_listen,
        ..StreamOptions::default()
    };
    if options.vmc_listen.is_some() && !matches!(profile.input, Input::Skeleton(_)) {
        anyhow::bail!(
            "profile {} has no VMC receiver for --vmc-listen (try --profile vmc)",
            profile.name
        );
    }
    if let Some(port) = args.port {
        match (
            &profile.input,
            profile.glove().is_some(),
            profile.tracker().is_some(),
        ) {
            (Input::Devices { .. }, true, false) => options.glove_port = Some(port),
            (Input::Devices { .. }, false, true) => options.tracker_port = Some(port),
            (Input::Devices { .. }, _, _) => {
                anyhow::bail!(
                    "profile {} has a glove and a tracker: use --glove-port and --tracker-port",
                    profile.name
                )
            }
            _ => anyhow::bail!("profile {} has no serial device for --port", profile.name),
        }
    }
    if let Input::Mouse(_) = profile.input {
        anyhow::bail!("the mouse hand is recorded from the window, not from the command line");
    }
    // From here on a stop signal ends the loop below instead of exiting the process (the
    // binary's handler, `super::signal`, defers to it).
    let stop = super::signal::DeferredStop::new();
    // Whatever is present starts now; a device absent or mute at start is retried through
    // the recording (as one unplugged mid-recording is). With none present there is nothing
    // to record: an error naming each device's problem, and no trace is written.
    let stream = HandStream::connect(&profile, &options)?;
    let status = stream.status();
    // (A replay has no devices to wait for: its states come with its frames.)
    let live = stream.source_header().is_none();
    if live && !status.is_empty() && status.iter().all(|s| s.state != SourceState::Ok) {
        let errors: Vec<String> = status
            .iter()
            .map(|s| {
                s.last_error
                    .clone()
                    .unwrap_or_else(|| format!("{} did not start", s.description))
            })
            .collect();
        drop(stream);
        anyhow::bail!("{}", errors.join("; "));
    }
    for s in status.iter().filter(|s| live && s.state != SourceState::Ok) {
        eprintln!(
            "nendo record: warning: {} is not there yet ({}); recording without it, retrying",
            s.role.name(),
            s.last_error.as_deref().unwrap_or("no answer")
        );
    }
    for w in stream.warnings() {
        eprintln!("nendo record: warning: {w}");
    }
    // A replayed trace is recorded with its own header, not the replay profile's (and its own
    // scene, unless the options name one).
    let mut header = stream.recording_header(&profile);
    if scene.is_some() {
        header.scene = scene;
    }
    // The gate the frames are marked by: the settings a replay of this trace filters with.
    let gate = Scene::of_trace(&header)
        .ok()
        .flatten()
        .and_then(|s| s.filter)
        .unwrap_or(profile.filter);
    let mut writer = match TraceRecorder::create_gated(&args.out, header, existing, gate) {
        Ok(w) => w,
        Err(DeviceError::File { error, .. })
            if error.kind() == std::io::ErrorKind::AlreadyExists =>
        {
            anyhow::bail!("{}", exists_message(&args.out))
        }
        Err(e) => return Err(e.into()),
    };
    let started = Instant::now();
    let end = started + Duration::from_secs_f64(args.seconds);
    let mut ending = Ending::Time;
    // The first write that fails ends the recording (the file keeps what came before).
    let mut failed = None;
    loop {
        if stop.requested() {
            ending = Ending::Signal;
            break;
        }
        if Instant::now() >= end {
            break;
        }
        // Read before draining: a replay sets it after its last frame, so the drain below
        // still takes every frame sent before.
        let finished = stream.finished();
        let written = match stream.next_timeout(Duration::from_millis(20)) {
            Some(frame) => std::iter::once(frame)
                .chain(stream.drain())
                .try_for_each(|f| writer.push(&f)),
            None if finished => {
                ending = Ending::ReplayEnded;
                break;
            }
            None => writer.sync_if_due(),
        };
        if let Err(e) = written {
            failed = Some(e);
            break;
        }
    }
    let elapsed = started.elapsed().as_secs_f64();
    // Frames that arrived before the stop are kept.
    if failed.is_none()
        && let Err(e) = stream.drain().iter().try_for_each(|f| writer.push(f))
    {
        failed = Some(e);
    }
    let description = stream.describe();
    let last_error = stream.last_error();
    let stats = stream.close();
    if let Some(e) = failed {
        anyhow::bail!("{e} (after {elapsed:.1} s)");
    }
    let marks = match writer.gate() {
        Some(gate) => format!(
            "\ngate: {} of {frames} frames marked held ({})",
            writer.marked(),
            crate::hand::filter::describe(gate.stats()),
            frames = writer.frames()
        ),
        None => "\ngate off: no frames marked".to_owned(),
    };
    let frames = writer.finish()?;
    let source = |name: &str, s: nendo_devices::DeviceStats| {
        format!(
            "{name}: {} records, {} rejected, {} bytes skipped, {} invalid values, {} faults, {} starts",
            s.decode.records,
            s.decode.rejected,
            s.decode.skipped_bytes,
            s.invalid,
            s.faults,
            s.starts
        )
    };
    let why = match ending {
        Ending::Signal => " (stopped by a signal)",
        Ending::ReplayEnded => " (the replayed trace ended)",
        Ending::Time => "",
    };
    let mut summary = format!(
        "recorded {frames} frames in {elapsed:.1} s{why} from {description} to {}\n{}\n{}\nwatchdog trips {}, disconnects {}, frames dropped on overflow {}",
        args.out.display(),
        source("glove", stats.glove),
        source("tracker", stats.tracker),
        stats.watchdog_trips,
        stats.disconnects,
        stats.overflow,
    );
    summary.push_str(&marks);
    if let Some(e) = last_error {
        summary.push_str(&format!("\nlast device error: {e}"));
    }
    Ok(summary)
}
