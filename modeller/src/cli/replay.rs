//! `nendo replay`: runs the whole hand loop headless on a recorded trace — frames → kinematic
//! hand → contact → push / pull / draw-a-line → regulation — and writes the model.
//!
//! ```text
//! nendo replay devices/traces/tube-pot.trace --out pot.json
//! nendo replay devices/traces/tube-pot.trace --primitive tube --patches 16x8 --out pot.json
//! nendo replay my.trace --model start.json --regulation g1 --profile cyberglove2-18-fastrak --out out.json
//! ```
//!
//! The scene comes from the trace's header when it has one (trace version 2, see
//! [`crate::hand::scene`]): the start surface (a primitive with its parameters, an embedded
//! model, or a model file named by path and SHA-256) and the session's settings (regulation,
//! finger, finger radius, mirrors, radial symmetry or the lathe, auto-refine), so that `nendo replay TRACE --out M.json`
//! reproduces the recorded session. Options given on the command line override the header's:
//! `--primitive` or `--model` replaces its start surface (`--patches`, `--radius`, `--height`,
//! `--minor-radius` alone change the parameters of the header's primitive), `--regulation`,
//! `--finger`, `--finger-radius` replace its settings, `--mirror x|y|z|none` its mirrors,
//! `--radial N` / `--lathe` its turns,
//! `--auto-refine` / `--no-auto-refine` its refinement. A trace without a scene (version 1, or
//! recorded without one) needs `--primitive` or `--model`.
//!
//! A trace without its `end` line — a recording killed, cut by a power failure or stopped by a
//! full disk — replays its complete frames (read as [`nendo_devices::Trace::read_recovering`]
//! does): a notice on standard error says how many were recovered and which damaged end was
//! dropped, and the summary says `N frames recovered from an interrupted recording`. A bad
//! line inside a finished trace stays an error, and nothing is written.
//!
//! The trace is streamed ([`nendo_devices::TraceStream`]): one frame line is held at a time
//! (at most 1 MB; a header line at most 640 MB, as a scene may embed a model), so memory is
//! flat in the trace's length — a 10-million-frame trace (a day at 120 Hz) replays in the
//! memory of a short one. A first pass counts the file's lines for the progress report
//! (holding none of them). `--out` may not be the model file the trace's scene starts from,
//! even when `--model` or `--primitive` replaces the start: the trace would never replay
//! again.
//!
//! The hand's sizes and the tracker-to-world transform come from the trace's header, or from
//! `--profile` (a shipped profile's name or a profile file); frames recorded with the `mouse`
//! profile use the view-ray finger. The result is a pure function of the trace, the starting
//! model and the options: replaying the same trace twice writes byte-identical files. A trace
//! of 1 000 frames or more reports its progress on standard error every tenth of the way.
//!
//! `--auto-refine`: before a frame that starts a contact, the grid is refined where that
//! contact's first frame reaches ([`crate::surface::refine::for_finger`]): patches within
//! reach are split until they are at most `3 r_f / 4` across, in pieces of at most `r_f / 2`
//! (the palm's: its radius for `r_f`; the slack [`crate::surface::refine::FINGER_SLACK`]). The
//! surface does not change; the frame then runs on the finer grid. Whether the frame starts a
//! contact, and with which pushes, is decided by the hand loop's own rules, the same code
//! ([`crate::hand::HandLoop::starting`]): no contact in progress, the finger acting, and every
//! part that presses by rule 4 of [`crate::hand::hand_loop`] — its axis crossing the surface no
//! farther behind the tip than its own joints reach, its tip past the surface along `m̂` by
//! more than the minimum depth, or within the grip distance while gripping — gives a push
//! ending at its tip `E`, along `m̂` by that depth `h` (from `E − h·m̂`); a pinch taking hold of the clay (rule 9) is refined
//! around the point held. A curled finger whose straight capsule runs on through the clay
//! behind it starts nothing and refines nothing. A contact that becomes a draw-a-line stroke
//! is not refined further while it lasts (its reference surface is fixed when it starts), nor
//! is a contact that starts on the very frame the previous one ends. A refinement stopped by
//! the grid limit is reported on standard error, and the contact goes on.
//! The summary on standard error counts the contacts and what they ended as: pushes, pulls
//! (the grip drawing the clay out), draw-a-line strokes, and grabs — pinches of thumb and
//! index that took hold of the clay (rule 9 of [`crate::hand::hand_loop`]), each one `move`.
//! Every frame goes through the hand loop's plausibility gate and One-Euro filter
//! ([`crate::hand::filter`]) with the settings of the trace's scene (what the recording was
//! made with), else `--profile`'s, else the defaults for the finger; `--no-filter` replays the
//! raw frames. The summary says what the gate held (per channel, with the first frames).
//!
//! A trace recorded with the gate's marks (version 4, `marks held`: which samples the
//! recording's gate held, [`nendo_devices::trace::HeldMarks`]) is checked against them: the
//! summary says how many frames the trace marks and whether this replay's gate held the same
//! channels on the same frames (`the trace marks 12 frames held, as this replay's gate does`).
//! Where it does not — the trace recorded with other filter settings than the replay's,
//! `--no-filter`, a trace edited by hand — a warning on standard error names how many frames
//! differ and the first of them; the replay goes on with its own gate all the same (the marks
//! are a record, never an input: a replay filters exactly as the window did), and the exit
//! status does not change. A trace without marks (version 3 or older, or recorded with the
//! gate off) replays as before, its summary unchanged.
//!
//! `--mirror x|y|z` presses every contact together with its mirror image across the plane
//! `x = 0` (`y = 0`, `z = 0`), keeping a symmetric model exactly symmetric; a model that is not
//! symmetric about the plane is refused (exit status 1). Mirrors combine (`--mirror x,y`), and
//! `--radial N` / `--lathe` add turns about the z axis ([`super::symmetry_args`]).

use super::arg_error::{parse_primitive, parse_regulation};
use super::primitive_args::ShapeArgs;
use clap::Args as ClapArgs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use crate::hand::scene::{Scene, Start};
use crate::hand::{FingerModel, Hand, HandLoop, HandOptions, filter};
use crate::model::Model;
use crate::surface::MAX_PATCHES;
use crate::surface::{Grid, Plane, Primitive, PrimitiveParams, Regulation, refine};
use nendo_devices::trace::HeldMarks;
use nendo_devices::{FilterSettings, HandFrame, TraceHeader, TraceStream};

/// Frames from which a replay reports its progress.
pub const PROGRESS_FROM: usize = 1_000;
/// Frames the summary names where the gate held something (the rest are counted).
const HELD_NAMED: usize = 8;

/// A trace's gate marks against the replay's own gate: how many frames the trace marks, and
/// the frames where the two differ (counted, the first few kept).
#[derive(Debug, Default)]
struct MarksCheck {
    marked: usize,
    differ: usize,
    first: Vec<usize>,
}

impl MarksCheck {
    /// Frame `number` (1-based): the trace's marks and what the replay's gate held.
    fn frame(&mut self, number: usize, trace: HeldMarks, gate: HeldMarks) {
        self.marked += usize::from(!trace.is_empty());
        if trace != gate {
            self.differ += 1;
            if self.first.len() < HELD_NAMED {
                self.first.push(number);
            }
        }
    }

    /// The summary's words, and a warning when the replay's gate (`filtered`: on) disagrees.
    fn summary(&self, filtered: bool) -> (String, Option<String>) {
        let frames = |n: usize| format!("{n} frame{}", if n == 1 { "" } else { "s" });
        let marked = format!("the trace marks {} held", frames(self.marked));
        if !filtered {
            return (format!("{marked} (not compared: not filtered)"), None);
        }
        if self.differ == 0 {
            return (format!("{marked}, as this replay's gate does"), None);
        }
        let first: Vec<String> = self.first.iter().map(usize::to_string).collect();
        let more = if self.differ > self.first.len() {
            ", …"
        } else {
            ""
        };
        (
            format!(
                "{marked}; this replay's gate differs on {} (see the warning)",
                frames(self.differ)
            ),
            Some(format!(
                "the trace's gate marks differ from this replay's gate on {} (first: {}{more}): recorded with other filter settings? The replay uses its own gate",
                frames(self.differ),
                first.join(", ")
            )),
        )
    }
}

/// The frames a trace file holds, for the progress report, counted without holding any of
/// it: its lines after the `header_lines`, less a last `end` line. `0` (no progress
/// report) when it is not a regular file (a pipe cannot be read twice).
fn frames_in(path: &Path, header_lines: usize) -> usize {
    use std::io::{BufRead, BufReader};
    // Asked before opening: opening a fifo a second time would wait for another writer.
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return 0;
    }
    let Ok(file) = std::fs::File::open(path) else {
        return 0;
    };
    let mut input = BufReader::with_capacity(1 << 16, file);
    let (mut lines, mut at_start, mut last_is_end) = (0usize, true, false);
    let mut head = Vec::with_capacity(4);
    loop {
        let chunk = match input.fill_buf() {
            Ok([]) | Err(_) => break,
            Ok(c) => c,
        };
        for &b in chunk {
            if at_start {
                lines += 1;
                head.clear();
                at_start = false;
            }
            if b == b'\n' {
                last_is_end = head == b"end ";
                at_start = true;
            } else if head.len() < 4 {
                head.push(b);
                last_is_end = false;
            }
        }
        let n = chunk.len();
        input.consume(n);
    }
    if !at_start {
        last_is_end = head == b"end ";
    }
    lines
        .saturating_sub(header_lines)
        .saturating_sub(usize::from(last_is_end))
}

/// Arguments of `nendo replay`.
#[derive(Debug, ClapArgs)]
pub struct ReplayArgs {
    /// The trace (`nendo-hand-trace` version 1 to 4).
    pub trace: PathBuf,
    /// Start from a primitive: plane, cylinder, hemisphere, sphere, torus or tube (default: the
    /// trace's scene).
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_primitive), conflicts_with = "model")]
    pub primitive: Option<Primitive>,
    /// The primitive's shape.
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// Start from this model file instead of a primitive (default: the trace's scene).
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Regulation method (default: the trace's scene's, else the model's, else the default
    /// method).
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_regulation))]
    pub regulation: Option<Regulation>,
    /// Device profile (shipped name or file) for the hand's sizes and the tracker-to-world
    /// transform; default: the trace's header.
    #[arg(long)]
    pub profile: Option<String>,
    /// The touching fingers: `all` (the five fingers), a comma-separated list of thumb, index,
    /// middle, ring, pinky, palm and all (`all,palm`: the whole hand), or ray (the mouse's
    /// view ray); default: the trace's scene's, else ray for mouse traces, all otherwise.
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_finger))]
    pub finger: Option<FingerModel>,
    /// Finger radius r_f in sides (the fingertip capsule's and the shape function's; default:
    /// the trace's scene's, else 1).
    #[arg(long, allow_hyphen_values = true)]
    pub finger_radius: Option<f64>,
    /// Before each contact, split the patches its finger reaches until they are at most half
    /// the finger radius across (the surface does not change). Not with `--mirror`. Default:
    /// the trace's scene's.
    #[arg(long, conflicts_with = "no_auto_refine")]
    pub auto_refine: bool,
    /// Do not refine before contacts, whatever the trace's scene says.
    #[arg(long)]
    pub no_auto_refine: bool,
    /// Press every contact together with its mirror image across the plane x = 0, y = 0 or
    /// z = 0 (`none`: no mirror, whatever the trace's scene says). The model must be symmetric
    /// about the plane. Default: the trace's scene's.
    /// `x,y` or the option repeated: every combination of the mirrors.
    #[arg(long, value_delimiter = ',', value_parser = clap::builder::ValueParser::new(parse_mirror))]
    pub mirror: Vec<Mirror>,
    /// `--radial N`, `--lathe` (with the trace's scene's mirror, or --mirror's; without them,
    /// the trace's scene's turns).
    #[command(flatten)]
    pub turns: super::symmetry_args::TurnArgs,
    /// Feed the hand loop the raw frames: no plausibility gate, no One-Euro filter. Default:
    /// the trace's scene's filter, else --profile's, else the defaults (none for the mouse's
    /// ray).
    #[arg(long)]
    pub no_filter: bool,
    /// Where to write the model (atomically).
    #[arg(long)]
    pub out: PathBuf,
}

/// `--mirror`: a plane, or `none`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mirror {
    /// No mirror, whatever the trace's scene says.
    None,
    /// Mirror across this plane.
    Plane(Plane),
}

fn parse_mirror(s: &str) -> Result<Mirror, crate::surface::UnknownName> {
    if s == "none" {
        return Ok(Mirror::None);
    }
    super::sculpt::parse_plane(s).map(Mirror::Plane)
}

/// `--finger`'s parser, shared with `nendo record` and with the `finger` of a trace's scene.
pub(crate) fn parse_finger(s: &str) -> Result<FingerModel, super::arg_error::ArgError> {
    s.parse::<FingerModel>()
        .map_err(super::arg_error::ArgError::Finger)
}

/// An error about the file `path`, named once: prefixed with the path unless its message
/// already names it (an I/O error does; a syntax error does not).
fn naming(path: &Path, e: &dyn std::fmt::Display) -> anyhow::Error {
    let message = e.to_string();
    let name = path.display().to_string();
    if message.contains(&name) {
        anyhow::anyhow!("{message}")
    } else {
        anyhow::anyhow!("{name}: {message}")
    }
}

/// Runs `nendo replay`.
pub fn run(args: ReplayArgs) -> ExitCode {
    match replay(&args) {
        Ok(summary) => {
            eprintln!("nendo replay: {summary}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("nendo replay: {e:#}");
            if e.is::<Refused>() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}

/// A replay that ran to the end and wrote its result, but with frames the surface refused
/// (exit status 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct Refused(String);

/// The refinement of `--auto-refine` (see the module docs).
#[derive(Debug, Default)]
struct AutoRefine {
    /// Contacts refined before.
    refined: usize,
}

impl AutoRefine {
    /// Refines `grid` for the contact frame `number` starts, if it starts one: for the
    /// operations [`HandLoop::starting`] says its first frame stands for, decided by the
    /// loop's own rules.
    fn before(
        &mut self,
        hl: &mut HandLoop,
        frame: &HandFrame,
        grid: &mut Grid,
        number: usize,
    ) -> anyhow::Result<()> {
        let Some(ops) = hl.starting(frame, grid) else {
            return Ok(());
        };
        let mut refined = false;
        let mut limited = None;
        for op in &ops {
            let f = refine::for_finger(grid, op)
                .map_err(|e| anyhow::anyhow!("frame {number}: refining for the finger: {e}"))?;
            if !f.refinement.is_empty() {
                *grid = f
                    .refinement
                    .apply(grid)
                    .map_err(|e| anyhow::anyhow!("frame {number}: refining for the finger: {e}"))?;
                refined = true;
            }
            if f.limited {
                limited.get_or_insert(f.target);
            }
        }
        if refined {
            self.refined += 1;
        }
        if let Some(target) = limited {
            eprintln!(
                "nendo replay: frame {number}: refinement for the finger (patches of at most {} side) stopped at the grid limit of {MAX_PATCHES} patches ({} x {}); the contact goes on with these patches",
                crate::num::Compact(target),
                grid.patches_u(),
                grid.patches_v()
            );
        }
        Ok(())
    }
}

/// The session a replay runs: the trace's scene with the command line's options over it.
struct Setup {
    model: Model,
    finger: Option<FingerModel>,
    finger_radius: Option<f64>,
    mirror: Vec<Plane>,
    /// `--radial N` / `--lathe`, or the trace's scene's.
    turns: super::symmetry_args::TurnArgs,
    auto_refine: bool,
    /// The trace's scene's gate and filter settings.
    filter: Option<FilterSettings>,
    /// What came from the trace's scene, for the summary.
    from_scene: Vec<&'static str>,
}

/// Merges the trace's scene (if any) and the command line (which wins).
fn setup(args: &ReplayArgs, header: &TraceHeader) -> anyhow::Result<Setup> {
    let in_trace = |e: &dyn std::fmt::Display| {
        anyhow::anyhow!("{}: the trace's scene: {e}", args.trace.display())
    };
    let scene = Scene::of_trace(header).map_err(|e| in_trace(&e))?;
    let mut from_scene = Vec::new();
    let shape_args = args.shape.given();
    let given = args.shape.params();
    let build = |p: Primitive, params: &PrimitiveParams| -> anyhow::Result<Model> {
        Ok(Model::new(
            p.build(params).map_err(|e| anyhow::anyhow!("{p}: {e}"))?,
        ))
    };
    let mut model = match (&args.model, args.primitive, &scene) {
        (Some(path), _, _) => {
            if shape_args {
                return Err(ShapeArgs::not_for_a_model());
            }
            Model::read(path).map_err(|e| naming(path, &e))?.model
        }
        (None, Some(p), _) => {
            args.shape.check_applies(p)?;
            build(p, &given)?
        }
        (None, None, Some(scene)) => {
            from_scene.push("start surface");
            match &scene.start {
                Start::Primitive { primitive, params } => {
                    args.shape.check_applies(*primitive)?;
                    // The command line's parameters over the scene's.
                    let params = PrimitiveParams {
                        patches: given.patches.or(params.patches),
                        radius: given.radius.or(params.radius),
                        height: given.height.or(params.height),
                        minor_radius: given.minor_radius.or(params.minor_radius),
                    };
                    build(*primitive, &params)?
                }
                _ if shape_args => {
                    return Err(anyhow::anyhow!(
                        "--patches, --radius, --height and --minor-radius shape a primitive; the trace's scene starts from a model"
                    ));
                }
                _ => scene
                    .start_model(trace_dir(&args.trace))
                    .map_err(|e| in_trace(&e))?,
            }
        }
        (None, None, None) => {
            anyhow::bail!("give --primitive or --model (the trace names no scene to start from)")
        }
    };
    let scene_finger = match scene.as_ref().and_then(|s| s.finger.as_deref()) {
        Some(f) => Some(parse_finger(f).map_err(|e| in_trace(&format!("finger: {e}")))?),
        None => None,
    };
    let regulation = match (args.regulation, scene.as_ref().and_then(|s| s.regulation)) {
        (Some(r), _) => Some(r),
        (None, Some(r)) => {
            from_scene.push("regulation");
            Some(r)
        }
        (None, None) => None,
    };
    if let Some(r) = regulation {
        model.regulation = r;
    }
    let finger = match (args.finger, scene_finger) {
        (Some(f), _) => Some(f),
        (None, Some(f)) => {
            from_scene.push("finger");
            Some(f)
        }
        (None, None) => None,
    };
    let finger_radius = match (
        args.finger_radius,
        scene.as_ref().and_then(|s| s.finger_radius),
    ) {
        (Some(r), _) => Some(r),
        (None, Some(r)) => {
            from_scene.push("finger radius");
            Some(r)
        }
        (None, None) => None,
    };
    let given: Vec<Plane> = args
        .mirror
        .iter()
        .filter_map(|m| match m {
            Mirror::Plane(p) => Some(*p),
            Mirror::None => None,
        })
        .collect();
    let scene_mirror = scene.as_ref().map(|s| s.mirror.clone()).unwrap_or_default();
    let mirror = if !args.mirror.is_empty() {
        given
    } else if scene_mirror.is_empty() {
        Vec::new()
    } else {
        from_scene.push("mirror");
        scene_mirror
    };
    // `--radial` / `--lathe` win over the scene's turns.
    let turns = match &scene {
        Some(s) if !args.turns.given() && (s.radial.is_some() || s.lathe) => {
            from_scene.push(if s.lathe { "lathe" } else { "radial symmetry" });
            super::symmetry_args::TurnArgs {
                radial: s.radial,
                lathe: s.lathe,
            }
        }
        _ => args.turns,
    };
    let auto_refine = if args.auto_refine {
        true
    } else if args.no_auto_refine {
        false
    } else {
        let on = scene.as_ref().is_some_and(|s| s.auto_refine);
        if on {
            from_scene.push("auto-refine");
        }
        on
    };
    if auto_refine && turns.given() {
        anyhow::bail!(
            "auto-refine does not go with --radial or --lathe{}",
            if args.auto_refine {
                ""
            } else {
                " (auto-refine from the trace's scene: add --no-auto-refine)"
            }
        );
    }
    if auto_refine && !mirror.is_empty() {
        let from_line = (
            args.auto_refine,
            args.mirror.iter().any(|m| matches!(m, Mirror::Plane(_))),
        );
        anyhow::bail!(
            "auto-refine does not go with a mirror ({})",
            match from_line {
                (true, true) => "--auto-refine and --mirror",
                (true, false) =>
                    "--auto-refine, and a mirror from the trace's scene: add --mirror none",
                (false, true) =>
                    "--mirror, and auto-refine from the trace's scene: add --no-auto-refine",
                (false, false) =>
                    "both from the trace's scene: add --no-auto-refine or --mirror none",
            }
        );
    }
    let filter = scene.as_ref().and_then(|s| s.filter);
    if filter.is_some() && !args.no_filter {
        from_scene.push("filter");
    }
    Ok(Setup {
        model,
        finger,
        finger_radius,
        mirror,
        turns,
        auto_refine,
        filter,
        from_scene,
    })
}

/// The directory a trace's relative paths are resolved against: the trace's own.
fn trace_dir(trace: &Path) -> &Path {
    trace
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// `--out` may not replace the model file the trace's scene starts from (by path and hash),
/// even when `--model` or `--primitive` replaces the start: the trace would then never replay
/// again. The same-file test is [`super::paths::same_file`]'s (links, `..`, not-yet-written
/// names).
fn check_start_model(args: &ReplayArgs, header: &TraceHeader) -> anyhow::Result<()> {
    // A scene that does not read is reported by `setup`, naming what is wrong.
    if let Ok(Some(scene)) = Scene::of_trace(header)
        && let Start::ModelFile { path, .. } = &scene.start
    {
        let full = trace_dir(&args.trace).join(path);
        super::paths::check(
            &[("--out", Some(&args.out))],
            &[("start model the trace's scene names", Some(&full))],
        )?;
    }
    Ok(())
}

pub(crate) fn replay(args: &ReplayArgs) -> anyhow::Result<String> {
    // `--out` may replace the `--model` read (a model either way), not the trace or profile.
    super::paths::check(
        &[("--out", Some(&args.out))],
        &[
            ("trace", Some(&args.trace)),
            ("profile", args.profile.as_deref().map(Path::new)),
        ],
    )?;
    // The trace is streamed: its header now, its frames one at a time in the loop below, so
    // memory stays flat in its length. An interrupted recording (killed, a power cut, a full
    // disk: no `end` line) replays its complete frames, saying so at the end and in the
    // summary.
    let mut stream = TraceStream::open(&args.trace).map_err(|e| naming(&args.trace, &e))?;
    let header = stream.header().clone();
    check_start_model(args, &header)?;
    let total = frames_in(&args.trace, stream.lines_read());
    let Setup {
        mut model,
        finger: chosen_finger,
        finger_radius,
        mirror,
        turns,
        auto_refine,
        filter: scene_filter,
        from_scene,
    } = setup(args, &header)?;
    let (hand, mut finger, profile_filter) = match &args.profile {
        Some(name) => {
            let profile =
                nendo_devices::profile::resolve(name).map_err(|e| anyhow::anyhow!("{e}"))?;
            (
                Hand::new(profile.hand, profile.world_from_tracker)?,
                FingerModel::for_profile(&profile),
                Some(profile.filter),
            )
        }
        None => (
            Hand::new(header.hand, header.world_from_tracker)?,
            FingerModel::for_profile_name(header.profile.as_deref()),
            None,
        ),
    };
    if let Some(f) = chosen_finger {
        finger = f;
    }
    let mut options = HandOptions {
        finger,
        ..HandOptions::default()
    };
    if let Some(r) = finger_radius {
        options.finger_radius = r;
    }
    let regulation = model.regulation;
    // The loop of a `HandSession`, with the grid at hand so that it can be refined between
    // contacts.
    let spec = turns.spec(&mirror);
    let symmetry = super::symmetry_args::symmetry_for(&mut model.surface, &spec, regulation)?;
    let mut hand_loop = HandLoop::new(hand, options)?;
    hand_loop.set_mirror(symmetry);
    hand_loop.set_filter(if args.no_filter {
        FilterSettings::off()
    } else {
        scene_filter
            .or(profile_filter)
            .unwrap_or_else(|| filter::default_for(finger))
    });
    // The frames where the gate held something: their count and the first few (named in
    // the summary), never a list as long as the trace.
    let mut held = Vec::new();
    let mut held_count = 0usize;
    // The trace's own marks, checked against the gate's (see the module docs).
    let mut marks = MarksCheck::default();
    let mut grid = model.surface.clone();
    let mut refiner = auto_refine.then(AutoRefine::default);
    let start = Instant::now();
    let mut next_tenth = 1;
    let mut refused = 0usize;
    let mut k = 0usize;
    while let Some(frame) = stream.next_frame().map_err(|e| naming(&args.trace, &e))? {
        let frame = &frame;
        if let Some(r) = &mut refiner {
            r.before(&mut hand_loop, frame, &mut grid, k + 1)?;
        }
        let out = hand_loop.frame(frame, &mut grid, regulation);
        if header.marks_held {
            let gate = HeldMarks::from(hand_loop.filter().held()).carried_by(
                frame,
                &header.joints,
                header.skeleton.is_some(),
            );
            marks.frame(k + 1, stream.held(), gate);
        }
        if !hand_loop.filter().held().is_empty() {
            held_count += 1;
            if held.len() < HELD_NAMED {
                held.push(k + 1);
            }
        }
        // A refused frame leaves the surface as the contact's last accepted application; the
        // replay goes on, reports every refusal with its frame number (1-based), and ends
        // with exit status 2 after writing the result.
        if let Some(e) = &out.refused {
            refused += 1;
            eprintln!("nendo replay: frame {}: {e}", k + 1);
        }
        if total >= PROGRESS_FROM && next_tenth <= 10 && (k + 1) * 10 >= next_tenth * total {
            let st = hand_loop.stats();
            eprintln!(
                "nendo replay: {:3}% ({}/{} frames, {} contacts, {:.1} s)",
                next_tenth * 10,
                k + 1,
                total,
                st.contacts,
                start.elapsed().as_secs_f64()
            );
            next_tenth += 1;
        }
        k += 1;
    }
    let total = stream.frames_read();
    let interrupted = stream.interrupted().map(|i| {
        eprintln!("nendo replay: {}: {i}", args.trace.display());
        " recovered from an interrupted recording".to_owned()
    });
    hand_loop.end_contact();
    let elapsed = start.elapsed();
    let st = *hand_loop.stats();
    model.surface = grid;
    model.write(&args.out).map_err(|e| naming(&args.out, &e))?;
    if refused > 0 {
        return Err(Refused(format!(
            "{refused} of {total} frames refused by the surface (see above); the surface kept the last accepted state -> {}",
            args.out.display()
        ))
        .into());
    }
    let refinement = refiner.map_or(String::new(), |r| {
        format!(
            "; refined before {} contacts, {} x {} patches",
            r.refined,
            model.surface.patches_u(),
            model.surface.patches_v()
        )
    });
    let scene = if from_scene.is_empty() {
        String::new()
    } else {
        format!("; from the trace's scene: {}", from_scene.join(", "))
    };
    let gate = if hand_loop.filter().settings().enabled {
        format!("; {}", filter::describe(hand_loop.filter().stats()))
    } else {
        "; not filtered".into()
    };
    let gate = match held_count {
        0 => gate,
        n => {
            let first: Vec<String> = held.iter().map(usize::to_string).collect();
            let more = if n > HELD_NAMED { ", …" } else { "" };
            format!("{gate} — frames {}{more}", first.join(", "))
        }
    };
    let filtered = hand_loop.filter().settings().enabled;
    let gate = match (header.marks_held, marks.summary(filtered)) {
        (false, _) => gate,
        (true, (summary, warning)) => {
            if let Some(w) = warning {
                eprintln!("nendo replay: warning: {}: {w}", args.trace.display());
            }
            format!("{gate}; {summary}")
        }
    };
    let clutched = match st.clutched {
        0 => String::new(),
        n => format!(", {n} frames clutched (the clutch key or a fist)"),
    };
    Ok(format!(
        "{total} frames{} ({} with a hand): {} contacts — {} pushes, {} pulls, {} strokes, {} grabs (pinches){clutched}; regulation {regulation}{gate}{refinement}{scene}; {:.3} s -> {}",
        interrupted.unwrap_or_default(),
        st.frames_with_finger,
        st.contacts,
        st.pushes,
        st.pulls,
        st.strokes,
        st.holds,
        elapsed.as_secs_f64(),
        args.out.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::arg_error::parse_counts;
    use crate::hand::Digit;

    #[test]
    fn a_path_is_named_once() {
        let p = Path::new("dir/nonexist.json");
        let io = format!("{}: No such file or directory (os error 2)", p.display());
        assert_eq!(naming(p, &io).to_string(), io);
        assert_eq!(
            naming(p, &"trace line 7: bad").to_string(),
            "dir/nonexist.json: trace line 7: bad"
        );
    }

    #[test]
    fn fingers_and_counts_parse() {
        assert_eq!(parse_finger("ray").ok(), Some(FingerModel::Ray));
        assert_eq!(
            parse_finger("middle").ok(),
            Some(FingerModel::digit(Digit::Middle))
        );
        assert_eq!(
            parse_finger("all,palm").ok(),
            Some(FingerModel::Hand(
                crate::hand::Fingers::ALL.with(crate::hand::Part::Palm)
            ))
        );
        assert_eq!(
            parse_finger("thumb,index").ok().map(|f| match f {
                FingerModel::Hand(f) => f.to_string(),
                FingerModel::Ray => String::new(),
            }),
            Some("thumb,index".to_owned())
        );
        let toe = parse_finger("toe").map(|_| ()).unwrap_err().to_string();
        assert_eq!(
            toe,
            "unknown finger \"toe\": expected thumb, index, middle, ring, pinky, palm or all (a comma-separated list), or ray"
        );
        assert_eq!(parse_counts("40x40").ok(), Some((40, 40)));
        assert!(parse_counts("40").is_err());
    }
}
