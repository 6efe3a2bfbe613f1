//! `nendo morph SRC.json DST.json --frames N --out DIR [--no-svg]`: the frames of a morph
//! between two figure files (P0 §4.2, Fig. 11) as PNG and SVG, in one view framing both
//! figures.
//!
//! Curve `k` of the source file corresponds to curve `k` of the destination; the metacircles
//! are matched through the curves' coordinates and interpolated ([`crate::figure::morph`]).
//! Frame `i` of `N` is the figure at `t = i / (N − 1)`, written as `DIR/frame_0000.png` and
//! `DIR/frame_0000.svg` (the SVG left out with `--no-svg`); a summary is printed as JSON.
//!
//! An output directory that holds anything is refused before any frame is drawn (its old frames would
//! mix with the new ones), unless `--replace` is given: then, once the new frames are written,
//! every other `frame_NNNN.png` / `frame_NNNN.svg` in it (an earlier run's) is removed, so the
//! directory holds exactly this run's frames and whatever else was there.

use anyhow::{Context, bail};
use clap::Args as ClapArgs;
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

use glam::DVec2;

use super::figure::{parse_size, read_document, write_png, write_text};
use crate::figure::morph::{Morph, MorphOptions};
use crate::figure::picture::{Backdrop, PictureOptions, draw};
use crate::figure::{ImageSize, RasterView, Rgb};

/// Arguments of `nendo morph`.
#[derive(Debug, Clone, ClapArgs)]
pub struct MorphArgs {
    /// The source figure file (metacircles and curves).
    pub source: PathBuf,
    /// The destination figure file (metacircles and as many curves).
    pub destination: PathBuf,
    /// Number of frames, source and destination included (≥ 2).
    #[arg(long, default_value_t = 10)]
    pub frames: usize,
    /// Output directory (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Frame size in pixels, `WIDTHxHEIGHT`.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: ImageSize,
    /// Supersampling of boundary pixels per axis (1..=16).
    #[arg(long, default_value_t = 4)]
    pub samples: u32,
    /// Write the PNG frames only: leave out each frame's SVG (the traced boundary and the
    /// interpolated curves), which is written by default.
    #[arg(long)]
    pub no_svg: bool,
    /// Move the centres along the interpolated skeleton curves instead of straight lines.
    #[arg(long)]
    pub skeleton: bool,
    /// Matching distance in figure units (default: twice the median metacircle radius).
    #[arg(long, allow_hyphen_values = true)]
    pub match_distance: Option<f64>,
    /// Write into an output directory that is not empty, removing an earlier run's frames
    /// (`frame_NNNN.png` / `.svg`) that this run does not write.
    #[arg(long)]
    pub replace: bool,
}

/// Whether `name` is a frame's file name: `frame_` digits `.png` or `.svg`.
fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|r| r.strip_suffix(".png").or_else(|| r.strip_suffix(".svg")))
        .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
}

/// Refuses a directory that is not empty, unless `replace`.
fn check_empty(dir: &std::path::Path, replace: bool) -> anyhow::Result<()> {
    if replace {
        return Ok(());
    }
    let mut entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", dir.display())),
    };
    if let Some(first) = entries.next() {
        let first = first.with_context(|| format!("cannot read {}", dir.display()))?;
        bail!(
            "--out {} is not empty (it holds {}, …): an earlier run's frames would mix with the new ones; give an empty or new directory, or --replace to replace its frames",
            dir.display(),
            first.file_name().to_string_lossy()
        );
    }
    Ok(())
}

/// Removes the frames in `dir` that are not in `written` (file names).
fn remove_old_frames(
    dir: &std::path::Path,
    written: &std::collections::HashSet<String>,
) -> anyhow::Result<usize> {
    let mut removed = 0;
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot read {}", dir.display()))? {
        let entry = entry.with_context(|| format!("cannot read {}", dir.display()))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_frame_name(&name) && !written.contains(&name) && entry.path().is_file() {
            std::fs::remove_file(entry.path())
                .with_context(|| format!("cannot remove {}", entry.path().display()))?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// Runs `nendo morph`.
pub fn run(args: MorphArgs) -> ExitCode {
    match morph(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => super::output::failed("nendo morph", &e),
    }
}

fn morph(args: &MorphArgs) -> anyhow::Result<()> {
    if args.frames < 2 || args.frames > 100_000 {
        bail!("--frames must be 2 to 100000, got {}", args.frames);
    }
    // Checked before any work: `create_dir_all` would only say "File exists".
    if args.out.exists() && !args.out.is_dir() {
        bail!(
            "--out {} is not a directory: give the directory the frames go in",
            args.out.display()
        );
    }
    let src = read_document(&args.source)?;
    let dst = read_document(&args.destination)?;
    let options = MorphOptions {
        match_distance: args.match_distance,
        skeleton: args.skeleton,
        ..MorphOptions::default()
    };
    let morph = Morph::new(
        (&src.figure, &src.curves),
        (&dst.figure, &dst.curves),
        options,
    )?;
    // One view for every frame: the union of both documents' frames.
    let (Some(a), Some(b)) = (src.frame(), dst.frame()) else {
        bail!("the figures have nothing to draw");
    };
    let (lo, hi) = (a.0.min(b.0), a.1.max(b.1));
    let (lo, hi) = if src.view.is_some() && dst.view.is_some() {
        (lo, hi)
    } else {
        let pad = 0.04 * (hi - lo).max_element();
        (lo - DVec2::splat(pad), hi + DVec2::splat(pad))
    };
    let view = RasterView::fit(lo, hi, args.size, 0.0);
    // Checked before any frame is drawn (the documents are read first, so a bad one is named
    // whatever the directory holds).
    check_empty(&args.out, args.replace)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let picture = PictureOptions {
        size: args.size,
        samples: args.samples,
        ..PictureOptions::default()
    };
    let background = src.background.or(dst.background).unwrap_or(Rgb::WHITE);
    let mut counts = Vec::with_capacity(args.frames);
    let mut written = std::collections::HashSet::new();
    for i in 0..args.frames {
        let t = i as f64 / (args.frames - 1) as f64;
        let figure = morph.at(t)?;
        let curves = morph.curves_at(t);
        let backdrop = Backdrop {
            background: Some(background),
            polygons: &[],
            curves: &curves,
        };
        let pic = draw(&figure, &backdrop, &view, &picture)?;
        let stem = format!("frame_{i:04}");
        write_png(&args.out.join(format!("{stem}.png")), &pic.image)?;
        written.insert(format!("{stem}.png"));
        if !args.no_svg {
            write_text(&args.out.join(format!("{stem}.svg")), &pic.svg)?;
            written.insert(format!("{stem}.svg"));
        }
        counts.push(figure.metacircles.len());
    }
    let removed = remove_old_frames(&args.out, &written)?;
    let s = morph.stats();
    super::output::println(json!({
        "frames": args.frames,
        "source_metacircles": src.figure.metacircles.len(),
        "destination_metacircles": dst.figure.metacircles.len(),
        "pairs": morph.pairs().len(),
        "forward_matches": s.forward,
        "backward_matches": s.backward,
        "dummies_at_destination": s.dummies_destination,
        "dummies_at_source": s.dummies_source,
        "out": args.out.display().to_string(),
        "old_frames_removed": removed,
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names_are_recognised() {
        assert!(is_frame_name("frame_0000.png"));
        assert!(is_frame_name("frame_12345.svg"));
        assert!(!is_frame_name("frame_.png"));
        assert!(!is_frame_name("frame_00a0.png"));
        assert!(!is_frame_name("notes.txt"));
        assert!(!is_frame_name("frame_0001.png.bak"));
    }
}
