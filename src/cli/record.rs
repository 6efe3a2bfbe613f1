//! `nendo record`: records live devices (or a replayed trace) into a trace file.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::Args as ClapArgs;
use nendo_devices::profile::{self, Input};
use nendo_devices::{HandStream, StreamOptions, TraceHeader, TraceWriter};

/// Arguments of `nendo record`.
#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Device profile: a shipped name (see `nendo devices`) or a path to a profile JSON file.
    #[arg(long)]
    pub profile: String,
    /// The trace file to write (written atomically when recording ends).
    #[arg(long)]
    pub out: PathBuf,
    /// How long to record, in seconds.
    #[arg(long, default_value_t = 10.0)]
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
}

/// Runs `nendo record`.
pub fn run(args: Args) -> ExitCode {
    match record(args) {
        Ok(summary) => {
            println!("{summary}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("nendo record: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn record(args: Args) -> anyhow::Result<String> {
    if !(args.seconds.is_finite() && args.seconds > 0.0) {
        anyhow::bail!("--seconds must be a positive number");
    }
    let profile = profile::resolve(&args.profile)?;
    let mut options = StreamOptions {
        glove_port: args.glove_port,
        tracker_port: args.tracker_port,
        ..StreamOptions::default()
    };
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
    let stream = HandStream::open(&profile, &options)?;
    let header = TraceHeader {
        profile: Some(profile.name.clone()),
        world_from_tracker: profile.world_from_tracker,
        hand: profile.hand,
        joints: stream.joints().to_vec(),
    };
    let mut writer = TraceWriter::create(&args.out, header)?;
    let end = Instant::now() + Duration::from_secs_f64(args.seconds);
    while Instant::now() < end {
        if let Some(frame) = stream.next_timeout(Duration::from_millis(20)) {
            writer.push(&frame)?;
            for frame in stream.drain() {
                writer.push(&frame)?;
            }
        }
    }
    let description = stream.describe();
    let stats = stream.close();
    let frames = writer.finish()?;
    let source = |name: &str, s: nendo_devices::DeviceStats| {
        format!(
            "{name}: {} records, {} rejected, {} bytes skipped, {} invalid values, {} starts",
            s.decode.records, s.decode.rejected, s.decode.skipped_bytes, s.invalid, s.starts
        )
    };
    Ok(format!(
        "recorded {frames} frames in {:.1} s from {description} to {}\n{}\n{}\nwatchdog trips {}, disconnects {}, frames dropped on overflow {}",
        args.seconds,
        args.out.display(),
        source("glove", stats.glove),
        source("tracker", stats.tracker),
        stats.watchdog_trips,
        stats.disconnects,
        stats.overflow,
    ))
}
