//! STEP's one-surface face: the whole grid as one `ADVANCED_FACE` on one
//! `B_SPLINE_SURFACE_WITH_KNOTS` (`nendo export --one-surface`).
//!
//! ## What is written
//! - The surface: degree 3×3 on the grid's [`GridSpline`] — control point `(i, j)` the net
//!   node at lattice column `columns[i]`, row `rows[j]` (`i` along STEP's first parameter,
//!   nendo's `u`), the knots the break points `U_k` with multiplicities `4, 2, …, 2, 4` (and
//!   `V_q` likewise). Closed directions are clamped, not periodic: their first and last control
//!   columns are the same points, flagged `u_closed` / `v_closed` (`.T.`). Same sense: the
//!   normal `S_u × S_v` is the patches' own.
//! - Its one loop runs counter-clockwise in `(u, v)` as the patches' do: `v = 0` forward,
//!   `u = U_M` forward, `v = V_N` backward, `u = 0` backward. Each side is an `EDGE_CURVE` whose
//!   3D curve is that boundary of the spline (the boundary row of its control points on the
//!   same knots) between `VERTEX_POINT`s at the grid's corners.
//! - **Closed directions get a seam edge**, as OpenCASCADE expects of a closed surface: the
//!   sides `u = 0` and `u = U_M` of a closed `u` are the same curve, written once and used
//!   twice, once each way (a cylinder's or a sphere's meridian seam; a torus has two seams
//!   and one vertex). A closed boundary curve (a cylinder's rim) starts and ends at one vertex.
//! - **Poles**: a side collapsed into a pole is left out of the loop, as OpenCASCADE writes a
//!   sphere's poles (its reader puts the degenerate edges back): a sphere's face is bounded by
//!   its seam alone, from pole to pole and back.

use std::collections::HashMap;

use super::step::{Data, StepCounts, bspline_curve, face as advanced_face, reals, refs};
use crate::surface::GridSpline;

/// Distinct knots and multiplicities of break points: `4, 2, …, 2, 4`.
fn multiplicities(breaks: &[f64]) -> String {
    let n = breaks.len();
    let mults: Vec<String> = (0..n)
        .map(|k| if k == 0 || k + 1 == n { "4" } else { "2" }.to_owned())
        .collect();
    format!("({})", mults.join(","))
}

/// Writes the one face of `spline` (`points[node]`: the `CARTESIAN_POINT` of each net node)
/// and returns it (as a one-element list, the shell's faces).
pub(super) fn face(
    data: &mut Data,
    points: &[usize],
    spline: &GridSpline,
    counts: &mut StepCounts,
) -> Vec<usize> {
    let (cu, cv) = (spline.count_u(), spline.count_v());
    let node = |i: usize, j: usize| spline.node_ids[i * cv + j];
    let mut rows = String::from("(");
    for i in 0..cu {
        if i > 0 {
            rows.push(',');
        }
        let row: Vec<usize> = (0..cv).map(|j| points[node(i, j)]).collect();
        rows.push_str(&refs(&row));
    }
    rows.push(')');
    let flag = |b: bool| if b { ".T." } else { ".F." };
    let surface = data.add(&format!(
        "B_SPLINE_SURFACE_WITH_KNOTS('',3,3,{rows},.UNSPECIFIED.,{},{},.F.,{},{},{},{},.UNSPECIFIED.)",
        flag(spline.closed_u),
        flag(spline.closed_v),
        multiplicities(&spline.breaks_u),
        multiplicities(&spline.breaks_v),
        reals(&spline.breaks_u),
        reals(&spline.breaks_v),
    ));

    // The four sides as node sequences, counter-clockwise, with their sense.
    let row_v = |j: usize| (0..cu).map(|i| node(i, j)).collect::<Vec<_>>();
    let col_u = |i: usize| (0..cv).map(|j| node(i, j)).collect::<Vec<_>>();
    let sides = [
        (row_v(0), &spline.breaks_u, true),
        (col_u(cu - 1), &spline.breaks_v, true),
        (row_v(cv - 1), &spline.breaks_u, false),
        (col_u(0), &spline.breaks_v, false),
    ];
    let mut vertices: HashMap<usize, usize> = HashMap::new();
    let mut edges: HashMap<Vec<usize>, usize> = HashMap::new();
    let mut oriented = Vec::with_capacity(4);
    for (nodes, breaks, forward) in sides {
        if nodes.iter().all(|&id| id == nodes[0]) {
            counts.pole_sides += 1;
            continue;
        }
        let edge = match edges.get(&nodes) {
            Some(&id) => id,
            None => {
                let pts: Vec<usize> = nodes.iter().map(|&id| points[id]).collect();
                let mults: Vec<usize> = (0..breaks.len())
                    .map(|k| {
                        if k == 0 || k + 1 == breaks.len() {
                            4
                        } else {
                            2
                        }
                    })
                    .collect();
                let curve = data.add(&bspline_curve(3, &pts, breaks, &mults));
                let mut vertex = |id: usize| {
                    *vertices
                        .entry(id)
                        .or_insert_with(|| data.add(&format!("VERTEX_POINT('',#{})", points[id])))
                };
                let start = vertex(nodes[0]);
                let end = vertex(nodes[nodes.len() - 1]);
                let id = data.add(&format!("EDGE_CURVE('',#{start},#{end},#{curve},.T.)"));
                edges.insert(nodes, id);
                id
            }
        };
        let sense = if forward { ".T." } else { ".F." };
        oriented.push(data.add(&format!("ORIENTED_EDGE('',*,*,#{edge},{sense})")));
    }
    vec![advanced_face(data, &oriented, surface)]
}
