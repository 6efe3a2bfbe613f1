//! The writer's guarantees, one test each (Unix).

use std::fs;
use std::io::Write;
use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::path::Path;

use nendo_file::{AtomicFile, WriteError, write_atomic, write_bytes};

/// The names in `dir` that look like temporaries of any target.
fn temporaries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .expect("list the directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".nendo-tmp-"))
        .collect();
    names.sort();
    names
}

fn mode(path: &Path) -> u32 {
    fs::metadata(path).expect("metadata").permissions().mode() & 0o7777
}

#[test]
fn the_temporary_is_beside_the_target_and_named_after_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("out.txt");
    let mut file = AtomicFile::create(&target).expect("create");
    file.write_all(b"hello").expect("write");
    file.flush().expect("flush");
    let temps = temporaries(dir.path());
    assert_eq!(temps.len(), 1, "{temps:?}");
    assert!(temps[0].starts_with(".out.txt.nendo-tmp-"), "{temps:?}");
    assert_eq!(temps[0].len(), ".out.txt.nendo-tmp-".len() + 6);
    assert_eq!(
        file.temporary_path().and_then(Path::parent),
        Some(dir.path())
    );
    assert!(!target.exists(), "nothing at the target before commit");
    file.commit().expect("commit");
    assert_eq!(fs::read(&target).expect("read"), b"hello");
    assert!(temporaries(dir.path()).is_empty());
}

#[test]
fn commit_replaces_an_existing_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("m.json");
    fs::write(&target, "old contents, longer than the new").expect("seed");
    write_bytes(&target, b"new").expect("write");
    assert_eq!(fs::read(&target).expect("read"), b"new");
    assert!(temporaries(dir.path()).is_empty());
}

#[test]
fn a_symbolic_link_is_written_through_and_stays_a_link() {
    let dir = tempfile::tempdir().expect("temp dir");
    let real_dir = dir.path().join("real");
    fs::create_dir(&real_dir).expect("mkdir");
    let real = real_dir.join("model.json");
    fs::write(&real, "old").expect("seed");
    let link = dir.path().join("link.json");
    // A relative link, resolved against the link's directory; and a link to that link.
    std::os::unix::fs::symlink("real/model.json", &link).expect("symlink");
    let link2 = dir.path().join("link2.json");
    std::os::unix::fs::symlink(&link, &link2).expect("symlink");
    write_bytes(&link2, b"new").expect("write");
    assert!(
        fs::symlink_metadata(&link)
            .expect("lstat")
            .file_type()
            .is_symlink()
    );
    assert!(
        fs::symlink_metadata(&link2)
            .expect("lstat")
            .file_type()
            .is_symlink()
    );
    assert_eq!(fs::read(&real).expect("read"), b"new");
    // The temporary was made beside the real file, and is gone.
    assert!(temporaries(&real_dir).is_empty());
    assert!(temporaries(dir.path()).is_empty());

    // A dangling link gets its file created.
    let dangling = dir.path().join("dangling");
    std::os::unix::fs::symlink("real/new.json", &dangling).expect("symlink");
    write_bytes(&dangling, b"created").expect("write");
    assert_eq!(
        fs::read(real_dir.join("new.json")).expect("read"),
        b"created"
    );
    assert!(
        fs::symlink_metadata(&dangling)
            .expect("lstat")
            .file_type()
            .is_symlink()
    );
}

#[test]
fn symbolic_link_loops_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let a = dir.path().join("a");
    std::os::unix::fs::symlink("b", &a).expect("symlink");
    std::os::unix::fs::symlink("a", dir.path().join("b")).expect("symlink");
    assert!(matches!(
        write_bytes(&a, b"x"),
        Err(WriteError::SymlinkLoop { .. })
    ));
}

#[test]
fn permissions_of_a_replaced_file_are_kept() {
    let dir = tempfile::tempdir().expect("temp dir");
    for bits in [0o600, 0o640, 0o755, 0o444] {
        let target = dir.path().join(format!("f{bits:o}"));
        fs::write(&target, "old").expect("seed");
        fs::set_permissions(&target, fs::Permissions::from_mode(bits)).expect("chmod");
        write_bytes(&target, b"new").expect("write");
        assert_eq!(mode(&target), bits, "{bits:o}");
        assert_eq!(fs::read(&target).expect("read"), b"new");
    }
}

#[test]
fn a_new_file_gets_the_default_permissions() {
    let dir = tempfile::tempdir().expect("temp dir");
    // What `File::create` gives under this process's umask.
    let reference = dir.path().join("reference");
    fs::File::create(&reference).expect("create");
    let target = dir.path().join("new");
    write_bytes(&target, b"x").expect("write");
    assert_eq!(mode(&target), mode(&reference));
}

#[test]
fn anything_but_a_regular_file_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().expect("temp dir");
    // A directory.
    let sub = dir.path().join("sub");
    fs::create_dir(&sub).expect("mkdir");
    let e = write_bytes(&sub, b"x").expect_err("a directory");
    assert!(matches!(e, WriteError::IsDirectory { .. }), "{e}");
    assert!(sub.is_dir());
    // A symbolic link to a directory.
    let to_sub = dir.path().join("to_sub");
    std::os::unix::fs::symlink(&sub, &to_sub).expect("symlink");
    assert!(matches!(
        write_bytes(&to_sub, b"x"),
        Err(WriteError::IsDirectory { .. })
    ));
    // A fifo.
    let fifo = dir.path().join("fifo");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("run mkfifo");
    assert!(made.success());
    let e = write_bytes(&fifo, b"x").expect_err("a fifo");
    assert!(matches!(e, WriteError::NotRegularFile { .. }), "{e}");
    assert!(
        fs::symlink_metadata(&fifo)
            .expect("lstat")
            .file_type()
            .is_fifo()
    );
    // A socket.
    let socket = dir.path().join("socket");
    let _listener = std::os::unix::net::UnixListener::bind(&socket).expect("bind");
    assert!(matches!(
        write_bytes(&socket, b"x"),
        Err(WriteError::NotRegularFile { .. })
    ));
    assert!(
        fs::symlink_metadata(&socket)
            .expect("lstat")
            .file_type()
            .is_socket()
    );
    // A device (through a link, so nothing beside /dev is tried).
    let null = dir.path().join("null");
    std::os::unix::fs::symlink("/dev/null", &null).expect("symlink");
    assert!(matches!(
        AtomicFile::create(&null),
        Err(WriteError::NotRegularFile { .. })
    ));
    assert!(
        fs::metadata("/dev/null")
            .expect("stat")
            .file_type()
            .is_char_device()
    );
    assert!(temporaries(dir.path()).is_empty());
}

#[test]
fn errors_name_the_target_once() {
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("no-such-dir").join("out.json");
    let e = write_bytes(&missing, b"x").expect_err("no directory");
    assert!(matches!(e, WriteError::Io { .. }));
    assert_eq!(e.path(), missing);
    let text = e.to_string();
    let shown = missing.display().to_string();
    assert_eq!(text.matches(&shown).count(), 1, "{text}");
    assert!(!text.contains("nendo-tmp"), "names the temporary: {text}");
    assert!(!e.into_io().to_string().contains(&shown));
}

#[test]
fn stale_temporaries_of_the_target_are_removed_by_the_next_write() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("m.json");
    // Left by a killed run: nobody holds them.
    for stale in [".m.json.nendo-tmp-abc123", ".m.json.nendo-tmp-ZZZZZZ"] {
        fs::write(dir.path().join(stale), "partial").expect("seed");
    }
    // Not this target's, or not this writer's pattern: kept.
    let others = [
        ".other.json.nendo-tmp-abc123",
        ".m.json.tmp-1234",
        "m.json.nendo-tmp-abc123",
    ];
    for other in others {
        fs::write(dir.path().join(other), "keep").expect("seed");
    }
    write_bytes(&target, b"new").expect("write");
    assert_eq!(
        temporaries(dir.path()),
        vec![
            ".other.json.nendo-tmp-abc123".to_string(),
            "m.json.nendo-tmp-abc123".to_string()
        ]
    );
    assert!(dir.path().join(".m.json.tmp-1234").exists());
    assert_eq!(fs::read(&target).expect("read"), b"new");
}

#[test]
fn a_live_temporary_is_not_stale() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("m.json");
    let mut first = AtomicFile::create(&target).expect("first");
    first.write_all(b"first").expect("write");
    let first_temp = first.temporary_path().expect("temp").to_path_buf();
    // A second writer of the same target sweeps, but the first one's temporary is locked.
    write_bytes(&target, b"second").expect("second");
    assert!(first_temp.exists());
    first.commit().expect("commit first");
    assert_eq!(fs::read(&target).expect("read"), b"first");
    assert!(temporaries(dir.path()).is_empty());
}

#[test]
fn the_temporary_is_removed_on_drop_and_on_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("out.bin");
    fs::write(&target, "old").expect("seed");

    // Dropped without commit.
    let mut file = AtomicFile::create(&target).expect("create");
    file.write_all(&[7; 100_000]).expect("write");
    drop(file);
    assert!(temporaries(dir.path()).is_empty());
    assert_eq!(fs::read(&target).expect("read"), b"old");

    // The writing closure fails.
    let result: Result<(), WriteError> = write_atomic(&target, |f| {
        f.write_all(b"partial").map_err(|error| WriteError::Io {
            path: f.target().to_path_buf(),
            error,
        })?;
        Err(WriteError::Io {
            path: f.target().to_path_buf(),
            error: std::io::Error::other("the encoder failed"),
        })
    });
    assert!(result.is_err());
    assert!(temporaries(dir.path()).is_empty());
    assert_eq!(fs::read(&target).expect("read"), b"old");

    // The rename fails: the target became a directory meanwhile.
    let mut file = AtomicFile::create(&target).expect("create");
    file.write_all(b"new").expect("write");
    fs::remove_file(&target).expect("rm");
    fs::create_dir(&target).expect("mkdir");
    fs::write(target.join("inside"), "x").expect("fill");
    let e = file.commit().expect_err("rename over a directory");
    assert_eq!(e.path(), target);
    assert!(temporaries(dir.path()).is_empty());
    assert!(target.is_dir());
}

#[test]
fn a_full_device_is_an_error_at_commit_or_before() {
    // /dev/full cannot be a target (refused as a device); a disk that fills up is the same
    // failure at write or flush time, which commit reports.
    assert!(matches!(
        write_bytes("/dev/full", b"x"),
        Err(WriteError::NotRegularFile { .. })
    ));
}
