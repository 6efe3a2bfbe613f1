//! Refinement (issue 13): more patches, the same surface, on every topology; the ratios that
//! keep the exact regulation a no-op; sculpting after refinement; the finger's refinement;
//! the grid limit; `nendo refine`, `sculpt --auto-refine` and `replay --auto-refine`.

use crate::support::{run as nendo, run_with_input, temp_dir};
use glam::DVec3;
use nendo::model::Model;
use nendo::surface::MAX_PATCHES;
use nendo::surface::continuity::report;
use nendo::surface::refine::{self, RefineError, Refinement, polygon_sizes};
use nendo::surface::{Grid, Op, Primitive, PrimitiveParams, Regulation, deform, regulate_all};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

fn build(p: Primitive, counts: Option<(usize, usize)>) -> Grid {
    p.build(&PrimitiveParams {
        patches: counts,
        ..PrimitiveParams::default()
    })
    .unwrap()
}

/// The surface point at global grid parameters `(u, v)`.
fn eval_global(g: &Grid, u: f64, v: f64) -> DVec3 {
    let iu = (u.floor().max(0.0) as usize).min(g.patches_u() - 1);
    let iv = (v.floor().max(0.0) as usize).min(g.patches_v() - 1);
    g.eval(iu, iv, u - iu as f64, v - iv as f64)
}

/// A few random pushes and pulls along the surface normal at random points (exact
/// regulation); refused ones are skipped.
fn sculpt_randomly(g: &mut Grid, rng: &mut ChaCha8Rng, count: usize) {
    let scale = g.bounds().half_extents().max_element();
    let mut applied = 0;
    for _ in 0..count * 4 {
        if applied == count {
            break;
        }
        let iu = rng.gen_range(0..g.patches_u());
        let iv = rng.gen_range(0..g.patches_v());
        let (u, v) = (rng.gen_range(0.2..0.8), rng.gen_range(0.2..0.8));
        let Some(n) = g.normal(iu, iv, u, v) else {
            continue;
        };
        let depth =
            rng.gen_range(0.03..0.12) * scale * if rng.r#gen::<bool>() { 1.0 } else { -1.0 };
        let op = Op::Push {
            at: g.eval(iu, iv, u, v),
            dir: -n,
            depth,
            radius: rng.gen_range(0.15..0.4) * scale,
        };
        if deform(g, &op, Regulation::Exact).is_ok() {
            applied += 1;
        }
    }
    assert!(applied > 0);
}

fn extent(g: &Grid) -> f64 {
    let b = g.bounds();
    b.min.abs().max(b.max.abs()).max_element().max(1.0)
}

/// Samples agree to 1e-12 relative; G1 and the pole spreads and normals unchanged; exact
/// regulation right after moves nothing.
fn assert_same_surface(old: &Grid, r: &Refinement, new: &Grid, rng: &mut ChaCha8Rng, what: &str) {
    assert_eq!((new.patches_u(), new.patches_v()), r.counts(), "{what}");
    assert_eq!(new.topology(), old.topology(), "{what}");
    let scale = extent(old);
    let (m, n) = (old.patches_u() as f64, old.patches_v() as f64);
    let mut worst = 0.0f64;
    for k in 0..600 {
        // Random points, and points on the old grid lines and the borders.
        let (u, v) = match k % 3 {
            0 => (rng.gen_range(0.0..m), rng.gen_range(0.0..n)),
            1 => (
                rng.gen_range(0..=old.patches_u()) as f64,
                rng.gen_range(0.0..n),
            ),
            _ => (
                rng.gen_range(0.0..m),
                rng.gen_range(0..=old.patches_v()) as f64,
            ),
        };
        let a = eval_global(old, u, v);
        let b = eval_global(new, r.map_u(u), r.map_v(v));
        worst = worst.max((a - b).length());
    }
    assert!(
        worst <= 1e-12 * scale,
        "{what}: samples differ by {worst:e}"
    );
    let (ro, rn) = (report(old, 33), report(new, 33));
    assert!(rn.g0_gap <= 1e-12 * scale, "{what}: G0 {}", rn.g0_gap);
    assert!(
        rn.g1_max_deg <= ro.g1_max_deg.max(1e-9),
        "{what}: G1 {} after, {} before",
        rn.g1_max_deg,
        ro.g1_max_deg
    );
    assert_eq!(ro.poles.len(), rn.poles.len());
    for (a, b) in ro.poles.iter().zip(&rn.poles) {
        assert_eq!(a.position, b.position, "{what}: the pole moved");
        assert!(
            (a.spread_deg - b.spread_deg).abs() <= 1e-9,
            "{what}: pole spread {} -> {}",
            a.spread_deg,
            b.spread_deg
        );
        let (na, nb) = (a.normal.unwrap(), b.normal.unwrap());
        assert!(
            (na - nb).length() <= 1e-9,
            "{what}: pole normal {na} -> {nb}"
        );
    }
    let mut again = new.clone();
    regulate_all(&mut again, Regulation::Exact).expect("exact regulates");
    let moved = new
        .nodes()
        .iter()
        .zip(again.nodes())
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max);
    assert!(moved <= 1e-12 * scale, "{what}: regulation moved {moved:e}");
}

/// Random parameters for `count` insertions along a direction of `segments` patches; around
/// a closed direction each comes with its opposite `T + segments/2`.
fn random_params(rng: &mut ChaCha8Rng, segments: usize, closed: bool, count: usize) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    while out.len() < count {
        let t = rng.gen_range(0..segments) as f64 + rng.gen_range(0.02..0.98);
        let mut new = vec![t];
        if closed {
            new.push((t + segments as f64 / 2.0) % segments as f64);
        }
        if new.iter().all(|x| out.iter().all(|y| (x - y).abs() > 1e-3)) {
            out.extend(new);
        }
    }
    out
}

#[test]
fn refinement_keeps_every_sculpted_surface_on_every_topology() {
    let mut rng = ChaCha8Rng::seed_from_u64(1301);
    for p in Primitive::ALL {
        for round in 0..2 {
            let mut g = build(p, None);
            sculpt_randomly(&mut g, &mut rng, 4);
            let t = g.topology();
            let (m, n) = (g.patches_u(), g.patches_v());
            // Random insertions, several in one patch column sometimes.
            let cu = if t.closed_u() { 2 } else { 1 + round * 2 };
            let cv = if t.closed_v() { 2 } else { 1 + round * 2 };
            let u = random_params(&mut rng, m, t.closed_u(), cu);
            let v = random_params(&mut rng, n, t.closed_v(), cv);
            let r = Refinement::new(&g, &u, &v).unwrap();
            assert_eq!(r.counts(), (m + u.len(), n + v.len()));
            let h = r.apply(&g).unwrap();
            assert_same_surface(&g, &r, &h, &mut rng, &format!("{p} insert {u:?} {v:?}"));
            // Uniform ×2 and ×3.
            for k in [2, 3] {
                let r = Refinement::uniform(&g, k).unwrap();
                assert_eq!(r.counts(), (k * m, k * n));
                let h = refine::uniform(&g, k).unwrap();
                assert_same_surface(&g, &r, &h, &mut rng, &format!("{p} x{k}"));
            }
        }
    }
}

#[test]
fn the_ratio_formula_holds_line_by_line() {
    // One split at t of column 1 of a 3-column plane with measured ratios: ρ·t on the left
    // line, (1 − t)/t on the new one, ρ/(1 − t) on the right one.
    let mut g = build(Primitive::Plane, Some((3, 2)));
    g.set_ratios(&[1.0, 0.8, 1.25, 1.0], &[1.0, 1.1, 1.0])
        .unwrap();
    let t = 0.3;
    let r = Refinement::new(&g, &[1.0 + t], &[]).unwrap();
    let h = r.apply(&g).unwrap();
    let want = [1.0, 0.8 * t, (1.0 - t) / t, 1.25 / (1.0 - t), 1.0];
    for (got, want) in h.ratios_u().iter().zip(want) {
        assert!((got - want).abs() < 1e-15, "{:?}", h.ratios_u());
    }
    assert_eq!(h.ratios_v(), g.ratios_v());
}

#[test]
fn sculpting_after_refinement_stays_g1() {
    let mut rng = ChaCha8Rng::seed_from_u64(1302);
    for p in Primitive::ALL {
        let mut g = build(p, None);
        sculpt_randomly(&mut g, &mut rng, 3);
        let t = g.topology();
        let u = random_params(&mut rng, g.patches_u(), t.closed_u(), 2);
        let v = random_params(&mut rng, g.patches_v(), t.closed_v(), 2);
        for mut h in [
            Refinement::new(&g, &u, &v).unwrap().apply(&g).unwrap(),
            refine::uniform(&g, 2).unwrap(),
        ] {
            sculpt_randomly(&mut h, &mut rng, 4);
            let rep = report(&h, 33);
            assert!(rep.g1_max_deg <= 0.01, "{p}: G1 {}°", rep.g1_max_deg);
            for pole in &rep.poles {
                assert!(pole.spread_deg <= 0.01, "{p}: spread {}°", pole.spread_deg);
            }
        }
    }
}

/// Distance from `x` to the half-line of a push finger (`tip` back against `axis`).
fn finger_distance(x: DVec3, tip: DVec3, axis: DVec3) -> f64 {
    let w = x - tip;
    let behind = -w.dot(axis);
    if behind > 0.0 {
        (w + behind * axis).length()
    } else {
        w.length()
    }
}

#[test]
fn an_auto_refined_stroke_moves_only_what_the_finger_reaches() {
    // The case: a radius-0.6 push on the 8 × 4 torus moves most of its patches.
    let g = build(Primitive::Torus, None);
    let (at, nrm) = (g.eval(1, 0, 0.5, 0.5), g.normal(1, 0, 0.5, 0.5).unwrap());
    let radius = 0.6;
    let op = Op::Push {
        at,
        dir: -nrm,
        depth: 0.2,
        radius,
    };
    let tip = at - nrm * 0.2;
    let far = |before: &Grid, after: &Grid| {
        // The farthest moved control point from the finger.
        before
            .nodes()
            .iter()
            .zip(after.nodes())
            .filter(|(a, b)| a != b)
            .map(|(a, _)| finger_distance(*a, tip, -nrm))
            .fold(0.0, f64::max)
    };
    let mut coarse = g.clone();
    deform(&mut coarse, &op, Regulation::Exact).unwrap();
    let coarse_far = far(&g, &coarse);

    let f = refine::for_finger(&g, &op).unwrap();
    assert!(!f.limited);
    assert_eq!(f.target, radius / 2.0);
    let fine = f.refinement.apply(&g).unwrap();
    // Every patch the finger reaches is at most σ·r_f/2 across both ways (σ the slack).
    let finger = op.finger().unwrap();
    let depth = finger.reach_depth(&fine.bounds());
    let mut reached = Vec::new();
    fine.patches_where(|b| finger.may_touch(b, depth), &mut reached);
    assert!(!reached.is_empty());
    let mut largest = 0.0f64;
    for &p in &reached {
        let (lu, lv) = polygon_sizes(&fine.patch_at(p));
        largest = largest.max(lu).max(lv);
    }
    assert!(
        largest <= refine::FINGER_SLACK * f.target * (1.0 + 1e-12),
        "{largest}"
    );
    let mut after = fine.clone();
    let touched = deform(&mut after, &op, Regulation::Exact).unwrap();
    // Moved patches: none farther from the finger than its reach plus one patch (the nearest
    // of 9 × 9 samples of each within r_f + l_u + l_v of the largest reached patch), and no
    // moved control point beyond one more control leg (at most r_f/2).
    let patch = 2.0 * f.target;
    for &p in &touched.patches {
        if fine.patch_at(p) == after.patch_at(p) {
            continue;
        }
        let (iu, iv) = (p % fine.patches_u(), p / fine.patches_u());
        let mut near = f64::INFINITY;
        for i in 0..9 {
            for j in 0..9 {
                let x = fine.eval(iu, iv, i as f64 / 8.0, j as f64 / 8.0);
                near = near.min(finger_distance(x, tip, -nrm));
            }
        }
        assert!(near <= radius + patch + 1e-9, "patch {p}: {near}");
    }
    let fine_far = far(&fine, &after);
    assert!(fine_far <= radius + patch + f.target + 1e-9, "{fine_far}");
    assert!(
        coarse_far > fine_far,
        "coarse {coarse_far}, fine {fine_far}"
    );
    assert!(report(&after, 33).g1_max_deg <= 0.01);
}

#[test]
fn refinement_past_the_grid_limit_is_refused() {
    let g = build(Primitive::Plane, Some((128, 128)));
    assert!(matches!(
        refine::uniform(&g, 3),
        Err(RefineError::TooLarge {
            from_u: 128,
            to_u: 384,
            ..
        })
    ));
    let full = build(Primitive::Plane, Some((256, 256)));
    assert_eq!(
        refine::uniform(&full, 1).unwrap().patch_count(),
        MAX_PATCHES
    );
    let e = Refinement::new(&full, &[0.5], &[]).unwrap_err();
    assert!(e.to_string().contains("grid limit of 65536"), "{e}");
    // The finger's rule stops short of it and says so.
    let op = Op::Push {
        at: DVec3::ZERO,
        dir: DVec3::NEG_Z,
        depth: 0.01,
        radius: 1e-3,
    };
    let f = refine::for_finger(&build(Primitive::Plane, Some((10, 10))), &op).unwrap();
    assert!(f.limited);
    let (mu, nv) = f.refinement.counts();
    assert!(mu * nv <= MAX_PATCHES, "{mu} x {nv}");
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn nendo_refine_writes_the_same_surface_with_its_curves() {
    let dir = temp_dir("refine-cli");
    let (input, out) = (dir.join("in.json"), dir.join("out.json"));
    let mut g = build(Primitive::Sphere, None);
    let mut rng = ChaCha8Rng::seed_from_u64(1303);
    sculpt_randomly(&mut g, &mut rng, 3);
    let mut doc = Model::new(g.clone()).to_json();
    doc["curves"] = serde_json::json!([{"bezier": [[0, 0, 4], [1, 0, 4], [2, 1, 4], [3, 1, 5]]}]);
    std::fs::write(&input, doc.to_string()).unwrap();
    let o = nendo(&[
        "refine",
        s(&input),
        "--insert-u",
        "1.25,5.25",
        "--insert-v",
        "0.5,2.75",
        "--uniform",
        "2",
        "--out",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("8 x 4 -> 20 x 12"), "{err}");
    let before = Model::read(&input).unwrap().model;
    let after = Model::read(&out).unwrap().model;
    assert_eq!(after.curves, before.curves);
    assert_eq!(after.regulation, before.regulation);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("\"version\":1"), "{}", &text[..80]);
    // The documented mapping, then ×2.
    let r = Refinement::new(&g, &[1.25, 5.25], &[0.5, 2.75]).unwrap();
    let h = &after.surface;
    for _ in 0..300 {
        let (u, v) = (rng.gen_range(0.0..8.0), rng.gen_range(0.0..4.0));
        let a = eval_global(&g, u, v);
        let b = eval_global(h, 2.0 * r.map_u(u), 2.0 * r.map_v(v));
        assert!(
            (a - b).length() <= 3e-12 * 1.0f64.max(extent(&g)),
            "{u} {v}"
        );
    }
}

#[test]
fn nendo_refine_refuses_bad_arguments_and_writes_nothing() {
    let dir = temp_dir("refine-args");
    let (input, out) = (dir.join("in.json"), dir.join("out.json"));
    let o = nendo(&["sculpt", "--primitive", "torus", "--out", s(&input)]);
    assert!(o.status.success());
    for (args, says) in [
        (vec!["--insert-u", "2"], "on an existing grid line"),
        (vec!["--insert-u", "8.5,1.5"], "outside (0, 8)"),
        (vec!["--insert-v", "-0.5,1.5"], "outside (0, 4)"),
        (vec!["--insert-v", "1.5"], "even number"),
        (vec!["--insert-u", "1.5,1.5"], "closer than"),
        (vec!["--uniform", "0"], "at least 1"),
        (vec!["--uniform", "100"], "grid limit of 65536"),
        (vec![], "give --uniform K"),
        // Extreme numbers are printed compactly, not as their 300-digit expansions.
        (
            vec!["--insert-u", "1e308"],
            "u parameter 1e308 is outside (0, 8)",
        ),
        (
            vec!["--insert-v", "-1e30"],
            "v parameter -1e30 is outside (0, 4)",
        ),
        (
            vec!["--insert-u", "1e-310"],
            "u parameter 1e-310 is on an existing grid line",
        ),
    ] {
        let mut all = vec!["refine", s(&input), "--out", s(&out)];
        all.extend(&args);
        let o = nendo(&all);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(says) && err.contains("nothing written"),
            "{args:?}: {err}"
        );
        assert!(!out.exists());
    }
    let o = nendo(&[
        "refine",
        s(&dir.join("none.json")),
        "--uniform",
        "2",
        "--out",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(!out.exists());
}

#[test]
fn sculpt_auto_refine_refines_where_the_finger_goes() {
    let dir = temp_dir("auto-refine");
    let (plain, fine) = (dir.join("plain.json"), dir.join("fine.json"));
    let ops =
        "{\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[0,0,-1],\"depth\":0.1,\"radius\":0.4}\n";
    for (out, auto) in [(&plain, false), (&fine, true)] {
        let mut args = vec![
            "sculpt",
            "--primitive",
            "plane",
            "--ops",
            "-",
            "--out",
            s(out),
        ];
        if auto {
            args.push("--auto-refine");
        }
        let o = run_with_input(&args, ops);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        if auto {
            assert!(err.contains("1 refined for the finger"), "{err}");
        }
    }
    let (a, b) = (
        Model::read(&plain).unwrap().model.surface,
        Model::read(&fine).unwrap().model.surface,
    );
    assert_eq!(a.patch_count(), 100);
    assert!(
        b.patch_count() > 100 && b.patches_u() < 20,
        "{} x {}",
        b.patches_u(),
        b.patches_v()
    );
    assert!(report(&b, 33).g1_max_deg <= 0.01);

    // Past the grid limit: the refinement stops, says so, and the push is still applied.
    let tiny =
        "{\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[0,0,-1],\"depth\":0.01,\"radius\":1e-6}\n";
    let o = run_with_input(
        &[
            "sculpt",
            "--primitive",
            "plane",
            "--auto-refine",
            "--ops",
            "-",
            "--out",
            s(&fine),
        ],
        tiny,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("stopped at the grid limit"), "{err}");
    // The target size printed compactly (before: `0.0000`).
    assert!(err.contains("patches of at most 5e-7 side"), "{err}");
    let g = Model::read(&fine).unwrap().model.surface;
    assert!(g.patch_count() <= MAX_PATCHES && g.patch_count() > 100);
}

#[test]
fn replay_auto_refine_refines_before_contacts() {
    let trace = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces/sphere-push-pull.trace")
        .display()
        .to_string();
    let dir = temp_dir("replay-refine");
    let out = dir.join("out.json");
    let o = nendo(&[
        "replay",
        &trace,
        "--primitive",
        "sphere",
        "--finger-radius",
        "0.6",
        "--auto-refine",
        "--out",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("refined before"), "{err}");
    let g = Model::read(&out).unwrap().model.surface;
    assert!(g.patch_count() > 32, "{}", g.patch_count());
    assert!(report(&g, 33).g1_max_deg <= 0.01);
}

/// A fist held over the default plane (z = 0), the back of the hand up: every finger curled
/// (the index as far as the others), the hand lowered until the index's tip, pointing back up
/// out of the fist, is `height` above the plane, and held. The straight capsule behind that
/// tip runs down through the plane, but the finger's own joints do not reach it: nothing
/// presses (rule 3 of `nendo::hand::hand_loop`).
fn fist_over_the_plane(height: f64) -> nendo_devices::Trace {
    use nendo::hand::script::Choreography;
    use nendo_devices::Joint;
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(0.5, 0.5, 4.0), -DVec3::Z, DVec3::Y);
    c.hold(2);
    c.bend_to(&[(Joint::IndexMcp, 1.35), (Joint::IndexPip, 1.35)], 10);
    let (tip, _) = c.fingertip();
    let low = c.shifted(c.pose(), DVec3::new(0.0, 0.0, height - tip.z));
    c.move_pose_to(low, 30);
    c.hold(10);
    c.finish("cyberglove2-18-fastrak").unwrap()
}

/// Replays `trace` from the default plane (every finger pressing), plain and with
/// `--auto-refine`: the two surfaces and the auto-refined run's summary.
fn replay_plane_both_ways(dir: &Path, trace: &nendo_devices::Trace) -> (Grid, Grid, String) {
    let path = dir.join("t.trace");
    trace.write(&path).unwrap();
    let mut outs = Vec::new();
    let mut summary = String::new();
    for (name, auto) in [("plain.json", false), ("fine.json", true)] {
        let out = dir.join(name);
        let mut args = vec!["replay", s(&path), "--primitive", "plane", "--out", s(&out)];
        if auto {
            args.push("--auto-refine");
        }
        let o = nendo(&args);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert!(o.status.success(), "{err}");
        if auto {
            summary = err;
        }
        outs.push(Model::read(&out).unwrap().model.surface);
    }
    let fine = outs.pop().unwrap();
    let plain = outs.pop().unwrap();
    (plain, fine, summary)
}

/// The surface's height over `(x, y)` of a plane-like grid (searched straight down).
fn height_at(g: &Grid, x: f64, y: f64) -> f64 {
    let hit = nendo::hand::Probe::new()
        .first_crossing(g, DVec3::new(x, y, 5.0), -DVec3::Z, 10.0)
        .unwrap();
    hit.point.z
}

#[test]
fn replay_auto_refine_refines_only_for_the_contacts_the_hand_loop_starts() {
    use nendo::hand::{FingerModel, Fingers, Hand, HandLoop, HandOptions, Part};
    let dir = temp_dir("replay-refine-fist");
    // The curled index: its capsule (2 side behind the tip) crosses the plane, while the
    // finger itself — its body from the back of the hand to the tip — stays above it: the tip
    // never enters the clay.
    let fist = fist_over_the_plane(1.0);
    let hand = Hand::new(fist.header.hand, fist.header.world_from_tracker).unwrap();
    let hl = HandLoop::new(
        hand,
        HandOptions {
            finger: FingerModel::Hand(Fingers::ALL),
            ..HandOptions::default()
        },
    )
    .unwrap();
    let (_, tips) = hl.parts_of(fist.frames.last().unwrap()).unwrap();
    let index = tips
        .iter()
        .find(|(p, _)| *p == Part::Digit(nendo::hand::Digit::Index))
        .unwrap()
        .1;
    assert!((index.tip.z - 1.0).abs() < 1e-3, "{}", index.tip);
    assert!(index.axis.z > 0.0, "the tip points back up: {}", index.axis);
    let behind = index.tip.z / index.axis.z;
    assert!(
        behind < index.length && index.body.iter().all(|p| p.z > 0.0),
        "the capsule crosses the plane {behind} behind the tip, the capsule is {} long, the body {:?}",
        index.length,
        index.body
    );
    let (plain, fine, summary) = replay_plane_both_ways(&dir, &fist);
    assert!(summary.contains(": 0 contacts"), "{summary}");
    assert!(
        summary.contains("refined before 0 contacts, 10 x 10 patches"),
        "{summary}"
    );
    assert_eq!(plain.patch_count(), 100);
    assert_eq!(fine, plain);

    // A real press (the `press` gesture: the index straight down 0.3 side into the plane at
    // (0.5, 0.5), the other fingers curled above it) is still refined for, and the refined
    // replay's dent is the plain one's: its bottom at the fingertip within a tenth of the
    // depth in both, the plane untouched beyond the finger's reach plus a patch.
    let press = nendo::hand::script::Gesture::Press
        .trace(nendo::hand::script::Choreography::WORLD, 120.0)
        .unwrap();
    let (plain, fine, summary) = replay_plane_both_ways(&dir, &press);
    assert!(summary.contains(": 1 contacts"), "{summary}");
    assert!(summary.contains("refined before 1 contacts"), "{summary}");
    assert_eq!(plain.patch_count(), 100);
    assert!(fine.patch_count() > 100, "{}", fine.patch_count());
    for g in [&plain, &fine] {
        let bottom = height_at(g, 0.5, 0.5);
        assert!((bottom + 0.3).abs() < 0.03, "{bottom}");
        for (x, y) in [
            (-2.0, 0.5),
            (3.0, 0.5),
            (0.5, -2.0),
            (0.5, 3.0),
            (-3.0, -3.0),
        ] {
            assert_eq!(height_at(g, x, y), 0.0, "({x}, {y})");
        }
    }
    assert!(report(&fine, 33).g1_max_deg <= 0.01);
    std::fs::remove_dir_all(&dir).unwrap();
}
