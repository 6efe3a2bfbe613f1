//! The clutch (rule 10 of the hand loop): the clutch key in the frames' buttons, or a fist,
//! moves the hand without touching the clay — measured on the surface itself; a part in the
//! clay when the clutch lets go presses only after it has come out and gone back in; none of
//! the shipped traces makes a fist.

use nendo::hand::hand_loop::clutch::{FIST_CLOSE, FIST_OPEN};
use nendo::hand::{FingerModel, Hand, HandOptions, HandSession, LoopStats};
use nendo::surface::{Grid, Primitive, PrimitiveParams, Regulation, deviation};
use nendo_devices::{HandFrame, Joint, Trace, buttons};
use std::path::Path;

fn trace(name: &str) -> Trace {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces")
        .join(format!("{name}.trace"));
    Trace::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn run(
    trace: &Trace,
    frames: &[HandFrame],
    start: &Grid,
    finger: FingerModel,
) -> (Grid, LoopStats) {
    let hand = Hand::new(trace.header.hand, trace.header.world_from_tracker).unwrap();
    let options = HandOptions {
        finger,
        ..HandOptions::default()
    };
    let mut s = HandSession::new(start.clone(), Regulation::default(), hand, options).unwrap();
    for f in frames {
        s.feed(f);
    }
    s.finish();
    let st = *s.hand_loop().stats();
    (s.into_grid(), st)
}

/// The highest `|z|` of the plane, every patch sampled 20 × 20.
fn height(g: &Grid) -> f64 {
    deviation::sample_iter(g, 20).fold(0.0, |m, p| m.max(p.z.abs()))
}

/// The four fingers' MCP and PIP bent to `phi` (a fist at `FIST_CLOSE` and above).
fn fist(f: &mut HandFrame, phi: f64) {
    if let Some(j) = &mut f.joints {
        for joint in [
            Joint::IndexMcp,
            Joint::IndexPip,
            Joint::MiddleMcp,
            Joint::MiddlePip,
            Joint::RingMcp,
            Joint::RingPip,
            Joint::PinkyMcp,
            Joint::PinkyPip,
        ] {
            j.set(joint, phi).unwrap();
        }
    }
}

/// The shipped groove (the index 0.3 into the plane) with every finger: untouched while the
/// clutch key is held all along, and while the hand makes a fist all along; the same groove
/// as without the clutch when the key is held only before the hand comes near.
#[test]
fn the_clutch_key_or_a_fist_moves_the_hand_without_touching() {
    let t = trace("plane-groove");
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let all = FingerModel::for_profile_name(t.header.profile.as_deref());
    let (free, st) = run(&t, &t.frames, &plane, all);
    assert!(height(&free) > 0.25, "the groove: {}", height(&free));
    assert_eq!(st.clutched, 0);
    // Every frame with a hand is held off the clay (and none acts).
    let with_hand = st.frames_with_finger;
    assert!(with_hand > 0);

    let mut keyed = t.frames.clone();
    for f in &mut keyed {
        f.buttons |= buttons::CLUTCH;
    }
    let (g, st) = run(&t, &keyed, &plane, all);
    println!(
        "plane-groove, the clutch key held: height {}; {st:?}",
        height(&g)
    );
    assert_eq!(g, plane, "the clutch key held: the plane untouched");
    assert_eq!(
        (st.contacts, st.clutched, st.frames_with_finger),
        (0, with_hand, 0)
    );

    let mut fisted = t.frames.clone();
    for f in &mut fisted {
        fist(f, FIST_CLOSE + 0.2);
    }
    let (g, st) = run(&t, &fisted, &plane, all);
    println!("plane-groove in a fist: height {}; {st:?}", height(&g));
    assert_eq!(g, plane, "a fist: the plane untouched");
    assert_eq!(st.contacts, 0);

    // The first frame held only: the hand was far above the plane then.
    let mut first = t.frames.clone();
    first[0].buttons |= buttons::CLUTCH;
    let (g, _) = run(&t, &first, &plane, all);
    assert_eq!(g, free);
}

/// The clutch let go while the index is in the clay (held from the start to the middle of the
/// groove): the index did not enter the clay while the hand acted, so it does not press —
/// the plane stays flat; the clutch taken while pressing ends the contact where it was (the
/// groove up to there, no deeper).
#[test]
fn a_finger_in_the_clay_when_the_clutch_lets_go_does_not_press() {
    let t = trace("plane-groove");
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let all = FingerModel::for_profile_name(t.header.profile.as_deref());
    let (free, _) = run(&t, &t.frames, &plane, all);
    let half = t.frames.len() / 2;
    let mut frames = t.frames.clone();
    for f in &mut frames[..half] {
        f.buttons |= buttons::CLUTCH;
    }
    let (g, st) = run(&t, &frames, &plane, all);
    println!("clutch let go mid-groove: height {}; {st:?}", height(&g));
    assert!(height(&g) < 1e-9, "{}", height(&g));
    let mut frames = t.frames.clone();
    for f in &mut frames[half..] {
        f.buttons |= buttons::CLUTCH;
    }
    let (g, st) = run(&t, &frames, &plane, all);
    let (h, full) = (height(&g), height(&free));
    println!("clutch taken mid-groove: height {h} (the whole groove {full}); {st:?}");
    assert!(h > 0.25 && h <= full + 1e-9, "{h} vs {full}");
    assert_ne!(g, free, "half the groove");
}

/// The fist's hysteresis: closing needs every finger at `FIST_CLOSE`; once closed, fingers
/// eased back to between `FIST_OPEN` and `FIST_CLOSE` keep it closed; below `FIST_OPEN` it
/// opens and the hand presses again (the groove's second half, entered anew).
#[test]
fn the_fist_holds_between_its_thresholds() {
    let t = trace("plane-groove");
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let all = FingerModel::for_profile_name(t.header.profile.as_deref());
    let mid = 0.5 * (FIST_OPEN + FIST_CLOSE);
    // Between the thresholds from the start: never closed, so the hand presses as it is.
    let mut between = t.frames.clone();
    for f in &mut between {
        fist(f, mid);
    }
    let (_, st) = run(&t, &between, &plane, all);
    assert_eq!(st.clutched, 0, "{st:?}");
    // Closed for one frame, then between: held all along.
    fist(&mut between[0], FIST_CLOSE);
    let (g, st) = run(&t, &between, &plane, all);
    assert_eq!(
        (st.clutched, st.frames_with_finger),
        (st.frames, 0),
        "{st:?}"
    );
    assert_eq!(g, plane);
}

/// No shipped trace makes a fist or holds the clutch: their replays are what they were.
#[test]
fn no_shipped_trace_is_clutched() {
    for s in nendo::hand::shipped::shipped().unwrap() {
        let t = trace(s.name);
        let (_, st) = run(&t, &t.frames, &s.grid().unwrap(), s.finger);
        assert_eq!(st.clutched, 0, "{}: {st:?}", s.name);
        let all = FingerModel::for_profile_name(t.header.profile.as_deref());
        let (_, st) = run(&t, &t.frames, &s.grid().unwrap(), all);
        assert_eq!(st.clutched, 0, "{} with every finger: {st:?}", s.name);
    }
}
