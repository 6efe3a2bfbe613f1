//! The paper's G1 regulation (P2 §4.2 and §4.3), with the misprints docs/design.md §12 names
//! corrected.
//!
//! ## Non-degenerate point (§4.2), steps (1)–(7)
//! With `P_O` the vertex and the lattice offsets `(s, t)` of [`super::GroupPoints`]:
//!
//! 1. `P_O` stays. The edge distances are `u₁ = |P_O − P(−1,0)|`, `u₂ = |P(1,0) − P_O|`,
//!    `v₁ = |P_O − P(0,−1)|`, `v₂ = |P(0,1) − P_O|`.
//! 2. The mean directions `ū = unit((P_O − P(−1,0)) + (P(1,0) − P_O))` and
//!    `v̄ = unit((P_O − P(0,−1)) + (P(0,1) − P_O))`.
//! 3. The edge points move onto these lines **each keeping its own side** and its distance:
//!    `P(∓1,0) = P_O ∓ u₁,₂ ū`, `P(0,∓1) = P_O ∓ v₁,₂ v̄`. *(Misprint: as printed, step (3)
//!    puts `P_AB = P_O − v₁ v̄'` with the `v̄'` of step (2), which points towards `P_AB`: the
//!    two v edge points would swap sides.)*
//! 4. The parallelogram vertices are `X(s,t) = P_O + s̃ ū + t̃ v̄`, `s̃ ∈ {−u₁, u₂}`,
//!    `t̃ ∈ {−v₁, v₂}`; the corners' deviations `D(s,t) = P(s,t) − X(s,t)` are replaced by one
//!    common direction `p̄ = unit(Σ sign(s̃t̃) D(s,t))`.
//! 5. `n̄ = Σ |D(s,t)|`.
//! 6. `P(s,t) = X(s,t) + s̃ t̃ / ((u₁ + u₂)(v₁ + v₂)) · n̄ p̄` for two corners, and
//! 7. for the other two: the bilinear form `P_O + s̃ū + t̃v̄ + s̃t̃w`, so every row and column
//!    of the group is collinear. *(The text
//!    has no Fig. 4 and so no corner labels; its weights `u₁v₂`, `u₂v₁` (added) and `u₂v₂`,
//!    `u₁v₁` (subtracted) are those of the bilinear form — naming the corners after their
//!    neighbouring edge points instead gives non-collinear rows.)*
//!
//! **Open boundaries.** A group cut by an open boundary (two patches) has one side only
//! along the boundary direction: that edge point keeps its place (`ū = unit(P(1,0) − P_O)`),
//! the shared direction is regulated as above, and the corners of the existing side get the
//! same bilinear form with the normaliser `Σ|s̃| · Σ|t̃|` over the offsets that exist — so the
//! two rows crossing the shared grid line are collinear, which is all G1 asks there. Grid
//! corners (one patch) carry no condition.
//!
//! ## Degenerate point (§4.3), steps (1)–(7)
//! For each pair of opposite meridians `k` and `n + k` (`2n` patches around the pole), with
//! `P_{k,0..2}` the first-ring points `ring[3k − 1 .. 3k + 1]`:
//!
//! 2. `v₁ = |O P_{k,1}|`, `v₂ = |O P_{n+k,1}|`;
//! 3. `v̄ = unit(P_{k,1}→O + O→P_{n+k,1})`, `P'_{k,1} = O − v₁ v̄`, `P'_{n+k,1} = O + v₂ v̄`;
//! 4. `ū = unit(P_{k,0}P_{k,1} + P_{k,1}P_{k,2} + P_{n+k,1}P_{n+k,0} + P_{n+k,2}P_{n+k,1})`;
//! 5. `u₁ = |P_{k,0}P_{k,1}| + |P_{n+k,1}P_{n+k,0}|`, `P'_{k,0} = P'_{k,1} − v₁/(v₁+v₂) u₁ ū`,
//!    `P'_{n+k,0} = P'_{n+k,1} + v₂/(v₁+v₂) u₁ ū` *(misprint: the paper builds `P'_{n+k,0}`
//!    from the unregulated `P_{n+k,1}`)*;
//! 6. `u₂ = |P_{k,1}P_{k,2}| + |P_{n+k,2}P_{n+k,1}|`, `P'_{k,2} = P'_{k,1} + v₁/(v₁+v₂) u₂ ū`,
//!    `P'_{n+k,2} = P'_{n+k,1} − v₂/(v₁+v₂) u₂ ū` *(misprint: the paper names this sum `u₁`
//!    and mixes `u₁` and `u₂` in the two points)*;
//! 7. repeat for `k = 0 .. n − 1`.
//!
//! Then `P'_{k,l}`, `O`, `P'_{n+k,l}` are collinear for `l = 0, 1, 2` (triangles
//! `O P_{k,0} P_{k,1}` and `O P_{n+k,0} P_{n+k,1}` similar), and each triple `P'_{k,0..2}` is
//! collinear. Each pair lies in its own plane through `O`, though: the procedure does not make
//! the whole first ring coplanar, so the pole has a tangent plane only when those planes
//! agree (for instance after a push straight down the pole axis).
//!
//! A step that would need `unit(0)` (coincident points) leaves that group or pair as it is.

use glam::DVec3;

use super::{GroupPoints, PolePoints};

/// Edge-point spacing: kept (the paper's G1 method) or made equal (the C1 baseline).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Spacing {
    /// Each edge point keeps its distance from `P_O`.
    Kept,
    /// Edge points on both sides of `P_O` are put at the mean distance (C1 rows).
    Equal,
}

/// Regulates one non-degenerate group by steps (1)–(7) of §4.2; `false` when it had to be
/// left as it is (a degenerate direction).
pub fn regulate_group(p: &mut GroupPoints) -> bool {
    construct_group(p, Spacing::Kept)
}

/// Regulates a pole by steps (1)–(7) of §4.3; `false` when no pair could be regulated.
pub fn regulate_pole(p: &mut PolePoints) -> bool {
    construct_pole(p, Spacing::Kept)
}

pub(crate) fn construct_group(p: &mut GroupPoints, spacing: Spacing) -> bool {
    let Some(o) = p[1][1] else { return false };
    // Steps (1)–(2): distances and mean directions (one side may be missing at a boundary).
    let (um, up, vm, vp) = (p[0][1], p[2][1], p[1][0], p[1][2]);
    let Some(u_dir) = (up.unwrap_or(o) - um.unwrap_or(o)).try_normalize() else {
        return false;
    };
    let Some(v_dir) = (vp.unwrap_or(o) - vm.unwrap_or(o)).try_normalize() else {
        return false;
    };
    let mut su = [
        um.map(|x| -(o - x).length()),
        Some(0.0),
        up.map(|x| (x - o).length()),
    ];
    let mut tv = [
        vm.map(|x| -(o - x).length()),
        Some(0.0),
        vp.map(|x| (x - o).length()),
    ];
    if spacing == Spacing::Equal {
        for d in [&mut su, &mut tv] {
            if let (Some(a), Some(b)) = (d[0], d[2]) {
                let h = 0.5 * (b - a);
                d[0] = Some(-h);
                d[2] = Some(h);
            }
        }
    }
    // Step (3): edge points on the mean lines, each on its own side.
    for s in [0, 2] {
        if let Some(sv) = su[s] {
            p[s][1] = Some(o + u_dir * sv);
        }
    }
    for t in [0, 2] {
        if let Some(tt) = tv[t] {
            p[1][t] = Some(o + v_dir * tt);
        }
    }
    // Steps (4)–(5): one twist direction and the summed deviation.
    let mut signed = DVec3::ZERO;
    let mut nbar = 0.0;
    let mut norm_u = 0.0;
    let mut norm_v = 0.0;
    for s in [0, 2] {
        norm_u += su[s].map_or(0.0, f64::abs);
        norm_v += tv[s].map_or(0.0, f64::abs);
    }
    for s in [0, 2] {
        for t in [0, 2] {
            let (Some(x), Some(sv), Some(tt)) = (p[s][t], su[s], tv[t]) else {
                continue;
            };
            let d = x - (o + u_dir * sv + v_dir * tt);
            signed += d * (sv * tt).signum();
            nbar += d.length();
        }
    }
    let norm = norm_u * norm_v;
    let twist = match signed.try_normalize() {
        Some(pbar) if norm > 0.0 => pbar * (nbar / norm),
        _ => DVec3::ZERO,
    };
    // Steps (6)–(7): the corners on the bilinear form.
    for s in [0, 2] {
        for t in [0, 2] {
            let (Some(_), Some(sv), Some(tt)) = (p[s][t], su[s], tv[t]) else {
                continue;
            };
            p[s][t] = Some(o + u_dir * sv + v_dir * tt + twist * (sv * tt));
        }
    }
    true
}

pub(crate) fn construct_pole(p: &mut PolePoints, spacing: Spacing) -> bool {
    let len = p.ring.len();
    if len < 18 || !len.is_multiple_of(6) {
        return false;
    }
    let n = len / 6; // 2n meridians, 3 ring points per meridian
    let o = p.pole;
    let r = p.ring.clone();
    let at = |a: isize| (a.rem_euclid(len as isize)) as usize;
    let mut any = false;
    for k in 0..n {
        let (a, b) = (3 * k as isize, 3 * (n + k) as isize);
        let (pk, pn) = (
            [r[at(a - 1)], r[at(a)], r[at(a + 1)]],
            [r[at(b - 1)], r[at(b)], r[at(b + 1)]],
        );
        // Steps (2)–(3).
        let (mut v1, mut v2) = ((pk[1] - o).length(), (pn[1] - o).length());
        let Some(vbar) = ((o - pk[1]) + (pn[1] - o)).try_normalize() else {
            continue;
        };
        if spacing == Spacing::Equal {
            let h = 0.5 * (v1 + v2);
            (v1, v2) = (h, h);
        }
        if v1 + v2 <= 0.0 || (v1 + v2).is_nan() {
            continue;
        }
        let pk1 = o - vbar * v1;
        let pn1 = o + vbar * v2;
        // Step (4).
        let Some(ubar) =
            ((pk[1] - pk[0]) + (pk[2] - pk[1]) + (pn[0] - pn[1]) + (pn[1] - pn[2])).try_normalize()
        else {
            continue;
        };
        // Steps (5)–(6), with the regulated P'_{n+k,1} and one sum per side.
        let u1 = (pk[1] - pk[0]).length() + (pn[0] - pn[1]).length();
        let u2 = (pk[2] - pk[1]).length() + (pn[1] - pn[2]).length();
        let (wk, wn) = (v1 / (v1 + v2), v2 / (v1 + v2));
        let (d0, d2) = match spacing {
            Spacing::Kept => (u1, u2),
            Spacing::Equal => (0.5 * (u1 + u2), 0.5 * (u1 + u2)),
        };
        p.ring[at(a - 1)] = pk1 - ubar * (wk * d0);
        p.ring[at(a)] = pk1;
        p.ring[at(a + 1)] = pk1 + ubar * (wk * d2);
        p.ring[at(b - 1)] = pn1 + ubar * (wn * d0);
        p.ring[at(b)] = pn1;
        p.ring[at(b + 1)] = pn1 - ubar * (wn * d2);
        any = true;
    }
    any
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bilinear group `P_O + s̃ū + t̃v̄ + s̃t̃w` with unequal spacings and a twist.
    fn bilinear(u1: f64, u2: f64, v1: f64, v2: f64) -> GroupPoints {
        let o = DVec3::new(0.3, -0.2, 0.1);
        let (u, v, w) = (
            DVec3::new(1.0, 0.1, 0.0).normalize(),
            DVec3::new(-0.2, 1.0, 0.3).normalize(),
            DVec3::new(0.1, 0.2, 0.7),
        );
        let ss = [-u1, 0.0, u2];
        let tt = [-v1, 0.0, v2];
        let mut p = [[None; 3]; 3];
        for s in 0..3 {
            for t in 0..3 {
                p[s][t] = Some(o + u * ss[s] + v * tt[t] + w * (ss[s] * tt[t]));
            }
        }
        p
    }

    fn perturbed(seed: u64) -> GroupPoints {
        let mut p = bilinear(0.3, 0.45, 0.25, 0.4);
        let mut u = crate::seeded::unit(seed);
        for s in 0..3 {
            for t in 0..3 {
                if (s, t) == (1, 1) {
                    continue;
                }
                let mut r = || (u() - 0.5) * 0.1;
                p[s][t] = p[s][t].map(|q| q + DVec3::new(r(), r(), r()));
            }
        }
        p
    }

    fn collinear(a: DVec3, b: DVec3, c: DVec3) -> f64 {
        (b - a).cross(c - b).length() / ((b - a).length() * (c - b).length())
    }

    /// Every row and column of the group is collinear (sine of the kink).
    fn worst_kink(p: &GroupPoints) -> f64 {
        let g = |s: usize, t: usize| p[s][t].unwrap();
        let mut worst = 0.0f64;
        for k in 0..3 {
            worst = worst.max(collinear(g(0, k), g(1, k), g(2, k)));
            worst = worst.max(collinear(g(k, 0), g(k, 1), g(k, 2)));
        }
        worst
    }

    #[test]
    fn regulated_groups_have_collinear_rows_and_columns() {
        for seed in 0..50 {
            let mut p = perturbed(seed);
            assert!(worst_kink(&p) > 1e-3);
            assert!(regulate_group(&mut p));
            assert!(worst_kink(&p) < 1e-12, "{seed}: {}", worst_kink(&p));
        }
    }

    #[test]
    fn a_bilinear_group_is_a_fixed_point() {
        let before = bilinear(0.3, 0.45, 0.25, 0.4);
        let mut p = before;
        regulate_group(&mut p);
        for s in 0..3 {
            for t in 0..3 {
                assert!((p[s][t].unwrap() - before[s][t].unwrap()).length() < 1e-14);
            }
        }
    }

    /// Step (3) as printed, with `P_AB` the point at `t = −1` (distance `v₁`) and `P_CD` at
    /// `t = +1`: step (2)'s `v̄' = unit(P_O→P_AB + P_CD→P_O)` points towards `P_AB`, and step (3)
    /// sets `P_AB = P_O − v₁ v̄'`, `P_CD = P_O + v₂ v̄'`.
    fn step3_as_printed(p: &mut GroupPoints) {
        let o = p[1][1].unwrap();
        let (ab, cd) = (p[1][0].unwrap(), p[1][2].unwrap());
        let (v1, v2) = ((ab - o).length(), (o - cd).length());
        let vbar = ((ab - o) + (o - cd)).normalize();
        p[1][0] = Some(o - vbar * v1);
        p[1][2] = Some(o + vbar * v2);
    }

    #[test]
    fn misprint_step_3_orientation_would_swap_the_edge_points() {
        // Each edge point keeps its side: the fixed-point test above fails with the printed
        // orientation, as this shows.
        let before = bilinear(0.3, 0.45, 0.25, 0.4);
        let mut printed = before;
        step3_as_printed(&mut printed);
        let moved = (printed[1][2].unwrap() - before[1][2].unwrap()).length();
        assert!(
            moved > 0.5,
            "the printed step (3) moves a settled point by {moved}"
        );
        let mut ours = before;
        regulate_group(&mut ours);
        let o = ours[1][1].unwrap();
        assert!((ours[1][2].unwrap() - o).dot(before[1][2].unwrap() - o) > 0.0);
        assert!((ours[1][0].unwrap() - o).dot(before[1][0].unwrap() - o) > 0.0);
    }

    /// Steps (6)–(7) with the corners named after their neighbouring edge points (A between
    /// DA and AB, …) instead of by the bilinear weights.
    fn corners_named_by_neighbours(p: &mut GroupPoints) {
        construct_group(p, Spacing::Kept);
        let o = p[1][1].unwrap();
        let (u1, u2) = (
            (o - p[0][1].unwrap()).length(),
            (p[2][1].unwrap() - o).length(),
        );
        let (v1, v2) = (
            (o - p[1][0].unwrap()).length(),
            (p[1][2].unwrap() - o).length(),
        );
        let u = (p[2][1].unwrap() - p[0][1].unwrap()).normalize();
        let v = (p[1][2].unwrap() - p[1][0].unwrap()).normalize();
        let x = |s: f64, t: f64| o + u * s + v * t;
        // A = (−u₁, −v₁), B = (u₂, −v₁), C = (u₂, v₂), D = (−u₁, v₂) with the printed weights.
        let corners = [
            (0, 0, -u1, -v1),
            (2, 0, u2, -v1),
            (2, 2, u2, v2),
            (0, 2, -u1, v2),
        ];
        let mut dev = [DVec3::ZERO; 4];
        for (k, &(s, t, ss, tt)) in corners.iter().enumerate() {
            dev[k] = p[s][t].unwrap() - x(ss, tt);
        }
        let pbar = (dev[0] + dev[2] - dev[1] - dev[3])
            .try_normalize()
            .unwrap_or(DVec3::ZERO);
        let nbar: f64 = dev.iter().map(|d| d.length()).sum();
        let q = (u1 + u2) * (v1 + v2);
        let w = [u1 * v2, -(u2 * v2), u2 * v1, -(u1 * v1)];
        for (k, &(s, t, ss, tt)) in corners.iter().enumerate() {
            p[s][t] = Some(x(ss, tt) + pbar * (w[k] / q * nbar));
        }
    }

    #[test]
    fn misprint_corner_labels_would_break_collinearity() {
        let mut printed = perturbed(3);
        corners_named_by_neighbours(&mut printed);
        assert!(worst_kink(&printed) > 1e-3, "{}", worst_kink(&printed));
        let mut ours = perturbed(3);
        regulate_group(&mut ours);
        assert!(worst_kink(&ours) < 1e-12);
    }

    #[test]
    fn boundary_groups_make_the_crossing_rows_collinear() {
        let mut p = perturbed(9);
        // Cut by the open boundary on the −u side.
        p[0] = [None; 3];
        assert!(regulate_group(&mut p));
        let g = |s: usize, t: usize| p[s][t].unwrap();
        for s in 1..3 {
            assert!(collinear(g(s, 0), g(s, 1), g(s, 2)) < 1e-12);
        }
    }

    /// A pole with `2n` meridians: first ring on a wavy cone, pole at the origin.
    fn pole(n: usize, seed: u64) -> PolePoints {
        let mut u = crate::seeded::unit(seed);
        let mut r = || (u() - 0.5) * 0.2;
        let len = 6 * n;
        let ring = (0..len)
            .map(|a| {
                let phi = std::f64::consts::TAU * a as f64 / len as f64;
                DVec3::new(
                    phi.cos() * (1.0 + r()),
                    phi.sin() * (1.0 + r()),
                    0.3 * phi.sin() + r(),
                )
            })
            .collect();
        PolePoints {
            pole: DVec3::ZERO,
            ring,
        }
    }

    fn pair_defects(p: &PolePoints) -> (f64, f64) {
        let len = p.ring.len();
        let n = len / 6;
        let at = |a: isize| p.ring[a.rem_euclid(len as isize) as usize];
        let (mut through_pole, mut along) = (0.0f64, 0.0f64);
        for k in 0..n {
            let (a, b) = (3 * k as isize, 3 * (n + k) as isize);
            for l in -1..=1 {
                through_pole = through_pole.max(collinear(at(a + l), p.pole, at(b + l)));
            }
            along = along.max(collinear(at(a - 1), at(a), at(a + 1)));
            along = along.max(collinear(at(b - 1), at(b), at(b + 1)));
        }
        (through_pole, along)
    }

    #[test]
    fn every_opposite_pair_is_collinear_through_the_pole() {
        for seed in 0..20 {
            let mut p = pole(4, seed);
            assert!(regulate_pole(&mut p));
            let (through, along) = pair_defects(&p);
            assert!(
                through < 1e-12 && along < 1e-12,
                "{seed}: {through} {along}"
            );
        }
    }

    /// Steps (5)–(6) as printed: `P'_{n+k,0}` from the unregulated `P_{n+k,1}`, and the
    /// step-(5) sum used for `P'_{n+k,2}`.
    fn pole_as_printed(p: &mut PolePoints) {
        let len = p.ring.len();
        let n = len / 6;
        let o = p.pole;
        let r = p.ring.clone();
        let at = |a: isize| (a.rem_euclid(len as isize)) as usize;
        for k in 0..n {
            let (a, b) = (3 * k as isize, 3 * (n + k) as isize);
            let (pk, pn) = (
                [r[at(a - 1)], r[at(a)], r[at(a + 1)]],
                [r[at(b - 1)], r[at(b)], r[at(b + 1)]],
            );
            let (v1, v2) = ((pk[1] - o).length(), (pn[1] - o).length());
            let vbar = ((o - pk[1]) + (pn[1] - o)).normalize();
            let (pk1, pn1) = (o - vbar * v1, o + vbar * v2);
            let ubar =
                ((pk[1] - pk[0]) + (pk[2] - pk[1]) + (pn[0] - pn[1]) + (pn[1] - pn[2])).normalize();
            let u1 = (pk[1] - pk[0]).length() + (pn[0] - pn[1]).length();
            let u2 = (pk[2] - pk[1]).length() + (pn[1] - pn[2]).length();
            let (wk, wn) = (v1 / (v1 + v2), v2 / (v1 + v2));
            p.ring[at(a - 1)] = pk1 - ubar * (wk * u1);
            p.ring[at(a)] = pk1;
            p.ring[at(a + 1)] = pk1 + ubar * (wk * u2);
            p.ring[at(b - 1)] = pn[1] + ubar * (wn * u1); // printed: P_{n+k,1}
            p.ring[at(b)] = pn1;
            p.ring[at(b + 1)] = pn1 - ubar * (wn * u1); // printed: u1 for this point
        }
    }

    #[test]
    fn misprints_in_the_pole_steps_would_break_collinearity_through_the_pole() {
        let mut printed = pole(4, 5);
        pole_as_printed(&mut printed);
        let (through, _) = pair_defects(&printed);
        assert!(through > 1e-3, "{through}");
        let mut ours = pole(4, 5);
        regulate_pole(&mut ours);
        assert!(pair_defects(&ours).0 < 1e-12);
    }
}
