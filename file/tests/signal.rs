//! A real process stopped in the middle of a write: by SIGTERM / SIGINT with a handler calling
//! `remove_live_temporaries` (nothing left), and by SIGKILL (a stale temporary, which the next
//! write removes).
//!
//! The child is this test binary itself, running the ignored `child_writer` test.

use std::fs;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use nendo_file::{AtomicFile, remove_live_temporaries, write_bytes};

const CHILD_DIR: &str = "NENDO_FILE_TEST_CHILD_DIR";

fn temporaries(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".nendo-tmp-"))
        .collect()
}

/// Starts the child writing `dir/out.bin` and waits until its temporary exists.
fn start_child(dir: &Path) -> Child {
    let exe = std::env::current_exe().expect("test binary");
    let mut child = Command::new(exe)
        .args([
            "--exact",
            "child_writer",
            "--ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD_DIR, dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("spawn the child");
    let stdout = child.stdout.take().expect("stdout");
    let ready = BufReader::new(stdout)
        .lines()
        .map_while(Result::ok)
        .any(|l| l.trim_end().ends_with("writing"));
    assert!(ready, "the child never started writing");
    assert_eq!(temporaries(dir).len(), 1, "one temporary while writing");
    child
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill")
        .args([format!("-{name}"), child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(status.success());
}

#[test]
fn sigterm_and_sigint_remove_the_live_temporary() {
    for name in ["TERM", "INT"] {
        let dir = tempfile::tempdir().expect("temp dir");
        fs::write(dir.path().join("out.bin"), "old").expect("seed");
        let mut child = start_child(dir.path());
        signal(&child, name);
        let status = child.wait().expect("wait");
        assert_eq!(status.code(), Some(130), "SIG{name}: {status:?}");
        assert!(temporaries(dir.path()).is_empty(), "SIG{name}");
        assert_eq!(fs::read(dir.path().join("out.bin")).expect("read"), b"old");
    }
}

#[test]
fn a_killed_writer_leaves_a_stale_temporary_that_the_next_write_removes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut child = start_child(dir.path());
    child.kill().expect("SIGKILL");
    child.wait().expect("wait");
    assert_eq!(temporaries(dir.path()).len(), 1, "SIGKILL runs no handler");
    write_bytes(dir.path().join("out.bin"), b"next").expect("next write");
    assert!(temporaries(dir.path()).is_empty());
    assert_eq!(fs::read(dir.path().join("out.bin")).expect("read"), b"next");
}

/// The child: a handler as a binary installs it, then a write that never ends.
#[test]
#[ignore = "run as a child process by the tests above"]
fn child_writer() {
    let Some(dir) = std::env::var_os(CHILD_DIR) else {
        panic!("{CHILD_DIR} is not set: this test only runs as a child of the others");
    };
    ctrlc::set_handler(|| {
        remove_live_temporaries();
        std::process::exit(130);
    })
    .expect("handler");
    let mut file = AtomicFile::create(Path::new(&dir).join("out.bin")).expect("create");
    file.write_all(&[1; 1 << 16]).expect("write");
    file.flush().expect("flush");
    println!("writing");
    std::io::stdout().flush().expect("stdout");
    for _ in 0..600 {
        file.write_all(&[2; 1024]).expect("write");
        std::thread::sleep(Duration::from_millis(100));
    }
    std::process::exit(3);
}
