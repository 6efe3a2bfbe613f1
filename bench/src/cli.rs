//! `nendo bench <suite>`: its arguments, and the run that prints one suite's table. The binary
//! (the root package `nendo`) adds this subcommand beside the library's ([`nendo::cli`]).

use clap::{Args as ClapArgs, ValueEnum};
use std::process::ExitCode;

/// Arguments of `nendo bench`.
#[derive(Debug, ClapArgs)]
pub struct BenchArgs {
    /// Which suite to run.
    #[arg(value_enum)]
    pub suite: Suite,
    /// Scale the number of cases (1.0 = the documented set-up; smaller for a quick look; at
    /// most 100).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub scale: f64,
}

/// The benchmark suites.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Suite {
    /// Closest point by Bezier clipping vs sampling and Newton; picking among 1 000 curves.
    Closest,
    /// Grab, split and refine on cubic and degree-9 curves; warping a 1 600-patch control net by 3 curves.
    Curves,
    /// One push on planes and spheres of growing size: median time and the 40x40 / 10x10 ratio.
    Sculpt,
    /// Decode throughput per device protocol; device sample -> regulated surface latency on a 1 600-patch sphere.
    Input,
    /// The paper's deviation experiment for every regulation method, and G1 after 10 000 random strokes.
    Regulation,
    /// Tessellation of 100 / 1 600 sculpted patches and headless 1280x720 frames.
    Render,
    /// One live-stroke frame (deform, regulate, re-tessellate the touched patches, build their upload) on 10x10 and 40x40 against the full rebuild; undo memory per stroke on 10x10, 40x40, 256x256.
    Live,
    /// Figures: 512x512 frame time of a 300-metacircle figure (render, picture, morph frame), fit time and residuals of the shipped figures, the metaball torso's fit, re-fit and mesh.
    Figures,
}

/// The largest `--scale`: a hundred times the documented set-up already runs for hours, and
/// the case counts of a larger one overflow what can be allocated.
pub const MAX_SCALE: f64 = 100.0;

/// Runs `nendo bench`.
pub fn run(args: BenchArgs) -> ExitCode {
    if !(args.scale.is_finite() && args.scale > 0.0 && args.scale <= MAX_SCALE) {
        eprintln!(
            "nendo bench: --scale must be a positive number of at most {MAX_SCALE}, got {}",
            nendo::num::Compact(args.scale)
        );
        return ExitCode::from(2);
    }
    let (text, ok) = match args.suite {
        Suite::Closest => (
            format!(
                "{}(kurbo's CubicBez::nearest joins this table in `cargo bench --bench closest`.)\n",
                crate::closest::report(args.scale, &[])
            ),
            true,
        ),
        Suite::Curves => (crate::curves::report(args.scale), true),
        Suite::Sculpt => (crate::sculpt::report(args.scale), true),
        Suite::Input => (crate::input::report(args.scale), true),
        Suite::Regulation => (crate::regulation::report_text(args.scale), true),
        Suite::Render => (crate::render::report(args.scale), true),
        #[cfg(feature = "gui")]
        Suite::Live => (crate::live::report(args.scale), true),
        #[cfg(not(feature = "gui"))]
        Suite::Live => (
            "nendo bench live: needs the `gui` feature\n".to_string(),
            false,
        ),
        Suite::Figures => {
            let text = crate::figures::report(args.scale);
            let ok = !text.starts_with("nendo bench figures:");
            (text, ok)
        }
    };
    if let Err(nendo::cli::output::StdoutError(e)) = nendo::cli::output::print(text) {
        return nendo::cli::output::stdout_failed("nendo bench", &e);
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
