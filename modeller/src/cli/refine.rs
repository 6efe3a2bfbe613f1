//! `nendo refine MODEL.json --out OUT.json [--uniform K] [--insert-u T,...] [--insert-v T,...]`:
//! more patches, the same surface (see [`crate::surface::refine`]).
//!
//! ```text
//! nendo refine plane.json --uniform 2 --out plane-x2.json
//! nendo refine pot.json --insert-u 3.5,11.5 --insert-v 0.25 --out pot-fine.json
//! ```
//!
//! `T` are global grid parameters: `--insert-u T` (`0 < T < M`, not an integer) splits patch
//! column `⌊T⌋` at `T − ⌊T⌋`, inserting one patch column; `--insert-v` likewise for rows
//! (`0 < T < N`). Around a closed direction the count must stay even: give an even number of
//! parameters there (e.g. `T` and `T + M/2`). `--uniform K` splits every patch into `K × K`;
//! with insertions too, the insertions are made first (in the old grid's parameters) and the
//! result is then split uniformly.
//!
//! **Parameters before and after.** With `s_c` parameters inserted in column `c` at local
//! `t_{c,1} < … < t_{c,s_c}`, the old point at global `T = c + s` (`t_{c,i} ≤ s ≤ t_{c,i+1}`,
//! `t_{c,0} = 0`, `t_{c,s_c+1} = 1`) is the new point at
//! `T' = c + Σ_{c'<c} s_{c'} + i + (s − t_{c,i}) / (t_{c,i+1} − t_{c,i})`; `--uniform K` then
//! multiplies by `K`. Everything else is kept: the surface to rounding, the topology, the
//! regulation, the curves, the file format (version 1; only the counts grow); the spacing
//! ratios are carried over so that regulation after refinement moves nothing.
//!
//! Exit status: 0 written; 1 the model could not be read or written; 2 a bad argument (a
//! parameter out of range, on a grid line, repeated, an odd count around a closed direction,
//! `--uniform 0`, nothing asked, or a refinement past the grid limit of 65 536 patches) —
//! nothing is written then.

use clap::Args as ClapArgs;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::model::Model;
use crate::surface::refine::{RefineError, Refinement};

/// Arguments of `nendo refine`.
#[derive(Debug, ClapArgs)]
pub struct RefineArgs {
    /// The model file.
    pub model: PathBuf,
    /// Split every patch into K x K.
    #[arg(long, value_name = "K")]
    pub uniform: Option<usize>,
    /// Insert patch columns at these global u parameters (comma-separated, each in (0, M), not
    /// an integer).
    #[arg(
        long,
        value_name = "T,...",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub insert_u: Vec<f64>,
    /// Insert patch rows at these global v parameters (each in (0, N), not an integer).
    #[arg(
        long,
        value_name = "T,...",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub insert_v: Vec<f64>,
    /// Where to write the refined model (atomically).
    #[arg(long)]
    pub out: PathBuf,
}

/// Why `nendo refine` stopped.
#[derive(Debug, thiserror::Error)]
enum Failure {
    /// A bad argument (exit status 2).
    #[error("{0}; nothing written")]
    Argument(String),
    /// Reading or writing (exit status 1).
    #[error("{0}")]
    File(String),
}

/// Runs `nendo refine`.
pub fn run(args: RefineArgs) -> ExitCode {
    match refine(&args) {
        Ok(summary) => {
            eprintln!("nendo refine: {summary}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("nendo refine: {e}");
            match e {
                Failure::Argument(_) => ExitCode::from(2),
                Failure::File(_) => ExitCode::from(1),
            }
        }
    }
}

fn refine(args: &RefineArgs) -> Result<String, Failure> {
    if args.uniform.is_none() && args.insert_u.is_empty() && args.insert_v.is_empty() {
        return Err(Failure::Argument(
            "give --uniform K, --insert-u T,... or --insert-v T,...".into(),
        ));
    }
    if args.uniform == Some(0) {
        return Err(Failure::Argument(RefineError::Factor(0).to_string()));
    }
    let mut model = Model::read(&args.model)
        .map_err(|e| Failure::File(e.in_file(&args.model)))?
        .model;
    let before = (model.surface.patches_u(), model.surface.patches_v());
    let start = Instant::now();
    let argument = |e: RefineError| match e {
        RefineError::Surface(_) | RefineError::Mismatch(..) => Failure::File(e.to_string()),
        _ => Failure::Argument(e.to_string()),
    };
    if !args.insert_u.is_empty() || !args.insert_v.is_empty() {
        let r =
            Refinement::new(&model.surface, &args.insert_u, &args.insert_v).map_err(argument)?;
        model.surface = r.apply(&model.surface).map_err(argument)?;
    }
    if let Some(k) = args.uniform {
        let r = Refinement::uniform(&model.surface, k).map_err(|e| match e {
            // Name the counts of the model read, not of an intermediate grid.
            RefineError::TooLarge { to_u, to_v, .. } => argument(RefineError::TooLarge {
                from_u: before.0,
                from_v: before.1,
                to_u,
                to_v,
            }),
            e => argument(e),
        })?;
        model.surface = r.apply(&model.surface).map_err(argument)?;
    }
    let elapsed = start.elapsed();
    model
        .write(&args.out)
        .map_err(|e| Failure::File(e.in_file(&args.out)))?;
    Ok(format!(
        "{} x {} -> {} x {} patches ({} topology) in {:.3} ms -> {}",
        before.0,
        before.1,
        model.surface.patches_u(),
        model.surface.patches_v(),
        model.surface.topology(),
        elapsed.as_secs_f64() * 1e3,
        args.out.display()
    ))
}
