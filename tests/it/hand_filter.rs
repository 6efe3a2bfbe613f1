//! The hand loop's plausibility gate and One-Euro filter (`nendo::hand::filter`) on the clay:
//! glitches that must leave no mark, jitter that must not move a resting finger, the lag on
//! recorded motions, a corrupted emulator stream recorded and replayed, and the gate's marks in
//! a trace (version 4) checked by the replay. Every surface is
//! measured on the surface itself, each patch evaluated on a 33 × 33 grid of parameters.

use glam::{DQuat, DVec3};
use nendo::hand::script::Choreography;
use nendo::hand::{Digit, FingerModel, Hand, HandOptions, HandSession};
use nendo::surface::{Grid, Primitive, PrimitiveParams, Regulation};
use nendo_devices::trace::HeldMarks;
use nendo_devices::{FilterSettings, FrameFilter, HandFrame, HandSize, Joint, Trace};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Stdio};

use crate::support::{nendo, temp_dir};

/// Samples per patch side for the dense evaluation.
const DENSE: usize = 33;

fn plane() -> Grid {
    Primitive::Plane.build(&PrimitiveParams::default()).unwrap()
}

/// Every patch of `g` evaluated on a `DENSE` × `DENSE` grid of parameters.
fn dense(g: &Grid) -> Vec<DVec3> {
    let mut out = Vec::new();
    for iu in 0..g.patches_u() {
        for iv in 0..g.patches_v() {
            for a in 0..DENSE {
                for b in 0..DENSE {
                    let (u, v) = (a as f64 / (DENSE - 1) as f64, b as f64 / (DENSE - 1) as f64);
                    out.push(g.eval(iu, iv, u, v));
                }
            }
        }
    }
    out
}

/// The largest `|z|` of the surface (the plane's height is 0).
fn max_height(g: &Grid) -> f64 {
    dense(g).iter().map(|p| p.z.abs()).fold(0.0, f64::max)
}

/// The largest distance between two surfaces of the same patches at the same parameters.
fn max_gap(a: &Grid, b: &Grid) -> f64 {
    dense(a)
        .iter()
        .zip(dense(b))
        .map(|(p, q)| (*p - q).length())
        .fold(0.0, f64::max)
}

/// A session on `start` with the index finger alone, the scripted traces' hand, `filter`.
fn session(start: &Grid, filter: FilterSettings) -> HandSession {
    let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
    let options = HandOptions {
        finger: FingerModel::digit(Digit::Index),
        ..HandOptions::default()
    };
    let mut s = HandSession::new(start.clone(), Regulation::default(), hand, options).unwrap();
    s.set_filter(filter);
    s
}

/// Replays `frames` on the plane; returns the surface and the session.
fn replay(frames: &[HandFrame], filter: FilterSettings) -> (Grid, HandSession) {
    let mut s = session(&plane(), filter);
    for f in frames {
        s.feed(f);
    }
    s.finish();
    (s.grid().clone(), s)
}

/// The index fingertip hovering one side above the plane at (0.5, 0.5), pointing down, for
/// one second at 120 Hz.
fn hovering() -> Trace {
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(0.5, 0.5, 1.0), -DVec3::Z, DVec3::Y);
    c.hold(120);
    c.finish("test").unwrap()
}

#[test]
fn a_one_sample_spike_leaves_the_plane_flat() {
    // One tracker sample 6 cm low (1.2 side at 20 sides per metre): the fingertip jumps 0.2
    // side into the plane for 8 ms.
    let mut spiked = hovering();
    let p = &mut spiked.frames[60].pose.as_mut().unwrap().position;
    p.z -= 0.06;
    let (raw, _) = replay(&spiked.frames, FilterSettings::off());
    let (filtered, s) = replay(&spiked.frames, FilterSettings::default());
    let (raw_h, filtered_h) = (max_height(&raw), max_height(&filtered));
    eprintln!("6 cm spike: dent {raw_h:.3} side unfiltered, {filtered_h:.2e} filtered");
    assert!(
        raw_h > 0.1,
        "the spike reaches the clay unfiltered: {raw_h}"
    );
    assert!(filtered_h < 0.01, "{filtered_h}");
    let st = s.hand_loop().filter().stats();
    assert_eq!(st.position.total(), 1, "{st:?}");
    assert_eq!(st.rejected(), 1);
    // Values no device layer would let through, in frames built elsewhere: NaN, 1e308,
    // infinity, a quaternion of NaN. Held, counted, and the plane untouched.
    let mut wild = hovering();
    for (k, bad) in [
        (30, f64::NAN),
        (50, 1e308),
        (70, f64::INFINITY),
        (90, -1e308),
    ] {
        wild.frames[k].pose.as_mut().unwrap().position.z = bad;
    }
    let q = &mut wild.frames[100].pose.as_mut().unwrap().orientation;
    *q = DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0);
    let (g, s) = replay(&wild.frames, FilterSettings::default());
    assert_eq!(max_height(&g), 0.0);
    let st = s.hand_loop().filter().stats();
    assert_eq!(
        (st.position.out_of_range, st.orientation.out_of_range),
        (4, 1),
        "{st:?}"
    );
}

#[test]
fn a_spike_while_the_hand_moves_leaves_no_mark() {
    // The index fingertip slides across 0.3 side above the plane at up to 0.3 m/s (6 side/s),
    // the finger leaning 45° forward. One sample of the tracker 4 cm low; one of its
    // orientation tilted by 0.3 rad either way (the fingertip swings about 0.9 side); one of
    // the index MCP 0.45 rad off either way (a flipped bit of a CyberGlove sensor).
    let axis = DVec3::new(1.0, 0.0, -1.0).normalize();
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(-3.0, 0.5, 0.3), axis, DVec3::X + DVec3::Z);
    c.hold(30);
    c.move_to(DVec3::new(3.0, 0.5, 0.3), axis, 180);
    c.hold(30);
    let trace = c.finish("test").unwrap();
    let mut cases: Vec<(&str, Vec<Trace>)> = Vec::new();
    let mut low = trace.clone();
    low.frames[80].pose.as_mut().unwrap().position.z -= 0.04;
    cases.push(("position", vec![low]));
    let tilt = |angle: f64| {
        let mut t = trace.clone();
        let pose = t.frames[120].pose.as_mut().unwrap();
        pose.orientation *= DQuat::from_axis_angle(DVec3::Y, angle);
        t
    };
    cases.push(("orientation", vec![tilt(0.3), tilt(-0.3)]));
    let curl = |by: f64| {
        let mut t = trace.clone();
        let j = t.frames[150].joints.as_mut().unwrap();
        let a = j.get(Joint::IndexMcp).unwrap();
        j.set(Joint::IndexMcp, a + by).unwrap();
        t
    };
    cases.push(("joint", vec![curl(0.45), curl(-0.45)]));
    for (what, variants) in cases {
        let mut deepest: f64 = 0.0;
        for t in variants {
            let (raw, _) = replay(&t.frames, FilterSettings::off());
            let (filtered, s) = replay(&t.frames, FilterSettings::default());
            let (raw_h, filtered_h) = (max_height(&raw), max_height(&filtered));
            eprintln!(
                "{what} spike while moving: {raw_h:.3} side unfiltered, {filtered_h:.2e} filtered"
            );
            deepest = deepest.max(raw_h);
            assert!(filtered_h < 0.01, "{what}: {filtered_h}");
            assert_eq!(s.hand_loop().filter().stats().rejected(), 1, "{what}");
        }
        assert!(
            deepest > 0.05,
            "{what}: the spike reaches the clay unfiltered: {deepest}"
        );
    }
}

#[test]
fn a_press_comes_to_rest_as_deep_as_without_the_filter() {
    // The index fingertip pressed 0.3 side into the plane in 0.2 s (up to 0.3 m/s) and held
    // for 1 s: the filtered finger goes on a little after the hand stops, and settles. When is
    // the surface within 1e-4 side (the loop's smallest depth step) of where it ends?
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(0.5, 0.5, 0.5), -DVec3::Z, DVec3::Y);
    c.move_to(DVec3::new(0.5, 0.5, -0.3), -DVec3::Z, 24);
    c.hold(120);
    let t = c.finish("test").unwrap();
    let mut settled = [0usize; 2];
    let mut last_change = [0usize; 2];
    let mut applications = [0u64; 2];
    let mut finals = Vec::new();
    for (i, filter) in [FilterSettings::off(), FilterSettings::default()]
        .into_iter()
        .enumerate()
    {
        let mut s = session(&plane(), filter);
        let mut grids = Vec::new();
        for f in &t.frames {
            s.feed(f);
            grids.push(s.grid().clone());
        }
        let last = grids.last().unwrap().clone();
        settled[i] = grids
            .iter()
            .rposition(|g| max_gap(g, &last) > 1e-4)
            .map_or(0, |k| k + 1);
        // The last frame that changed the surface at all: a press re-applied for depth
        // changes below the loop's smallest step would go on changing it long after.
        last_change[i] = grids
            .windows(2)
            .rposition(|w| w[0] != w[1])
            .map_or(0, |k| k + 1);
        applications[i] = s.hand_loop().stats().applications;
        finals.push(last);
    }
    eprintln!(
        "press held still: the surface last changed {} frames after the hand stops unfiltered, {} filtered; {applications:?} applications",
        last_change[0].saturating_sub(24),
        last_change[1].saturating_sub(24)
    );
    assert!(
        last_change[1] <= 24 + 36,
        "the filtered press stops re-applying within 0.3 s: {last_change:?}"
    );
    let gap = max_gap(&finals[0], &finals[1]);
    eprintln!(
        "press held still: the surface within 1e-4 side of its end {} frames after the hand stops unfiltered, {} filtered (120 Hz); the dents {gap:.2e} side apart",
        settled[0].saturating_sub(24),
        settled[1].saturating_sub(24)
    );
    assert!(settled[1] <= 24 + 24, "settled within 0.2 s: {settled:?}");
    assert!(gap < 2e-3, "{gap}");
}

/// A standard normal deviate (Box–Muller).
fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.gen_range(f64::EPSILON..1.0);
    let v: f64 = rng.r#gen();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

#[test]
fn jitter_does_not_move_a_resting_finger() {
    // The index fingertip comes down 0.3 side into the plane, rests there 4 s, and lifts; the
    // tracker adds 0.5 mm RMS of white noise per axis (0.01 side at 20 sides per metre).
    // Measured against the same motion without noise, through the same filter: how far the
    // loop's fingertip (the contact point) strays while resting, and how far the finished
    // surface is from the noise-free one.
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(0.5, 0.5, 0.5), -DVec3::Z, DVec3::Y);
    c.move_to(DVec3::new(0.5, 0.5, -0.3), -DVec3::Z, 60);
    c.hold(480);
    c.move_to(DVec3::new(0.5, 0.5, 0.5), -DVec3::Z, 60);
    let clean = c.finish("test").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5_0e_5e);
    let mut noisy = clean.clone();
    for f in &mut noisy.frames {
        let n = DVec3::new(gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)) * 0.5e-3;
        let pose = f.pose.as_mut().unwrap();
        pose.position = (pose.position + n)
            .to_array()
            .map(nendo_devices::trace::quantize)
            .into();
    }
    let rms = (noisy
        .frames
        .iter()
        .zip(&clean.frames)
        .map(|(a, b)| (a.pose.unwrap().position - b.pose.unwrap().position).length_squared())
        .sum::<f64>()
        / (3 * clean.frames.len()) as f64)
        .sqrt();
    assert!((rms - 0.5e-3).abs() < 0.03e-3, "{rms}");
    let mut report = Vec::new();
    for (name, filter) in [
        ("unfiltered", FilterSettings::off()),
        ("filtered", FilterSettings::default()),
    ] {
        let mut a = session(&plane(), filter);
        let mut b = session(&plane(), filter);
        let mut stray: f64 = 0.0;
        for (k, (fa, fb)) in clean.frames.iter().zip(&noisy.frames).enumerate() {
            a.feed(fa);
            b.feed(fb);
            if (120..540).contains(&k) {
                let ta = a.hand_loop().fingertip().unwrap().tip;
                let tb = b.hand_loop().fingertip().unwrap().tip;
                stray = stray.max((ta - tb).length());
            }
        }
        a.finish();
        b.finish();
        let gap = max_gap(a.grid(), b.grid());
        let placements = b.hand_loop().stats().placements;
        report.push(format!(
            "{name}: contact point strays {stray:.4} side, surface {gap:.4} side from the noise-free one, {placements} placements"
        ));
        if filter.enabled {
            assert!(stray < 0.05, "{name}: {stray}");
            assert!(gap < 0.05, "{name}: {gap}");
            assert_eq!(b.hand_loop().filter().stats().rejected(), 0);
        }
    }
    eprintln!("0.5 mm RMS of jitter at rest: {}", report.join("; "));
}

/// The fingertip of every fresh tracker frame of `trace`, raw and through the default filter,
/// for the trace's own hand (world units).
fn fingertips(trace: &Trace) -> Vec<(DVec3, DVec3)> {
    let hand = Hand::new(trace.header.hand, trace.header.world_from_tracker).unwrap();
    let options = HandOptions {
        finger: FingerModel::digit(Digit::Index),
        ..HandOptions::default()
    };
    let raw_loop = nendo::hand::HandLoop::new(hand, options).unwrap();
    let mut filter = FrameFilter::default();
    let mut out = Vec::new();
    for f in &trace.frames {
        let filtered = filter.apply(f);
        if !f.status.tracker_fresh {
            continue;
        }
        if let (Some((_, a)), Some((_, b))) = (raw_loop.finger_of(f), raw_loop.finger_of(&filtered))
        {
            out.push((a.tip, b.tip));
        }
    }
    out
}

/// Replays a shipped trace on its scene's surface with its scene's finger, through `filter`.
fn replay_shipped(trace: &Trace, filter: FilterSettings) -> Grid {
    let scene = nendo::hand::scene::Scene::of_trace(&trace.header)
        .unwrap()
        .unwrap();
    let start = scene.start_model(Path::new(".")).unwrap().surface;
    let finger: FingerModel = scene
        .finger
        .as_deref()
        .map_or(FingerModel::digit(Digit::Index), |f| f.parse().unwrap());
    let hand = Hand::new(trace.header.hand, trace.header.world_from_tracker).unwrap();
    let options = HandOptions {
        finger,
        finger_radius: scene.finger_radius.unwrap_or(1.0),
        ..HandOptions::default()
    };
    let regulation = scene.regulation.unwrap_or_default();
    let mut s = HandSession::new(start, regulation, hand, options).unwrap();
    s.set_filter(filter);
    for f in &trace.frames {
        s.feed(f);
    }
    s.finish();
    s.into_grid()
}

#[test]
fn the_lag_on_the_shipped_traces_is_small_and_nothing_is_held() {
    // The shipped glove traces are scripted motions at 60 and 120 Hz, 20 sides per metre
    // (the mouse's is not filtered). At every tracker sample, the fingertip through the
    // filter against the raw one; and the finished surfaces, filtered and raw.
    let (mut report, mut figures) = (Vec::new(), Vec::new());
    for name in [
        "plane-groove",
        "plane-palm",
        "sphere-push-pull",
        "sphere-pinch-pull",
        "tube-rim-pinch",
        "tube-pot",
    ] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("devices/traces")
            .join(format!("{name}.trace"));
        let trace = Trace::read(&path).unwrap();
        let mut filter = FrameFilter::default();
        for f in &trace.frames {
            filter.apply(f);
        }
        assert_eq!(filter.stats().rejected(), 0, "{name}: {:?}", filter.stats());
        let tips = fingertips(&trace);
        let lags: Vec<f64> = tips.iter().map(|(a, b)| (*a - *b).length()).collect();
        let max = lags.iter().copied().fold(0.0, f64::max);
        let rms = (lags.iter().map(|l| l * l).sum::<f64>() / lags.len() as f64).sqrt();
        let scale = trace.header.world_from_tracker.scale;
        let gap = max_gap(
            &replay_shipped(&trace, FilterSettings::off()),
            &replay_shipped(&trace, FilterSettings::default()),
        );
        report.push(format!(
            "{name}: lag max {max:.3} side ({:.1} mm), RMS {rms:.4} side; surfaces {gap:.4} side apart",
            max / scale * 1e3
        ));
        figures.push((name, rms, max, gap));
    }
    eprintln!("filter lag at the fingertip: {}", report.join("; "));
    for (name, rms, max, gap) in figures {
        assert!(rms < 0.075, "{name}: {rms}");
        assert!(max < 0.25, "{name}: {max}");
        // The pot's 60 Hz pecks: 0.10 side between the filtered and the raw pot since a press
        // re-applies only when it goes more than `min_depth` deeper (issue 25's desk branch;
        // 0.1 before) — fewer applications of the filter's creeping tail, each adjusting
        // the rule-7 correction.
        let most = if name == "tube-pot" { 0.11 } else { 0.1 };
        assert!(gap < most, "{name}: {gap}");
    }
    // The emulators' gestures at both shipped scales pass the gate untouched.
    for world in [
        Choreography::WORLD,
        nendo_devices::profile::resolve("cyberglove2-18-fastrak")
            .unwrap()
            .world_from_tracker,
    ] {
        for g in nendo::hand::script::Gesture::ALL {
            for rate in [60.0, 120.0, 240.0] {
                let t = g.trace(world, rate).unwrap();
                let mut filter = FrameFilter::default();
                for f in &t.frames {
                    filter.apply(f);
                }
                assert_eq!(
                    filter.stats().rejected(),
                    0,
                    "{} at {rate} Hz, {world:?}",
                    g.name()
                );
            }
        }
    }
}

/// Starts `nendo emulate DEVICE` with `args`; returns the child and the port it printed.
fn emulator(device: &str, args: &[&str]) -> (Child, String) {
    let mut child = nendo()
        .arg("emulate")
        .arg(device)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    (child, line.trim().to_string())
}

/// `|x_i − (x_{i−1} + x_{i+1})/2|` at every inner sample: how far a sample is off the line
/// through its neighbours (the device samples at a fixed rate).
fn off_neighbours(xs: &[Vec<f64>]) -> Vec<f64> {
    let mut d = vec![0.0; xs.len()];
    for i in 1..xs.len().saturating_sub(1) {
        d[i] = xs[i]
            .iter()
            .zip(&xs[i - 1])
            .zip(&xs[i + 1])
            .map(|((x, a), b)| (x - 0.5 * (a + b)).powi(2))
            .sum::<f64>()
            .sqrt();
    }
    d
}

/// Isolated spikes of at least `min`: off their neighbours by `min` or more and by twice as
/// much as either neighbour is (a lone spike of size `s` puts each neighbour `s/2` off).
fn spikes(d: &[f64], min: f64) -> Vec<usize> {
    (1..d.len().saturating_sub(1))
        .filter(|&i| d[i] >= min && d[i] >= 1.9 * d[i - 1].max(d[i + 1]))
        .collect()
}

#[test]
fn a_corrupted_emulator_stream_has_its_spikes_held() {
    // `nendo emulate --corrupt 0.05` on both devices (a bit flipped in one record in twenty),
    // the press gesture at 20 sides per metre, recorded for 6 s and replayed.
    let dir = temp_dir("filter-corrupt");
    let mut profile = nendo_devices::profile::resolve("cyberglove2-18-fastrak").unwrap();
    profile.world_from_tracker = Choreography::WORLD;
    let profile_path = dir.join("glove-20.json");
    profile.save(&profile_path).unwrap();
    let pp = profile_path.to_str().unwrap();
    let common = [
        "--corrupt",
        "0.05",
        "--motion",
        "press",
        "--seconds",
        "12",
        "--profile",
        pp,
    ];
    let (mut tracker, tracker_port) = emulator("fastrak", &common);
    let (mut glove, glove_port) = emulator("cyberglove", &common);
    let trace_path = dir.join("corrupt.trace");
    let out = nendo()
        .args([
            "record",
            "--profile",
            pp,
            "--seconds",
            "6",
            "--primitive",
            "plane",
        ])
        .args(["--finger", "index", "--glove-port", &glove_port])
        .args(["--tracker-port", &tracker_port])
        .arg("--out")
        .arg(&trace_path)
        .output()
        .unwrap();
    let _ = tracker.kill();
    let _ = glove.kill();
    let _ = tracker.wait();
    let _ = glove.wait();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let trace = Trace::read(&trace_path).unwrap();

    // The gate, as the hand loop runs it, over the recorded frames.
    let mut filter = FrameFilter::new(profile.filter);
    let (mut positions, mut held_position) = (Vec::new(), Vec::new());
    let mut position_times = Vec::new();
    let mut joints: Vec<Vec<f64>> = Vec::new();
    let mut joint_times = Vec::new();
    let mut held_joints: Vec<u32> = Vec::new();
    // The marks the recording wrote (trace version 4) are the gate's on the frames read back.
    assert!(
        trace.header.marks_held,
        "a gated recording declares its marks"
    );
    let mut marks = Vec::new();
    for (k, f) in trace.frames.iter().enumerate() {
        filter.apply(f);
        let held = filter.held();
        let m = HeldMarks::from(held).carried_by(f, &trace.header.joints, false);
        if !m.is_empty() {
            marks.push((k, m));
        }
        if f.status.tracker_fresh
            && let Some(p) = f.pose
        {
            positions.push(p.position.to_array().to_vec());
            position_times.push(f.time.as_secs_f64());
            held_position.push(held.position);
        }
        if f.status.glove_fresh
            && let Some(a) = f.joints
        {
            joints.push(
                Joint::ALL
                    .iter()
                    .map(|&j| a.get(j).unwrap_or(0.0))
                    .collect(),
            );
            joint_times.push(f.time.as_secs_f64());
            held_joints.push(held.joints);
        }
    }
    let st = *filter.stats();
    assert_eq!(trace.held, marks, "the recorded marks are the gate's");
    assert_eq!(trace.held.len() as u64, st.frames_held);
    let recorded = String::from_utf8_lossy(&out.stdout);
    let says = format!(
        "gate: {} of {} frames marked held",
        trace.held.len(),
        trace.frames.len()
    );
    assert!(recorded.contains(&says), "{says}: {recorded}");

    // The independent reference: isolated spikes found after the fact, each sample against
    // both its neighbours (which the gate, deciding at once, never sees).
    let limits = &profile.filter.gate;
    let longer_interval =
        |times: &[f64], i: usize| (times[i] - times[i - 1]).max(times[i + 1] - times[i]);
    let d = off_neighbours(&positions);
    let big = spikes(&d, 0.01);
    // A spike a hand could have made in the time the samples were actually apart is not one
    // the gate may hold: a sample read late (a loaded machine delays the reader, then it reads
    // a burst) spans a longer interval, over which the hand may move farther off the chord of
    // its neighbours, by at most `a_max·Δt² + n` (Δt the longer of the two intervals).
    let plausible = |i: usize| {
        let dt = longer_interval(&position_times, i);
        d[i] <= limits.max_acceleration_m_s2 * dt * dt + limits.position_noise_m
    };
    let excused = big
        .iter()
        .filter(|&&i| held_position[i].is_none() && plausible(i))
        .count();
    let missed: Vec<(usize, f64)> = big
        .iter()
        .filter(|&&i| held_position[i].is_none() && !plausible(i))
        .map(|&i| (i, d[i]))
        .collect();
    let smooth_held = (0..positions.len())
        .filter(|&i| held_position[i].is_some() && d[i] < 2e-3)
        .count();
    let largest = big.iter().map(|&i| d[i]).fold(0.0, f64::max);
    // Joint by joint, spikes of 0.2 rad or more (a flipped bit 5, 6 or 7 of a sensor).
    let (mut joint_spikes, mut joint_missed, mut joint_largest) = (0, 0, 0.0f64);
    let mut joint_excused = 0;
    for j in Joint::ALL {
        let series: Vec<Vec<f64>> = joints.iter().map(|v| vec![v[j.index()]]).collect();
        let d = off_neighbours(&series);
        for i in spikes(&d, 0.2) {
            joint_spikes += 1;
            joint_largest = joint_largest.max(d[i]);
            if held_joints[i] & (1 << j.index()) == 0 {
                let dt = longer_interval(&joint_times, i);
                if d[i] <= limits.max_joint_acceleration_rad_s2 * dt * dt + limits.joint_noise_rad {
                    joint_excused += 1;
                } else {
                    joint_missed += 1;
                }
            }
        }
    }
    eprintln!(
        "--corrupt 0.05, 6 s: {} frames, {} marked held in the trace (as the gate recomputes); {} tracker and {} glove samples; reference spikes: {} of the position ≥ 1 cm (largest {:.3} m), {} of a joint ≥ 0.2 rad (largest {:.2} rad); the gate held {} positions ({} out of range, {} too fast, {} too sudden), {} orientations, {} joint angles; missed {:?} / {joint_missed} ({excused} position and {joint_excused} joint spikes within what a hand can do in their interval); held {smooth_held} positions lying within 2 mm of their neighbours",
        trace.frames.len(),
        trace.held.len(),
        positions.len(),
        joints.len(),
        big.len(),
        largest,
        joint_spikes,
        joint_largest,
        st.position.total(),
        st.position.out_of_range,
        st.position.too_fast,
        st.position.too_sudden,
        st.orientation.total(),
        st.joints.total(),
        missed,
    );
    assert!(positions.len() > 400 && joints.len() > 300, "{st:?}");
    assert!(
        big.len() + joint_spikes >= 3,
        "the corruption must make spikes to hold"
    );
    assert!(
        missed.is_empty(),
        "position spikes through the gate: {missed:?}"
    );
    assert_eq!(joint_missed, 0);
    assert!(
        smooth_held * 100 <= positions.len(),
        "{smooth_held} good samples held"
    );

    // `nendo replay` reports what the gate held, and with the gate the plane away from the
    // press stays flat.
    let filtered = dir.join("filtered.json");
    let raw = dir.join("raw.json");
    let out = nendo()
        .arg("replay")
        .arg(&trace_path)
        .arg("--out")
        .arg(&filtered)
        .output()
        .unwrap();
    let summary = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{summary}");
    // The replay's gate agrees with the trace's marks.
    let agree = format!(
        "the trace marks {} frames held, as this replay's gate does",
        trace.held.len()
    );
    assert!(summary.contains(&agree), "{agree}: {summary}");
    assert!(!summary.contains("warning"), "{summary}");
    let n = st.position.total();
    if n > 0 {
        let says = format!("{n} tracker position");
        assert!(summary.contains(&says), "{says}: {summary}");
    }
    assert!(
        summary.contains("from the trace's scene: start surface, finger, filter"),
        "{summary}"
    );
    let out = nendo()
        .arg("replay")
        .arg(&trace_path)
        .arg("--no-filter")
        .arg("--out")
        .arg(&raw)
        .output()
        .unwrap();
    assert!(out.status.success());
    let unfiltered = String::from_utf8_lossy(&out.stderr);
    assert!(
        unfiltered.contains("held (not compared: not filtered)"),
        "{unfiltered}"
    );
    let away = |path: &Path| {
        let g = nendo::model::Model::read(path).unwrap().model.surface;
        dense(&g)
            .iter()
            .filter(|p| (p.x - 0.5).hypot(p.y - 0.5) > 1.5)
            .map(|p| p.z.abs())
            .fold(0.0, f64::max)
    };
    let (away_filtered, away_raw) = (away(&filtered), away(&raw));
    // The same press without corruption, straight from the gesture's script.
    let clean = nendo::hand::script::Gesture::Press
        .trace(Choreography::WORLD, 120.0)
        .unwrap();
    let (press, _) = replay(&clean.frames, FilterSettings::default());
    let clean_path = dir.join("clean.json");
    nendo::model::Model::new(press).write(&clean_path).unwrap();
    let away_clean = away(&clean_path);
    eprintln!(
        "replay: {summary}; the plane more than 1.5 side from the press: {away_raw:.4} unfiltered, {away_filtered:.4} filtered, {away_clean:.4} for the press without corruption"
    );
    assert!(away_filtered < away_clean + 0.01, "{away_filtered}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The gate's marks of a trace (version 4) are checked against the replay's own gate: the
/// summary counts them and says the gate agrees; marks that differ give a warning naming the
/// first differing frames, and change nothing else (exit status, the model written byte for
/// byte). A version-2 trace's summary says nothing of marks.
#[test]
fn a_traces_gate_marks_are_checked_by_the_replay() {
    use nendo::hand::scene::Scene;
    use nendo_devices::FrameFilter;
    use nendo_devices::trace::{HeldMarks, quantize_frame};
    let dir = temp_dir("filter-marks");
    let s = |p: &Path| p.to_str().unwrap().to_owned();
    let nendo = |args: &[&str]| nendo().args(args).output().unwrap();
    let source = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces/plane-groove.trace")
        .display()
        .to_string();
    let plain = dir.join("plain.json");
    let o = nendo(&["replay", &source, "--out", &s(&plain)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("the trace marks"), "{err}");

    // The shipped trace with three tracker spikes, marked by the gate the replay filters with
    // (its scene's filter, else the defaults for a glove's hand).
    let mut trace = Trace::read(Path::new(&source)).unwrap();
    let joints = trace.header.joints.clone();
    let with_pose: Vec<usize> = (0..trace.frames.len())
        .filter(|&k| trace.frames[k].pose.is_some() && trace.frames[k].status.tracker_fresh)
        .collect();
    for &k in &[with_pose[100], with_pose[250], with_pose[400]] {
        let f = &mut trace.frames[k];
        if let Some(p) = &mut f.pose {
            p.position.z -= 0.06;
        }
        *f = quantize_frame(f, &joints);
    }
    let settings = Scene::of_trace(&trace.header)
        .unwrap()
        .and_then(|s| s.filter)
        .unwrap_or_default();
    let mut gate = FrameFilter::new(settings);
    trace.held = trace
        .frames
        .iter()
        .enumerate()
        .filter_map(|(k, f)| {
            gate.apply(f);
            let m = HeldMarks::from(gate.held()).carried_by(f, &joints, false);
            (!m.is_empty()).then_some((k, m))
        })
        .collect();
    let spikes = [with_pose[100], with_pose[250], with_pose[400]];
    for k in spikes {
        assert!(trace.held.iter().any(|(i, m)| *i == k && m.position), "{k}");
    }
    let marked = dir.join("marked.trace");
    trace.write(&marked).unwrap();
    let text = std::fs::read_to_string(&marked).unwrap();
    assert!(text.starts_with("nendo-hand-trace 4\n") && text.contains("\nmarks held\n"));
    let agreed = dir.join("agreed.json");
    let o = nendo(&["replay", &s(&marked), "--out", &s(&agreed)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let says = format!(
        "the trace marks {} frames held, as this replay's gate does",
        trace.held.len()
    );
    assert!(err.contains(&says), "{says}: {err}");
    assert!(!err.contains("warning"), "{err}");

    // Marks that differ: the first one dropped, one added where the gate held nothing.
    let mut tampered = trace.clone();
    let (dropped, _) = tampered.held.remove(0);
    let added = with_pose
        .iter()
        .copied()
        .find(|k| *k > dropped && !trace.held.iter().any(|(i, _)| i == k))
        .unwrap();
    let at = tampered.held.partition_point(|(i, _)| *i < added);
    tampered.held.insert(
        at,
        (
            added,
            HeldMarks {
                orientation: true,
                ..HeldMarks::default()
            },
        ),
    );
    let path = dir.join("tampered.trace");
    tampered.write(&path).unwrap();
    let out = dir.join("tampered.json");
    let o = nendo(&["replay", &s(&path), "--out", &s(&out)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "a warning, not a failure: {err}");
    let warning = format!(
        "warning: {}: the trace's gate marks differ from this replay's gate on 2 frames (first: {}, {})",
        path.display(),
        dropped + 1,
        added + 1
    );
    assert!(err.contains(&warning), "{warning}: {err}");
    assert!(
        err.contains(&format!(
            "the trace marks {} frames held; this replay's gate differs on 2 frames",
            trace.held.len()
        )),
        "{err}"
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        std::fs::read(&agreed).unwrap(),
        "the replay filters with its own gate"
    );
    eprintln!(
        "marks: {} frames of {} marked ({} spikes injected); tampered: {err}",
        trace.held.len(),
        trace.frames.len(),
        spikes.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
