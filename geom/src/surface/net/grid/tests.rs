//! Tests of [`super`].

use glam::DVec3;

use crate::surface::{Aabb, Primitive, PrimitiveParams};

#[test]
fn patch_and_edge_ids_are_the_lattice_ids() {
    // The shortcuts of `patch_ids` and `edge_ids` against the lattice arithmetic of
    // `node_id`, on every topology (seams, poles, open borders) and two sizes.
    for primitive in Primitive::ALL {
        for patches in [None, Some((6, 4))] {
            let grid = primitive
                .build(&PrimitiveParams {
                    patches,
                    ..PrimitiveParams::default()
                })
                .unwrap();
            let (m, n) = (grid.patches_u(), grid.patches_v());
            let shape = grid.shape();
            let lattice = |iu: usize, iv: usize, i: usize, j: usize| {
                grid.node_id((3 * iu + i) as isize, (3 * iv + j) as isize)
                    .unwrap()
            };
            for iv in 0..n {
                for iu in 0..m {
                    let ids = shape.patch_ids(iu, iv);
                    for i in 0..4 {
                        for j in 0..4 {
                            assert_eq!(ids[4 * i + j], lattice(iu, iv, i, j), "{primitive}");
                        }
                    }
                    let right = ((iu + 1) % m, iv);
                    let above = (iu, (iv + 1) % n);
                    let e = shape.edge_ids((iu, iv), right, true);
                    let f = shape.edge_ids((iu, iv), above, false);
                    for k in 0..4 {
                        let (a, b) = (iu, iv);
                        assert_eq!(e[0][k], lattice(a, b, 2, k), "{primitive}");
                        assert_eq!(e[1][k], lattice(a, b, 3, k), "{primitive}");
                        assert_eq!(e[2][k], lattice(right.0, right.1, 1, k), "{primitive}");
                        assert_eq!(f[0][k], lattice(a, b, k, 2), "{primitive}");
                        assert_eq!(f[1][k], lattice(a, b, k, 3), "{primitive}");
                        assert_eq!(f[2][k], lattice(above.0, above.1, k, 1), "{primitive}");
                    }
                }
            }
        }
    }
}

#[test]
fn set_nodes_refits_exactly_the_patches_holding_the_nodes() {
    for primitive in Primitive::ALL {
        let grid = primitive.build(&PrimitiveParams::default()).unwrap();
        for id in 0..grid.nodes().len() {
            let holding: Vec<usize> = (0..grid.patch_count())
                .filter(|&p| {
                    let (m, _) = (grid.patches_u(), grid.patches_v());
                    grid.patch_node_ids(p % m, p / m).contains(&id)
                })
                .collect();
            let mut moved = grid.clone();
            let x = grid.nodes()[id] + DVec3::new(0.25, -0.5, 1.0);
            let got = moved.set_nodes(&[(id, x)]).unwrap();
            assert_eq!(got, holding, "{primitive:?} node {id}");
            let rebuilt = crate::surface::Grid::from_net(
                grid.topology(),
                grid.patches_u(),
                grid.patches_v(),
                moved.nodes().to_vec(),
            )
            .unwrap();
            for p in 0..grid.patch_count() {
                assert_eq!(moved.patch_bounds(p), rebuilt.patch_bounds(p));
            }
            assert_eq!(moved.bounds(), rebuilt.bounds());
        }
    }
    let mut grid = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let before = grid.clone();
    assert!(grid.set_nodes(&[(0, DVec3::NAN)]).is_err());
    assert!(grid.set_nodes(&[(usize::MAX, DVec3::ZERO)]).is_err());
    assert_eq!(grid, before, "a refused change changes nothing");
}

#[test]
fn patches_where_finds_exactly_the_patches_whose_boxes_pass() {
    let grid = Primitive::Sphere
        .build(&PrimitiveParams {
            patches: Some((16, 8)),
            ..PrimitiveParams::default()
        })
        .unwrap();
    let probe = Aabb {
        min: DVec3::new(0.5, -1.0, 1.0),
        max: DVec3::new(3.5, 1.0, 3.5),
    };
    let overlaps = |b: &Aabb| probe.min.cmple(b.max).all() && b.min.cmple(probe.max).all();
    let mut got = Vec::new();
    grid.patches_where(overlaps, &mut got);
    got.sort_unstable();
    let want: Vec<usize> = (0..grid.patch_count())
        .filter(|&p| overlaps(&grid.patch_bounds(p)))
        .collect();
    assert!(!want.is_empty() && want.len() < grid.patch_count());
    assert_eq!(got, want);
}
