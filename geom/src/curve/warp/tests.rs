//! Tests of [`super`].

use super::*;
use crate::curve::Bezier;

#[test]
fn rmf_of_a_planar_arc_is_orthonormal_and_keeps_the_plane_normal() {
    // A planar arc's rotation-minimising frame keeps its plane normal as one axis.
    let arc: Curve<DVec3> = Bezier::new(vec![
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 0.55, 0.0),
        DVec3::new(0.55, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ])
    .into();
    let track = Track::new(&arc);
    let rmf = <DVec3 as frames::FrameConstruction>::frames(&track, None);
    let f0 = <DVec3 as frames::FrameConstruction>::frame_at(&track, &rmf, 0.0);
    let normal_axis = if f0[1].z.abs() > 0.5 { 1 } else { 2 };
    for k in 0..=20 {
        let f = <DVec3 as frames::FrameConstruction>::frame_at(&track, &rmf, k as f64 / 20.0);
        for i in 0..3 {
            assert!((f[i].length() - 1.0).abs() < 1e-12);
            for j in i + 1..3 {
                assert!(f[i].dot(f[j]).abs() < 1e-12);
            }
        }
        assert!((f[normal_axis].z.abs() - 1.0).abs() < 1e-9, "{f:?}");
    }
}

#[test]
fn length_of_a_straight_cubic() {
    let c: Curve<DVec2> = Bezier::new(vec![
        DVec2::ZERO,
        DVec2::new(0.2, 0.0),
        DVec2::new(2.5, 0.0),
        DVec2::new(3.0, 0.0),
    ])
    .into();
    assert!((Track::new(&c).length() - 3.0).abs() < 1e-12);
}

#[test]
fn bad_parameters_are_rejected() {
    let c: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::X]).into();
    for params in [
        WarpParams {
            a: -1.0,
            ..WarpParams::default()
        },
        WarpParams {
            b: f64::NAN,
            ..WarpParams::default()
        },
        WarpParams {
            reach: 0.0,
            ..WarpParams::default()
        },
    ] {
        assert!(CurveWarp::new(vec![(c.clone(), c.clone())], params).is_err());
    }
}
