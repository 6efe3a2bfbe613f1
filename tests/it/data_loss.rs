//! Nothing of the user's is lost (issue 28, data loss items 1–4): an autosave path holds an
//! autosave or nothing and is never the open document; every orphaned autosave slot is
//! offered; a save from the window notices a file changed on disk and asks; concurrent
//! `sculpt --model m --out m` runs take turns; a corrupt settings file is kept as `.bad`.

use crate::support::{nendo, temp_dir};
use glam::DVec3;
use nendo::editor::autosave::Autosave;
use nendo::editor::command::{Command, DialogPurpose};
use nendo::editor::lifecycle::{ConflictAnswer, Pending, Prompt, UnsavedAnswer};
use nendo::editor::{Document, Modeller};
use nendo::model::Model;
use nendo::surface::{Op, Primitive, PrimitiveParams};
use std::path::{Path, PathBuf};
use std::process::{Child, Output, Stdio};
use std::time::{Duration, Instant};

fn plane() -> Model {
    Model::new(
        Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane"),
    )
}

fn push(x: f64, y: f64) -> Op {
    Op::Push {
        at: DVec3::new(x, y, 0.0),
        dir: -DVec3::Z,
        depth: 0.3,
        radius: 1.0,
    }
}

fn pushed(x: f64, y: f64) -> Model {
    let mut doc = Document::new(plane());
    doc.apply(&push(x, y)).expect("push");
    doc.model().clone()
}

/// Waits for `child` (a hang guard, not a timing assertion) and returns what it printed.
fn wait(child: Child) -> Output {
    let id = child.id();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(child.wait_with_output());
    });
    match rx.recv_timeout(Duration::from_secs(120)) {
        Ok(out) => out.expect("nendo ends"),
        Err(_) => {
            let _ = std::process::Command::new("kill")
                .args(["-9", &id.to_string()])
                .status();
            panic!("nendo (pid {id}) did not end within two minutes");
        }
    }
}

/// The window started with no display at all: it must refuse the autosave path before it
/// tries to open a window.
fn window(dir: &Path, args: &[&Path]) -> Output {
    let child = nendo()
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("XDG_CONFIG_HOME", dir.join("config"))
        .env("XDG_STATE_HOME", dir.join("state"))
        .env("XDG_RUNTIME_DIR", dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("nendo runs");
    wait(child)
}

/// `nendo m.json --autosave m.json` and `--autosave notes.txt` are refused with a clear
/// error, before anything is written; the files stay as they were.
#[test]
fn an_autosave_path_holding_something_else_is_refused() {
    let dir = temp_dir("autosave-path");
    let model = dir.join("m.json");
    pushed(0.5, 0.5).write(&model).expect("model");
    let before = std::fs::read(&model).expect("read");
    let out = window(&dir, &[&model, Path::new("--autosave"), &model]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("that is the model being edited"),
        "names the problem: {err}"
    );
    assert_eq!(std::fs::read(&model).expect("read"), before);

    let notes = dir.join("notes.txt");
    std::fs::write(&notes, "my notes\n").expect("notes");
    let out = window(&dir, &[Path::new("--autosave"), &notes]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("not a nendo autosave"), "{err}");
    assert_eq!(std::fs::read_to_string(&notes).expect("read"), "my notes\n");
    // A model without the autosave header is not an autosave either.
    let other = dir.join("other.json");
    plane().write(&other).expect("model");
    let out = window(&dir, &[Path::new("--autosave"), &other]);
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("not a nendo autosave"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Headless, the same paths: edits are autosaved elsewhere (never over the model or the
/// notes), and "Quit without saving" removes neither.
#[test]
fn quit_without_saving_never_removes_a_file_that_is_not_an_autosave() {
    let dir = temp_dir("autosave-keep");
    let model = dir.join("m.json");
    pushed(0.5, 0.5).write(&model).expect("model");
    let notes = dir.join("notes.txt");
    std::fs::write(&notes, "my notes\n").expect("notes");
    let before = std::fs::read(&model).expect("read");
    for (doc, autosave) in [
        (Document::open(&model).expect("open"), model.clone()),
        (Document::new(plane()), notes.clone()),
    ] {
        let mut m = Modeller::new(doc, Some(autosave.clone()), true);
        assert_eq!(m.session().prompt(), None, "nothing to recover");
        assert_ne!(
            m.session().autosave().map(Autosave::path),
            Some(autosave.as_path()),
            "the slot holding another file is passed over"
        );
        m.devices_mut().1.apply(&push(-1.0, -1.0)).expect("edit");
        let t0 = Instant::now();
        m.tick(t0);
        m.tick(t0 + Autosave::SETTLE * 2);
        m.tick(t0 + Autosave::INTERVAL * 3);
        m.request_close();
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Discard));
        assert!(m.wants_to_quit());
        m.on_exit();
        assert_eq!(std::fs::read(&model).expect("the model is there"), before);
        assert_eq!(
            std::fs::read_to_string(&notes).expect("the notes are there"),
            "my notes\n"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Slot `k` of an autosave base path, as the window names them.
fn slot(base: &Path, k: usize) -> PathBuf {
    if k == 1 {
        base.to_path_buf()
    } else {
        base.with_file_name(format!("autosave-{k}.nendo.json"))
    }
}

fn write_autosave(model: &Model, path: &Path) {
    let mut a = Autosave::new(path.to_path_buf());
    a.write_now(model, 1);
    assert_eq!(a.last_error, None);
}

/// Killed windows left autosaves in slots 1, 2 and 5: the next window offers each in turn;
/// recovering one from another slot moves it into the window's own slot. A running window's
/// slot is never offered.
#[test]
fn every_orphaned_autosave_slot_is_offered() {
    let dir = temp_dir("orphans");
    let base = dir.join("autosave.nendo.json");
    let models = [pushed(0.5, 0.5), pushed(-0.5, 0.5), pushed(0.5, -0.5)];
    for (k, model) in [1, 2, 5].into_iter().zip(&models) {
        write_autosave(model, &slot(&base, k));
    }
    let mut m = Modeller::new(Document::new(plane()), Some(base.clone()), true);
    assert_eq!(m.session().prompt(), Some(Prompt::Recover(base.clone())));
    m.apply(Command::DiscardRecovery);
    assert!(!base.exists(), "declined: removed");
    assert_eq!(
        m.session().prompt(),
        Some(Prompt::Recover(slot(&base, 2))),
        "slot 2 is offered next"
    );
    m.apply(Command::DiscardRecovery);
    assert_eq!(m.session().prompt(), Some(Prompt::Recover(slot(&base, 5))));
    m.apply(Command::Recover(slot(&base, 5)));
    assert_eq!(m.document().model(), &models[2]);
    assert!(m.document().is_dirty());
    assert!(!slot(&base, 5).exists(), "moved into this window's slot");
    assert_eq!(
        Model::read(&base).expect("own slot").model,
        models[2],
        "the recovered work is in this window's autosave"
    );
    assert_eq!(m.session().prompt(), None);

    // A second window runs (slot 2) with unsaved work in its autosave; a third window starts:
    // it takes slot 3 and is not offered the running window's work.
    let mut second = Modeller::new(Document::new(plane()), Some(base.clone()), true);
    assert_eq!(
        second.session().autosave().map(Autosave::path),
        Some(slot(&base, 2).as_path())
    );
    second.devices_mut().1.apply(&push(0.0, 0.0)).expect("edit");
    let t0 = Instant::now();
    second.tick(t0);
    second.tick(t0 + Autosave::SETTLE * 2);
    assert!(slot(&base, 2).is_file());
    let third = Modeller::new(Document::new(plane()), Some(base.clone()), true);
    assert_eq!(third.session().prompt(), None, "a live window's slot");
    drop((third, second, m));

    // Both windows killed (dropped without on_exit): the next start offers both, own slot
    // first, and one recovery leaves the other in place for the start after.
    let mut next = Modeller::new(Document::new(plane()), Some(base.clone()), true);
    assert_eq!(next.session().prompt(), Some(Prompt::Recover(base.clone())));
    next.apply(Command::Recover(base.clone()));
    assert_eq!(next.session().prompt(), None);
    assert!(slot(&base, 2).is_file(), "kept for the next start");
    let status = next.status().expect("a status").text.clone();
    assert!(status.contains("1 more autosave"), "{status}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A save to the document's own file that another program changed since it was opened asks
/// (overwrite / save as / reload / cancel) instead of overwriting it.
#[test]
fn save_asks_when_the_file_changed_on_disk() {
    let dir = temp_dir("conflict");
    let file = dir.join("m.json");
    plane().write(&file).expect("model");
    let mut m = Modeller::new(Document::open(&file).expect("open"), None, false);
    m.devices_mut().1.apply(&push(0.5, 0.5)).expect("edit");
    let mine = m.document().model().clone();

    // Another program (here `nendo sculpt --model m --out m`) changes the file.
    let ops = dir.join("ops.jsonl");
    std::fs::write(
        &ops,
        "{\"op\":\"push\",\"at\":[-0.5,-0.5,0],\"dir\":[0,0,-1],\"depth\":0.3,\"radius\":1}\n",
    )
    .expect("ops");
    let out = nendo()
        .arg("sculpt")
        .arg("--model")
        .arg(&file)
        .arg("--ops")
        .arg(&ops)
        .arg("--out")
        .arg(&file)
        .output()
        .expect("sculpt");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs = std::fs::read(&file).expect("read");

    m.apply(Command::Save);
    assert_eq!(
        m.session().prompt(),
        Some(Prompt::ChangedOnDisk(file.clone())),
        "the save asks"
    );
    assert_eq!(
        std::fs::read(&file).expect("read"),
        theirs,
        "nothing written"
    );
    assert!(m.document().is_dirty());
    m.apply(Command::AnswerConflict(ConflictAnswer::Cancel));
    assert_eq!(m.session().prompt(), None);
    assert_eq!(std::fs::read(&file).expect("read"), theirs);

    // Save as: the dialog, another file; the changed file is left alone.
    m.apply(Command::Save);
    m.apply(Command::AnswerConflict(ConflictAnswer::SaveAs));
    assert!(m.file_request().is_some(), "the save dialog");
    let copy = dir.join("mine.json");
    m.apply(Command::DialogChosen(
        DialogPurpose::SaveModel,
        copy.clone(),
    ));
    assert_eq!(Model::read(&copy).expect("saved").model, mine);
    assert_eq!(std::fs::read(&file).expect("read"), theirs);

    // Reload: the file as it is now, the edits dropped.
    let mut m = Modeller::new(Document::open(&copy).expect("open"), None, false);
    m.devices_mut().1.apply(&push(1.0, 1.0)).expect("edit");
    plane().write(&copy).expect("changed by someone else");
    m.apply(Command::Save);
    assert_eq!(
        m.session().prompt(),
        Some(Prompt::ChangedOnDisk(copy.clone()))
    );
    m.apply(Command::AnswerConflict(ConflictAnswer::Reload));
    assert_eq!(m.document().model(), &plane());
    assert!(!m.document().is_dirty());

    // Overwrite, with Close waiting on the save: saved, then the window closes.
    m.devices_mut().1.apply(&push(1.0, 1.0)).expect("edit");
    let edited = m.document().model().clone();
    pushed(0.0, 0.0).write(&copy).expect("changed again");
    m.request_close();
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
    assert_eq!(
        m.session().prompt(),
        Some(Prompt::ChangedOnDisk(copy.clone()))
    );
    assert!(!m.wants_to_quit());
    assert_eq!(m.session().lifecycle().waiting(), Some(&Pending::Close));
    m.apply(Command::AnswerConflict(ConflictAnswer::Overwrite));
    assert_eq!(Model::read(&copy).expect("saved").model, edited);
    assert!(m.wants_to_quit());

    // A file saved here and not changed since saves again without a question.
    let mut m = Modeller::new(Document::open(&copy).expect("open"), None, false);
    m.devices_mut().1.apply(&push(0.5, 0.5)).expect("edit");
    m.apply(Command::Save);
    m.devices_mut().1.apply(&push(-0.5, 0.5)).expect("edit");
    m.apply(Command::Save);
    assert_eq!(m.session().prompt(), None);
    assert_eq!(
        Model::read(&copy).expect("saved").model,
        *m.document().model()
    );
    // Work recovered from a killed window's autosave remembers what its file held: saving it
    // over the file changed since asks too.
    let base = dir.join("state").join("autosave.nendo.json");
    let mut killed = Modeller::new(
        Document::open(&copy).expect("open"),
        Some(base.clone()),
        true,
    );
    killed.devices_mut().1.apply(&push(0.5, 0.5)).expect("edit");
    let t0 = Instant::now();
    killed.tick(t0);
    killed.tick(t0 + Autosave::SETTLE * 2);
    drop(killed);
    plane().write(&copy).expect("changed after the crash");
    let mut m = Modeller::new(Document::new(plane()), Some(base.clone()), true);
    m.apply(Command::Recover(base.clone()));
    assert_eq!(m.document().path.as_deref(), Some(copy.as_path()));
    m.apply(Command::Save);
    assert_eq!(
        m.session().prompt(),
        Some(Prompt::ChangedOnDisk(copy.clone()))
    );
    assert_eq!(Model::read(&copy).expect("untouched").model, plane());
    let _ = std::fs::remove_dir_all(&dir);
}

/// 40 pairs of `nendo sculpt --model m --ops X --out m` run at once: each file ends with both
/// updates (in either order), or one run failed with a clear error and the file holds the
/// other's.
#[test]
fn concurrent_sculpts_on_one_file_keep_every_update() {
    let dir = temp_dir("sculpt-pairs");
    let base = dir.join("base.json");
    plane().write(&base).expect("base");
    let a = dir.join("a.jsonl");
    let b = dir.join("b.jsonl");
    std::fs::write(
        &a,
        "{\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[0,0,-1],\"depth\":0.3,\"radius\":1}\n",
    )
    .expect("a");
    std::fs::write(
        &b,
        "{\"op\":\"push\",\"at\":[-0.5,-0.5,0],\"dir\":[0,0,1],\"depth\":0.2,\"radius\":1}\n",
    )
    .expect("b");
    let sculpt = |model: &Path, ops: &Path, out: &Path| {
        nendo()
            .arg("sculpt")
            .arg("--model")
            .arg(model)
            .arg("--ops")
            .arg(ops)
            .arg("--out")
            .arg(out)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("sculpt runs")
    };
    let done = |child: Child| {
        let out = wait(child);
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let read = |p: &Path| Model::read(p).expect("a model").model;
    // The results of one run and of both in either order.
    let only = |ops: &Path, name: &str| {
        let out = dir.join(name);
        assert!(done(sculpt(&base, ops, &out)).0);
        out
    };
    let (only_a, only_b) = (only(&a, "only-a.json"), only(&b, "only-b.json"));
    let ab = dir.join("ab.json");
    assert!(done(sculpt(&only_a, &b, &ab)).0);
    let ba = dir.join("ba.json");
    assert!(done(sculpt(&only_b, &a, &ba)).0);
    let (only_a, only_b, ab, ba) = (read(&only_a), read(&only_b), read(&ab), read(&ba));
    assert_ne!(only_a, ab);
    assert_ne!(only_b, ba);

    let mut both = 0;
    for pair in 0..40 {
        let m = dir.join(format!("m{pair}.json"));
        std::fs::copy(&base, &m).expect("copy");
        let first = sculpt(&m, &a, &m);
        let second = sculpt(&m, &b, &m);
        let (ok_a, err_a) = done(first);
        let (ok_b, err_b) = done(second);
        let result = read(&m);
        match (ok_a, ok_b) {
            (true, true) => {
                assert!(
                    result == ab || result == ba,
                    "pair {pair}: an update was lost"
                );
                both += 1;
            }
            (true, false) => {
                assert!(err_b.contains("another nendo is writing"), "{err_b}");
                assert_eq!(result, only_a, "pair {pair}");
            }
            (false, true) => {
                assert!(err_a.contains("another nendo is writing"), "{err_a}");
                assert_eq!(result, only_b, "pair {pair}");
            }
            (false, false) => panic!("pair {pair}: both failed: {err_a} / {err_b}"),
        }
        assert!(
            !dir.join(format!(".m{pair}.json.nendo-lock")).exists(),
            "no lock file left"
        );
    }
    eprintln!("concurrent sculpt pairs: {both} of 40 kept both updates, the rest failed clearly");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A settings file with one syntax error is kept as `settings.json.bad` before the defaults
/// are written over it, and the window says so.
#[test]
fn a_corrupt_settings_file_is_kept_as_bad() {
    let dir = temp_dir("settings-bad");
    let path = dir.join("settings.json");
    let broken = "{\"format\":\"nendo-settings\",\"version\":1,\"orbit\":\"middle\",\
                  \"record_folder\":\"/home/me/traces\",}\n";
    std::fs::write(&path, broken).expect("settings");
    let mut m =
        Modeller::new(Document::new(plane()), None, false).with_settings(Some(path.clone()));
    let bad = dir.join("settings.json.bad");
    let status = m.status().expect("a warning").clone();
    assert!(status.error);
    assert!(
        status.text.contains(&bad.display().to_string()),
        "the window names the kept copy: {}",
        status.text
    );
    // A change writes the settings: the defaults and the change, the broken file kept.
    m.set_orbit_button(nendo::editor::input::OrbitButton::Middle);
    m.remember_settings();
    m.set_orbit_button(nendo::editor::input::OrbitButton::Right);
    m.remember_settings();
    assert!(path.is_file(), "settings written");
    assert_eq!(std::fs::read_to_string(&bad).expect("kept"), broken);
    let _ = std::fs::remove_dir_all(&dir);
}
