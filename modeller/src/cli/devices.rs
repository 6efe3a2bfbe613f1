//! `nendo devices`: the serial ports and HID devices present, and which profiles fit each.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args as ClapArgs;
use nendo_devices::discover;
use nendo_devices::profile::{self, Input, Profile};

/// Arguments of `nendo devices`.
#[derive(Debug, ClapArgs)]
pub struct DevicesArgs {
    /// A directory of further profile JSON files to match, besides the shipped ones.
    #[arg(long)]
    pub profiles: Option<PathBuf>,
}

/// Runs `nendo devices`. A profile in `--profiles` that does not load is reported on
/// standard error and skipped; the rest are listed. A directory that cannot be read is an
/// error.
pub fn run(args: DevicesArgs) -> ExitCode {
    let mut profiles = profile::builtin();
    if let Some(dir) = &args.profiles {
        match load_dir(dir) {
            Ok(loaded) => {
                for entry in loaded {
                    match entry {
                        Ok(p) => profiles.push(p),
                        Err(e) => eprintln!("nendo devices: warning: skipping {e}"),
                    }
                }
            }
            Err(e) => {
                eprintln!("nendo devices: {e:#}");
                return ExitCode::FAILURE;
            }
        }
    }
    let inv = discover::inventory(&profiles);
    super::output::exit_after(
        "nendo devices",
        super::output::print(render(&inv, &profiles)),
    )
}

/// Why one `*.json` file of `--profiles` was skipped; each message names the file.
#[derive(Debug, thiserror::Error)]
enum LoadError {
    /// The file reads but is no valid profile (or cannot be read).
    #[error("{0}")]
    Profile(nendo_devices::DeviceError),
    /// A fifo, socket, device or directory named `*.json`: never read.
    #[error("{}: not a regular file", .0.display())]
    NotAFile(PathBuf),
    /// The file's metadata cannot be read (a dangling link, no permission).
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
}

/// Every `*.json` file of `dir`, in name order, each loaded or with the reason it does not
/// load (which names the file).
fn load_dir(dir: &std::path::Path) -> anyhow::Result<Vec<Result<Profile, LoadError>>> {
    let entries = std::fs::read_dir(dir).map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    // A fifo, socket or device named `*.json` would block or stream forever: only regular files
    // (or links to them) are read as profiles.
    Ok(paths
        .iter()
        .map(|p| match std::fs::metadata(p) {
            Ok(m) if m.is_file() => Profile::load(p).map_err(LoadError::Profile),
            Ok(_) => Err(LoadError::NotAFile(p.clone())),
            Err(error) => Err(LoadError::Io {
                path: p.clone(),
                error,
            }),
        })
        .collect())
}

fn fits(list: &[String]) -> String {
    if list.is_empty() {
        "no profile fits".to_string()
    } else {
        format!("fits: {}", list.join(", "))
    }
}

fn render(inv: &discover::Inventory, profiles: &[Profile]) -> String {
    let mut s = String::from("Serial ports:\n");
    if let Some(e) = &inv.serial_error {
        s.push_str(&format!("  cannot list serial ports: {e}\n"));
    } else if inv.serial.is_empty() {
        s.push_str("  (none)\n");
    }
    for p in &inv.serial {
        s.push_str(&format!("  {}  [{}]  {}\n", p.path, p.kind, fits(&p.fits)));
    }
    s.push_str("HID devices:\n");
    if let Some(e) = &inv.hid_error {
        s.push_str(&format!("  cannot list HID devices: {e}\n"));
    } else if inv.hid.is_empty() {
        s.push_str("  (none)\n");
    }
    for h in &inv.hid {
        s.push_str(&format!(
            "  {:04x}:{:04x} {}  {}  {}\n",
            h.vid,
            h.pid,
            h.product,
            h.path,
            fits(&h.fits)
        ));
    }
    s.push_str("Profiles:\n");
    for p in profiles {
        let wants = match &p.input {
            Input::Devices { .. } => {
                let mut parts = Vec::new();
                if let Some(g) = p.glove() {
                    parts.push(match (g.port(), g.usb()) {
                        (Some(port), _) => format!("{} on {port}", g.protocol()),
                        (None, Some(u)) => format!(
                            "{} on USB {:04x}:{}",
                            g.protocol(),
                            u.vid,
                            u.pid.map_or("*".into(), |x| format!("{x:04x}"))
                        ),
                        (None, None) => g.protocol().to_string(),
                    });
                }
                if let Some(t) = p.tracker() {
                    parts.push(format!("{} on {}", t.protocol(), t.port()));
                }
                parts.join(" + ")
            }
            Input::Mouse(_) => "the mouse (in the window)".to_string(),
            Input::Replay(r) => format!("replay of {}", r.trace),
        };
        s.push_str(&format!("  {:<24} {wants}\n", p.name));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each skipped file comes with its own reason, typed, and the message names the file.
    #[cfg(unix)]
    #[test]
    fn load_dir_reports_typed_reasons_per_file() {
        let dir = std::env::temp_dir().join(format!("nendo-devices-load-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("a-folder.json")).expect("temp dir");
        std::os::unix::fs::symlink(dir.join("nowhere"), dir.join("b-dangling.json"))
            .expect("symlink");
        std::fs::write(dir.join("c-broken.json"), "{").expect("write");
        let got = load_dir(&dir).expect("the directory reads");
        assert_eq!(got.len(), 3);
        match &got[0] {
            Err(e @ LoadError::NotAFile(p)) => {
                assert_eq!(*p, dir.join("a-folder.json"));
                assert_eq!(
                    e.to_string(),
                    format!("{}: not a regular file", p.display())
                );
            }
            other => panic!("{other:?}"),
        }
        match &got[1] {
            Err(e @ LoadError::Io { path, error }) => {
                assert_eq!(error.kind(), std::io::ErrorKind::NotFound);
                assert_eq!(e.to_string(), format!("{}: {error}", path.display()));
            }
            other => panic!("{other:?}"),
        }
        match &got[2] {
            Err(e @ LoadError::Profile(_)) => {
                assert!(e.to_string().contains("c-broken.json"), "{e}");
            }
            other => panic!("{other:?}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
