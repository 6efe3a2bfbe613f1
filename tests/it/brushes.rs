//! Brushes (issue 27): each falloff against its formula on the plane (the surface sampled, not
//! the control net), the swept groove's centre line and walls, and the brush settings kept in
//! the settings file.

use glam::DVec3;
use nendo::editor::settings::{BrushSettings, Brushes, Settings};
use nendo::editor::tools::{Tool, ToolSettings};
use nendo::surface::{
    Brush, Dirs, Falloff, Grid, Op, Primitive, PrimitiveParams, Regulation, Sculptor, nearest,
    refine,
};

use crate::support::temp_dir;

fn plane() -> Grid {
    Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("the default plane")
}

/// The height of the surface above `(x, y)`: the nearest surface point, then Newton steps on
/// the patch parameters until the point lies on the vertical line (walking to the nearest
/// point again when a step leaves the patch).
fn height(grid: &Grid, x: f64, y: f64) -> f64 {
    let m = grid.patches_u();
    let mut z = 0.0;
    for _ in 0..6 {
        let near = nearest(grid, DVec3::new(x, y, z)).expect("a surface point");
        let (iu, iv) = (near.patch % m, near.patch / m);
        let (mut u, mut v) = (near.u, near.v);
        let mut inside = true;
        for _ in 0..30 {
            let p = grid.eval(iu, iv, u, v);
            let (ex, ey) = (p.x - x, p.y - y);
            z = p.z;
            if ex.abs() < 1e-13 && ey.abs() < 1e-13 {
                return z;
            }
            let h = 1e-7;
            let pu = (grid.eval(iu, iv, u + h, v) - p) / h;
            let pv = (grid.eval(iu, iv, u, v + h) - p) / h;
            let det = pu.x * pv.y - pu.y * pv.x;
            let du = (ex * pv.y - ey * pv.x) / det;
            let dv = (pu.x * ey - pu.y * ex) / det;
            u -= du;
            v -= dv;
            if !(-1e-9..=1.0 + 1e-9).contains(&u) || !(-1e-9..=1.0 + 1e-9).contains(&v) {
                inside = false;
                z = grid.eval(iu, iv, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)).z;
                break;
            }
        }
        if inside {
            return z;
        }
    }
    z
}

/// The grid refined as the window refines for `op` (every reached patch at most `r_f / 2`
/// across), then `op` applied with the exact regulation.
fn sculpted(grid: &Grid, ops: &[Op]) -> Grid {
    let mut g = grid.clone();
    let mut sculptor = Sculptor::new();
    for op in ops {
        let f = refine::for_finger(&g, op).expect("a refinement");
        g = f.refinement.apply(&g).expect("refined");
        sculptor
            .apply(&mut g, op, Regulation::Exact)
            .expect("the operation applies");
    }
    g
}

#[test]
fn each_brush_presses_its_formula_on_the_plane() {
    let (depth, strength, radius) = (0.5, 0.6, 2.0);
    let (mut profiles, mut errors) = (Vec::new(), Vec::new());
    for falloff in Falloff::ALL {
        let op = Op::Brushed {
            op: Box::new(Op::Push {
                at: DVec3::ZERO,
                dir: -DVec3::Z,
                depth,
                radius,
            }),
            brush: Brush { falloff, strength },
        };
        let g = sculpted(&plane(), &[op]);
        let mut worst = 0.0f64;
        let mut profile = Vec::new();
        for k in 0..=24 {
            let r = 2.4 * k as f64 / 24.0;
            for a in 0..6 {
                let t = a as f64 * std::f64::consts::TAU / 6.0 + 0.3;
                let got = -height(&g, r * t.cos(), r * t.sin());
                let want = strength * depth * falloff.weight(r * r / (radius * radius));
                worst = worst.max((got - want).abs());
                if a == 0 {
                    profile.push(got);
                }
            }
        }
        let rel = worst / (strength * depth);
        eprintln!(
            "brush {}: worst |surface − formula| {worst:.5} ({:.2} % of the pressed depth)",
            falloff.name(),
            100.0 * rel
        );
        errors.push((falloff, rel));
        profiles.push(profile);
    }
    // The bicubic patches (refined to r_f / 2) follow each profile to within 8 % of the
    // pressed depth; the finger's C0 rim is the worst of them (6.2 % measured).
    for (falloff, rel) in errors {
        assert!(rel <= 0.08, "{falloff:?}: {rel}");
    }
    // The brushes are told apart by far more than that.
    for i in 0..profiles.len() {
        for j in i + 1..profiles.len() {
            let d = profiles[i]
                .iter()
                .zip(&profiles[j])
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(d > 0.1 * strength * depth, "{i} vs {j}: {d}");
        }
    }
}

#[test]
fn the_finger_brush_at_full_strength_is_the_plain_push() {
    let push = Op::Push {
        at: DVec3::new(0.3, -0.2, 0.0),
        dir: DVec3::new(0.1, 0.0, -1.0),
        depth: 0.4,
        radius: 1.25,
    };
    let brushed = Op::Brushed {
        op: Box::new(push.clone()),
        brush: Brush::default(),
    };
    let (mut a, mut b) = (plane(), plane());
    Sculptor::new()
        .apply(&mut a, &push, Regulation::Exact)
        .unwrap();
    Sculptor::new()
        .apply(&mut b, &brushed, Regulation::Exact)
        .unwrap();
    assert_eq!(a.nodes(), b.nodes());
}

/// Points along `path` every `step` (by arc length), the first and last included.
fn resample(path: &[DVec3], step: f64) -> Vec<DVec3> {
    let mut out = vec![path[0]];
    let mut carry = 0.0;
    for w in path.windows(2) {
        let len = (w[1] - w[0]).length();
        let mut s = step - carry;
        while s <= len {
            out.push(w[0].lerp(w[1], s / len));
            s += step;
        }
        carry = len - (s - step);
    }
    if out.last() != path.last() {
        out.push(path[path.len() - 1]);
    }
    out
}

/// An arc of radius 4 across the plane's patches (not along their lines), densely sampled.
fn arc() -> Vec<DVec3> {
    (0..=400)
        .map(|k| {
            let t = (-50.0 + 100.0 * k as f64 / 400.0).to_radians();
            DVec3::new(4.0 * t.sin(), 4.0 * t.cos() - 3.5, 0.0)
        })
        .collect()
}

/// The groove's profile at 50 stations along the middle of the arc: depth on the centre line
/// and at `offset` either side (across the arc, i.e. radially).
fn stations(g: &Grid, offset: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut centre, mut wall) = (Vec::new(), Vec::new());
    for k in 0..50 {
        let t = (-30.0 + 60.0 * k as f64 / 49.0).to_radians();
        let c = DVec3::new(0.0, -3.5, 0.0);
        let dir = DVec3::new(t.sin(), t.cos(), 0.0);
        let p = c + 4.0 * dir;
        centre.push(-height(g, p.x, p.y));
        for s in [-1.0, 1.0] {
            let q = p + s * offset * dir;
            wall.push(-height(g, q.x, q.y));
        }
    }
    (centre, wall)
}

/// `(max − min) / mean` of the values.
fn variation(x: &[f64]) -> f64 {
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(*v), h.max(*v))
        });
    (hi - lo) / (x.iter().sum::<f64>() / x.len() as f64)
}

#[test]
fn a_drawn_groove_is_swept_not_dabbed() {
    // The issue's case: radius 0.72, depth 0.33, the window's path spacing r_f / 5.
    let (radius, depth) = (0.72, 0.33);
    let path = resample(&arc(), radius / 5.0);
    let swept = Op::Groove {
        path: path.clone(),
        dirs: Dirs::Normal,
        depth,
        radius,
    };
    let after = sculpted(&plane(), &[swept]);
    let offset = radius / 2.0;
    let (centre, wall) = stations(&after, offset);
    let (cv, wv) = (variation(&centre), variation(&wall));
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    eprintln!(
        "groove r 0.72 depth 0.33, 50 stations: centre depth mean {:.4} variation {:.3} %; \
         walls at r_f/2 mean {:.4} variation {:.3} %",
        mean(&centre),
        100.0 * cv,
        mean(&wall),
        100.0 * wv,
    );
    assert!(cv <= 0.02, "centre line varies {cv}");
    // The walls at r_f / 2: the swept finger's formula there is depth · 3/4, along the whole
    // groove (a ripple at the r_f / 5 spacing would show here).
    assert!(wv <= 0.03, "wall varies {wv}");
    assert!((mean(&centre) - depth).abs() <= 0.03 * depth);
    assert!((mean(&wall) - 0.75 * depth).abs() <= 0.03 * depth);
}

#[test]
fn brush_settings_survive_a_restart_per_tool_and_old_files_still_read() {
    let dir = temp_dir("brush-settings");
    let path = dir.join("settings.json");
    // Each tool its own brush, as the window keeps them.
    let push = ToolSettings {
        radius: 0.72,
        depth: 0.33,
        press_strength: 0.4,
        falloff: Falloff::Soft,
        ridge: true,
        ..ToolSettings::default()
    };
    let smooth = ToolSettings {
        radius: 2.5,
        strength: 0.8,
        ..ToolSettings::default()
    };
    let mut s = Settings::default();
    s.brush.store(Tool::Pull, &push);
    s.brush.store(Tool::Smooth, &smooth);
    s.save(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains("\"push\"") && text.contains("\"smooth\""),
        "{text}"
    );
    let (back, warning) = Settings::load(&path);
    assert!(warning.is_none(), "{warning:?}");
    assert_eq!(back.brush, s.brush);
    // What the window takes from them when each tool is picked.
    let mut tools = ToolSettings::default();
    back.brush.restore(Tool::Push, &mut tools);
    assert_eq!(
        (
            tools.radius,
            tools.depth,
            tools.press_strength,
            tools.strength
        ),
        (0.72, 0.33, 0.4, 0.5)
    );
    assert!(tools.ridge && tools.falloff == Falloff::Soft);
    back.brush.restore(Tool::Smooth, &mut tools);
    assert_eq!((tools.radius, tools.strength), (2.5, 0.8));
    assert!(!tools.ridge && tools.falloff == Falloff::Finger);
    // A tool not remembered, or a curve tool, leaves the panel as it is.
    let before = tools;
    back.brush.restore(Tool::Move, &mut tools);
    back.brush.restore(Tool::GrabCurve, &mut tools);
    assert_eq!(tools, before);
    // The older file: one brush for every tool.
    std::fs::write(
        &path,
        r#"{"format":"nendo-settings","version":1,"record":true,
            "brush":{"radius":0.72,"depth":0.33,"strength":0.4,"falloff":"soft","smooth_strength":0.8,"ridge":true}}"#,
    )
    .unwrap();
    let (old, warning) = Settings::load(&path);
    assert!(warning.is_none() && old.record, "{warning:?}");
    let one = BrushSettings {
        radius: 0.72,
        depth: 0.33,
        strength: 0.4,
        falloff: "soft".into(),
        smooth_strength: 0.8,
        ridge: true,
    };
    for tool in [
        Tool::Push,
        Tool::Pull,
        Tool::DrawLine,
        Tool::Smooth,
        Tool::Move,
        Tool::Hand,
    ] {
        let key = Brushes::key(tool).expect("a sculpting tool");
        assert_eq!(old.brush.tools.get(key), Some(&one), "{tool:?}");
    }
    // A file from before the brush settings reads with the defaults, no warning.
    std::fs::write(
        &path,
        r#"{"format":"nendo-settings","version":1,"record":true,"orbit":"middle"}"#,
    )
    .unwrap();
    let (older, warning) = Settings::load(&path);
    assert!(warning.is_none() && older.record);
    assert_eq!(older.brush, Brushes::default());
    // Out-of-range numbers and unknown falloffs keep the window in range.
    let odd = BrushSettings {
        radius: 1e9,
        depth: f64::NAN,
        strength: -1.0,
        falloff: "spiky".into(),
        ..BrushSettings::default()
    };
    let mut tools = ToolSettings::default();
    odd.apply_to(&mut tools);
    assert_eq!(tools.radius, 6.0);
    assert_eq!(tools.depth, ToolSettings::default().depth);
    assert_eq!(tools.press_strength, 0.01);
    assert_eq!(tools.falloff, Falloff::Finger);
}
