//! Running a [`DeviceModel`] on a pseudo-terminal.

use std::fs::{File, OpenOptions};
use std::io::{ErrorKind, Read, Write};
use std::os::fd::AsRawFd;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use nix::fcntl::{FcntlArg, OFlag, fcntl};
use nix::poll::{PollFd, PollFlags, poll};
use nix::pty::{PtyMaster, grantpt, posix_openpt, ptsname_r, unlockpt};
use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};

use super::DeviceModel;

#[derive(Debug, Default)]
struct Control {
    silent: bool,
    unplugged: bool,
    stop: bool,
    inject: Vec<u8>,
    received: Vec<u8>,
    records: u64,
    dropped_bytes: u64,
    corrupt_every: Option<u64>,
    /// Probability of flipping one bit of a streamed record, and the seeded generator.
    corrupt_probability: Option<(f64, ChaCha8Rng)>,
    /// Answers still to garble: (command byte, XOR mask of the answer's first byte).
    garble: Vec<(u8, u8)>,
    answers_garbled: u64,
    ptys_opened: u64,
}

fn lock(c: &Mutex<Control>) -> MutexGuard<'_, Control> {
    c.lock().unwrap_or_else(|p| p.into_inner())
}

/// One pseudo-terminal: the master the emulator drives, and a slave descriptor held open so the
/// pty survives the host closing and reopening its side.
struct Pty {
    master: PtyMaster,
    _slave: File,
}

fn open_pty() -> std::io::Result<(Pty, String)> {
    let master = posix_openpt(OFlag::O_RDWR | OFlag::O_NOCTTY)?;
    grantpt(&master)?;
    unlockpt(&master)?;
    let name = ptsname_r(&master)?;
    let slave = OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(nix::libc::O_NOCTTY)
        .open(&name)?;
    // Raw mode: no echo, no line editing, no CR/LF translation.
    let mut t = tcgetattr(slave.as_raw_fd())?;
    cfmakeraw(&mut t);
    tcsetattr(slave.as_raw_fd(), SetArg::TCSANOW, &t)?;
    fcntl(master.as_raw_fd(), FcntlArg::F_SETFL(OFlag::O_NONBLOCK))?;
    Ok((
        Pty {
            master,
            _slave: slave,
        },
        name,
    ))
}

fn point_link(link: &Path, target: &str) -> std::io::Result<()> {
    let tmp = link.with_extension("new");
    let _ = std::fs::remove_file(&tmp);
    std::os::unix::fs::symlink(target, &tmp)?;
    std::fs::rename(&tmp, link)
}

/// Writes without blocking; what the host side cannot take is dropped (as a serial line
/// overruns) and counted.
fn write_all_or_drop(master: &mut PtyMaster, mut bytes: &[u8], control: &Mutex<Control>) {
    while !bytes.is_empty() {
        match master.write(bytes) {
            Ok(0) => break,
            Ok(n) => bytes = &bytes[n..],
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => break,
        }
    }
    if !bytes.is_empty() {
        lock(control).dropped_bytes += bytes.len() as u64;
    }
}

static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// A device model running on a pseudo-terminal behind a stable path (a symbolic link that
/// follows the pty across unplug/replug). Dropping it stops the device and removes the link.
pub struct PtyEmulator {
    dir: PathBuf,
    link: PathBuf,
    control: Arc<Mutex<Control>>,
    thread: Option<JoinHandle<()>>,
    name: &'static str,
}

impl std::fmt::Debug for PtyEmulator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PtyEmulator")
            .field("device", &self.name)
            .field("path", &self.link)
            .finish()
    }
}

impl PtyEmulator {
    /// Starts the model on a new pty; its path is ready when this returns.
    pub fn spawn(model: impl DeviceModel + 'static) -> std::io::Result<PtyEmulator> {
        let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("nendo-emulator-{}-{id}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let link = dir.join("tty");
        let (pty, target) = open_pty()?;
        point_link(&link, &target)?;
        let control = Arc::new(Mutex::new(Control {
            ptys_opened: 1,
            ..Control::default()
        }));
        let name = model.name();
        let thread = {
            let control = Arc::clone(&control);
            let link = link.clone();
            std::thread::Builder::new()
                .name(format!("emulator {name}"))
                .spawn(move || run(model, Some(pty), &link, &control))?
        };
        Ok(PtyEmulator {
            dir,
            link,
            control,
            thread: Some(thread),
            name,
        })
    }

    /// The device path to open (a symbolic link to the current pty).
    pub fn path(&self) -> &Path {
        &self.link
    }

    /// The device path as a string.
    pub fn port(&self) -> String {
        self.link.display().to_string()
    }

    /// A silent device neither answers nor streams (its cable still plugged in).
    pub fn set_silent(&self, silent: bool) {
        lock(&self.control).silent = silent;
    }

    /// Pulls the plug: the pty closes (the host sees a hang-up) and the path disappears.
    pub fn unplug(&self) {
        lock(&self.control).unplugged = true;
    }

    /// Plugs back in: a new pty appears behind the same path.
    pub fn replug(&self) {
        lock(&self.control).unplugged = false;
    }

    /// Sends these bytes (garbage, a burst) before anything else.
    pub fn inject(&self, bytes: &[u8]) {
        lock(&self.control).inject.extend_from_slice(bytes);
    }

    /// Flips one bit in every `n`-th streamed record (`None`: stop corrupting).
    pub fn corrupt_every(&self, n: Option<u64>) {
        lock(&self.control).corrupt_every = n.filter(|&n| n > 0);
    }

    /// Flips one bit in each streamed record with probability `p` (0 ≤ p ≤ 1; `None` or 0:
    /// stop), drawn from a generator seeded with `seed` (the same seed corrupts the same
    /// records).
    pub fn corrupt_randomly(&self, p: Option<f64>, seed: u64) {
        lock(&self.control).corrupt_probability = p
            .filter(|p| p.is_finite() && *p > 0.0)
            .map(|p| (p.min(1.0), ChaCha8Rng::seed_from_u64(seed)));
    }

    /// Garbles the device's answer to the next `command` byte the host sends: the answer's
    /// first byte is XORed with `mask` (a header made unrecognisable, a phasing bit lost).
    /// Several calls queue several answers to garble.
    pub fn garble_answer_to(&self, command: u8, mask: u8) {
        lock(&self.control).garble.push((command, mask));
    }

    /// Answers garbled so far ([`PtyEmulator::garble_answer_to`]).
    pub fn answers_garbled(&self) -> u64 {
        lock(&self.control).answers_garbled
    }

    /// Every byte the host has sent so far.
    pub fn received(&self) -> Vec<u8> {
        lock(&self.control).received.clone()
    }

    /// Records streamed so far (not counting answers to polls).
    pub fn records_sent(&self) -> u64 {
        lock(&self.control).records
    }

    /// Bytes the host side did not take in time (dropped as on an overrun line).
    pub fn dropped_bytes(&self) -> u64 {
        lock(&self.control).dropped_bytes
    }

    /// How many ptys have been opened (1 + replugs that took effect).
    pub fn ptys_opened(&self) -> u64 {
        lock(&self.control).ptys_opened
    }
}

impl Drop for PtyEmulator {
    fn drop(&mut self) {
        lock(&self.control).stop = true;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// With random corruption on, whether to flip a bit of a record of `len` bytes, and which
/// (bit index `8·byte + bit`). A seeded ChaCha8 stream: a fixed seed gives the same flips.
fn random_flip(control: &Mutex<Control>, len: usize) -> Option<usize> {
    let mut c = lock(control);
    let (p, rng) = c.corrupt_probability.as_mut()?;
    let draw = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let bit = (rng.next_u64() % (8 * len as u64).max(1)) as usize;
    (draw < *p).then_some(bit)
}

fn run(mut model: impl DeviceModel, mut pty: Option<Pty>, link: &Path, control: &Mutex<Control>) {
    let mut buf = [0u8; 512];
    let mut reply = Vec::new();
    let mut record = Vec::new();
    let mut next_due = Instant::now();
    let mut streamed: u64 = 0;
    loop {
        let (silent, unplugged, inject, corrupt_every) = {
            let mut c = lock(control);
            if c.stop {
                return;
            }
            (
                c.silent,
                c.unplugged,
                std::mem::take(&mut c.inject),
                c.corrupt_every,
            )
        };
        if unplugged {
            if pty.take().is_some() {
                let _ = std::fs::remove_file(link);
            }
            std::thread::sleep(Duration::from_millis(2));
            continue;
        }
        let p = match &mut pty {
            Some(p) => p,
            None => {
                match open_pty().and_then(|(p, target)| point_link(link, &target).map(|()| p)) {
                    Ok(p) => {
                        lock(control).ptys_opened += 1;
                        pty.insert(p)
                    }
                    Err(_) => {
                        std::thread::sleep(Duration::from_millis(10));
                        continue;
                    }
                }
            }
        };
        let now = Instant::now();
        let streaming = model.streaming() && !silent;
        if !streaming {
            next_due = now;
        }
        let wait_ms = if streaming {
            next_due.saturating_duration_since(now).as_millis().min(5) as i32
        } else {
            5
        };
        let mut fds = [PollFd::new(p.master.as_raw_fd(), PollFlags::POLLIN)];
        let _ = poll(&mut fds, wait_ms);
        reply.clear();
        loop {
            match p.master.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    let mut c = lock(control);
                    c.received.extend_from_slice(&buf[..n]);
                    if !silent {
                        // Byte by byte, so an answer can be told apart from the others.
                        for &b in &buf[..n] {
                            let before = reply.len();
                            model.receive(&[b], &mut reply);
                            if reply.len() > before
                                && let Some(i) = c.garble.iter().position(|g| g.0 == b)
                            {
                                let (_, mask) = c.garble.remove(i);
                                reply[before] ^= mask;
                                c.answers_garbled += 1;
                            }
                        }
                    }
                }
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => break,
            }
        }
        if !inject.is_empty() {
            write_all_or_drop(&mut p.master, &inject, control);
        }
        if !reply.is_empty() {
            write_all_or_drop(&mut p.master, &reply, control);
        }
        let now = Instant::now();
        if model.streaming() && !silent && now >= next_due {
            record.clear();
            model.next_record(&mut record);
            streamed += 1;
            if let Some(n) = corrupt_every
                && streamed.is_multiple_of(n)
                && !record.is_empty()
            {
                let i = (streamed as usize * 7) % record.len();
                record[i] ^= 1 << (streamed % 8);
            }
            if !record.is_empty()
                && let Some(flip) = random_flip(control, record.len())
            {
                record[flip / 8] ^= 1 << (flip % 8);
            }
            write_all_or_drop(&mut p.master, &record, control);
            lock(control).records += 1;
            next_due += model.period();
            if next_due + 2 * model.period() < now {
                next_due = now + model.period();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flips(p: f64, seed: u64, len: usize, n: usize) -> Vec<Option<usize>> {
        let control = Mutex::new(Control {
            corrupt_probability: Some((p, ChaCha8Rng::seed_from_u64(seed))),
            ..Control::default()
        });
        (0..n).map(|_| random_flip(&control, len)).collect()
    }

    #[test]
    fn random_corruption_is_seeded_and_flips_a_bit_of_the_record() {
        // Always: every record gets one bit flipped, inside it.
        let all = flips(1.0, 7, 12, 500);
        assert!(all.iter().all(|b| b.is_some_and(|b| b < 8 * 12)), "{all:?}");
        // The same seed, the same flips; another seed, others.
        assert_eq!(all, flips(1.0, 7, 12, 500));
        assert_ne!(all, flips(1.0, 8, 12, 500));
        // About the probability asked for.
        let some = flips(0.2, 7, 12, 5000).iter().flatten().count();
        assert!((800..1200).contains(&some), "{some} of 5000");
        // Off: nothing.
        let control = Mutex::new(Control::default());
        assert_eq!(random_flip(&control, 12), None);
    }
}
