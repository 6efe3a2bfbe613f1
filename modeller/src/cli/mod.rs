//! The `nendo` command line: one module per subcommand, each with its own clap arguments.
//!
//! The binary (`src/main.rs` of the root package `nendo`) parses the top level: the window's
//! options ([`window::WindowArgs`]), these subcommands ([`Subcommand`]) and `nendo bench`, whose suites
//! are their own crate (`nendo-bench`, which depends on this one).

pub mod arg_error;
pub mod check;
pub mod closest;
pub mod curve;
pub mod devices;
pub mod emulate;
mod emulate_vmc;
pub mod export;
pub mod figure;
pub mod json_lines;
pub mod morph;
pub mod output;
pub mod paths;
pub mod primitive_args;
pub mod record;
pub mod refine;
#[cfg(feature = "gui")]
pub mod render;
pub mod replay;
pub mod sculpt;
pub mod shape;
pub mod signal;
pub mod symmetry_args;
pub mod window;
use std::process::ExitCode;

/// Every subcommand of the `nendo` binary but `nendo bench` (the binary adds it).
#[derive(Debug, clap::Subcommand)]
pub enum Subcommand {
    /// Print a model's continuity report (G0 gap, G1 angles, pole spread) as JSON.
    Check(check::CheckArgs),
    /// Closest point, pick, probe sphere and ray queries on curves, as JSON Lines (`--batch`).
    Closest(closest::ClosestArgs),
    /// Curve editing (grab, split, tangent, insert), similarity-preserving refinement, warping and SVG, as JSON Lines (`--batch`).
    Curve(curve::CurveArgs),
    /// List serial ports and HID devices, and which device profile fits each.
    Devices(devices::DevicesArgs),
    /// Run a device emulator (fastrak, cyberglove, flock, 5dt-glove5) on a pseudo-terminal: print
    /// its port, then move a hand through a scripted gesture, for trying glove mode without hardware.
    Emulate(emulate::EmulateArgs),
    /// Write a model as a mesh (OBJ with normals, binary STL, GLB) within a tolerance, or exactly
    /// as CAD (STEP AP214, IGES 5.3: the patches as B-spline surfaces, the curves).
    Export(export::ExportArgs),
    /// Figures of metacircles: fit to a contour, render to PNG / SVG, warp by curves, measure;
    /// metaball shapes fitted to sections.
    Figure(figure::FigureArgs),
    /// Write the frames of a morph between two figure files as PNG and SVG.
    Morph(morph::MorphArgs),
    /// Record hand frames from the devices of a profile into a trace file.
    Record(record::RecordArgs),
    /// Run the hand loop headless on a recorded trace (frames -> hand -> contact -> push / pull /
    /// draw-a-line) and write the model.
    Replay(replay::ReplayArgs),
    /// Split patches without changing the surface: insert patch columns / rows at global grid
    /// parameters, or every patch into K x K; write the refined model.
    Refine(refine::RefineArgs),
    /// Draw a model to a PNG with the window's renderer, offscreen.
    #[cfg(feature = "gui")]
    Render(render::RenderArgs),
    /// Build a primitive or read a model, apply push / drag operations, write the model.
    Sculpt(sculpt::SculptArgs),
}

impl Subcommand {
    /// Runs the subcommand. The binary installs the stop-signal handler first
    /// ([`signal::install`]).
    pub fn run(self) -> ExitCode {
        match self {
            Subcommand::Check(args) => check::run(args),
            Subcommand::Closest(args) => closest::run(args),
            Subcommand::Curve(args) => curve::run(args),
            Subcommand::Devices(args) => devices::run(args),
            Subcommand::Emulate(args) => emulate::run(args),
            Subcommand::Export(args) => export::run(args),
            Subcommand::Figure(args) => figure::run(args),
            Subcommand::Morph(args) => morph::run(args),
            Subcommand::Record(args) => record::run(args),
            Subcommand::Refine(args) => refine::run(args),
            Subcommand::Replay(args) => replay::run(args),
            #[cfg(feature = "gui")]
            Subcommand::Render(args) => render::run(args),
            Subcommand::Sculpt(args) => sculpt::run(args),
        }
    }
}
