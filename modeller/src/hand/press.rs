//! The operation of one contact: the finger's placements applied together, as an envelope,
//! to the surface as it was before the contact. The engine lives in the geometry crate
//! ([`crate::surface::engine`]); this module re-exports it under the hand's paths.

pub use crate::surface::{Placement, Presser, Stroke, describe};

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::surface::{Grid, Primitive, PrimitiveParams, Regulation, Sculptor};

    #[test]
    fn pushing_from_inside_leaves_the_opposite_wall_alone() {
        let tube = Primitive::Tube.build(&PrimitiveParams::default()).unwrap();
        let mut grid = tube.clone();
        let push = [Placement {
            tip: DVec3::new(2.3, 0.0, 3.5),
            dir: DVec3::X,
            depth: 0.3,
        }];
        Presser::default()
            .apply(&tube, &mut grid, &push, 1.0, 2.0, Regulation::default())
            .unwrap();
        let mut probe = crate::hand::Probe::new();
        let mut wall = |g: &Grid, d: DVec3| probe_t(&mut probe, g, d);
        assert!((wall(&grid, DVec3::X) - 2.3).abs() < 0.02);
        assert_eq!(wall(&grid, -DVec3::X), wall(&tube, -DVec3::X));
        // The shape function alone (an endless finger) would press the far wall outward too.
        let mut endless = tube.clone();
        Sculptor::new()
            .apply(
                &mut endless,
                &describe(&push, 1.0)[0],
                Regulation::default(),
            )
            .unwrap();
        assert!(wall(&endless, -DVec3::X) < 1.8);
    }

    fn probe_t(probe: &mut crate::hand::Probe, g: &Grid, d: DVec3) -> f64 {
        probe
            .first_crossing(g, DVec3::new(0.0, 0.0, 3.5), d, 10.0)
            .unwrap()
            .t
    }
}
