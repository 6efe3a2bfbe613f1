//! Smoothing at the window's defaults (issue 27): a groove drawn with Draw a line at the
//! window's finger and depth on the default plane, then Smooth passes along it as the window
//! applies them (dabs every fifth of the finger radius at the surface points under the path,
//! each refined for and applied to the surface the previous ones left, exact regulation),
//! measured on the surface.

use glam::DVec3;
use nendo::editor::tools::ToolSettings;
use nendo::surface::{
    Dirs, Grid, Op, Primitive, PrimitiveParams, Regulation, Sculptor, nearest, refine,
};

fn plane() -> Grid {
    Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("the default plane")
}

/// The height of the surface above `(x, y)`: the nearest surface point, then Newton steps on
/// the patch parameters until the point lies on the vertical line.
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
            u -= (ex * pv.y - ey * pv.x) / det;
            v -= (pu.x * ey - pu.y * ex) / det;
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

/// `op` as the window applies it: the grid refined where it reaches, then the exact
/// regulation.
fn apply(g: &mut Grid, sculptor: &mut Sculptor, op: &Op) {
    let f = refine::for_finger(g, op).expect("a refinement");
    *g = f.refinement.apply(g).expect("refined");
    sculptor.apply(g, op, Regulation::Exact).expect("applies");
}

/// The groove's path (across the patches, not along their lines) at the window's spacing.
fn path(radius: f64) -> Vec<DVec3> {
    let n = (6.0 / (radius / 5.0)).round() as usize;
    (0..=n)
        .map(|k| DVec3::new(-3.0 + 6.0 * k as f64 / n as f64, 0.3, 0.0))
        .collect()
}

/// One Smooth pass along `path` at the window's defaults: a dab at the surface point under
/// every path point.
fn smooth_pass(g: &mut Grid, sculptor: &mut Sculptor, path: &[DVec3], t: &ToolSettings) {
    let dabs: Vec<Op> = path
        .iter()
        .map(|p| Op::Smooth {
            at: DVec3::new(p.x, p.y, height(g, p.x, p.y)),
            radius: t.radius,
            strength: t.strength,
        })
        .collect();
    for d in &dabs {
        apply(g, sculptor, d);
    }
}

/// The groove's depth: the deepest point of its middle stretch's centre line.
fn depth(g: &Grid) -> f64 {
    (0..=20)
        .map(|k| -height(g, -1.0 + 0.1 * k as f64, 0.3))
        .fold(0.0f64, f64::max)
}

/// The highest point of the surface on a 41 × 41 lattice over the plane.
fn top(g: &Grid) -> f64 {
    (0..=40)
        .flat_map(|k| (0..=40).map(move |l| (k, l)))
        .map(|(k, l)| height(g, -4.5 + 0.225 * f64::from(k), -4.5 + 0.225 * f64::from(l)))
        .fold(f64::MIN, f64::max)
}

#[test]
fn three_default_smooth_passes_halve_a_drawn_groove() {
    let t = ToolSettings::default();
    let path = path(t.radius);
    let mut g = plane();
    let mut sculptor = Sculptor::new();
    let groove = Op::Groove {
        path: path.clone(),
        dirs: Dirs::Normal,
        depth: t.depth,
        radius: t.radius,
    };
    apply(&mut g, &mut sculptor, &groove);
    let start = depth(&g);
    assert!((start - t.depth).abs() < 0.01, "the groove is {start} deep");
    let rim = top(&g);
    let mut depths = Vec::new();
    for _ in 0..3 {
        smooth_pass(&mut g, &mut sculptor, &path, &t);
        depths.push(depth(&g));
    }
    eprintln!(
        "groove r {} depth {}: {start:.4} deep; after 1/2/3 Smooth passes at strength {}:          {:.4} / {:.4} / {:.4}; highest point {rim:.3e} before, {:.3e} after",
        t.radius,
        t.depth,
        t.strength,
        depths[0],
        depths[1],
        depths[2],
        top(&g)
    );
    assert!(depths.windows(2).all(|w| w[1] < w[0]), "{depths:?}");
    assert!(depths[2] <= 0.5 * t.depth, "{depths:?}");
    // Still exactly G1 where the regulation keeps it.
    let g1 = nendo::surface::continuity::report(&g, 9).g1_max_deg;
    assert!(g1 <= 0.01, "G1 {g1}°");
}

#[test]
fn smoothing_a_flat_plane_moves_nothing() {
    let t = ToolSettings::default();
    let base = plane();
    let mut sculptor = Sculptor::new();
    for at in [
        DVec3::new(0.3, -0.7, 0.0),
        DVec3::new(-4.9, 4.9, 0.0),
        DVec3::new(5.0, 0.0, 0.0),
    ] {
        for strength in [t.strength, 1.0] {
            let mut g = base.clone();
            let op = Op::Smooth {
                at,
                radius: t.radius,
                strength,
            };
            let touched = sculptor
                .apply(&mut g, &op, Regulation::Exact)
                .expect("applies");
            assert!(touched.patches.is_empty(), "{at} {strength}: {touched:?}");
            assert_eq!(g.nodes(), base.nodes(), "{at} {strength}");
        }
    }
}
