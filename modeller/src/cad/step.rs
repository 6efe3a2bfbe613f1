//! STEP export: ISO 10303-21 clear text, application protocol 214 (`AUTOMOTIVE_DESIGN`),
//! the exact surface as a boundary representation and the curves as wireframe.
//!
//! ## What becomes what
//! - Every control-net node is one `CARTESIAN_POINT` (times the scale), shared by everything
//!   that uses it, so a shared point is one value in the file as in memory.
//! - Patch `(iu, iv)` is an `ADVANCED_FACE` (same sense) on a `B_SPLINE_SURFACE_WITH_KNOTS` of
//!   degree 3×3 with knots `0,0,0,0,1,1,1,1` in both directions (multiplicities 4,4 over
//!   `0., 1.`) whose control points are the patch's own `P[4i + j]`, `i` along STEP's first
//!   parameter (nendo's `u`). Its normal `S_u × S_v` is nendo's, outward on the primitives.
//! - Its boundary is one `EDGE_LOOP` counter-clockwise in `(u, v)`: `v = 0` forward, `u = 1`
//!   forward, `v = 1` backward, `u = 0` backward. Each boundary cubic is an `EDGE_CURVE` whose
//!   3D curve is that cubic (`B_SPLINE_CURVE_WITH_KNOTS`, the four control points of the
//!   boundary row, which *are* the boundary curve of a Bezier patch) between `VERTEX_POINT`s at
//!   its ends; an edge shared by two patches (inner grid lines, closed seams) is written once
//!   and used by both faces' `ORIENTED_EDGE`s, once in each direction.
//! - A boundary row collapsed into a pole is left out of the loop, as OpenCASCADE's own writer
//!   does: a pole patch is bounded by three edges meeting at the pole vertex (OpenCASCADE's
//!   reader puts its degenerate edge back). No zero-length edges, which stricter readers
//!   reject, and no `VERTEX_LOOP`: some readers drop a face bounded by one.
//! - Closed topologies (sphere, torus: every edge shared, or a pole) give a `CLOSED_SHELL`
//!   in a `MANIFOLD_SOLID_BREP` of an `ADVANCED_BREP_SHAPE_REPRESENTATION`; the others an
//!   `OPEN_SHELL` in a `SHELL_BASED_SURFACE_MODEL` of a `MANIFOLD_SURFACE_SHAPE_REPRESENTATION`.
//! - The model's curves are `B_SPLINE_CURVE_WITH_KNOTS` (a Bezier curve on its `d+1`-fold
//!   knots 0 and 1, a B-spline on its own knots; a planar curve at `z = 0`) in a
//!   `GEOMETRIC_CURVE_SET` of a `GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION`, tied to
//!   the surface's representation by a `SHAPE_REPRESENTATION_RELATIONSHIP`.
//! - One product named after the model (`PRODUCT`, its definition and
//!   `SHAPE_DEFINITION_REPRESENTATION`), one geometric context with the length unit chosen
//!   ([`CadUnit`]: `SI_UNIT(.MILLI.,.METRE.)`, `.CENTI.`, `$` for metres, or the inch as a
//!   `CONVERSION_BASED_UNIT` of 25.4 mm), radian and steradian, and an uncertainty of `1e-7`
//!   in that unit.
//! - With [`CadOptions::one_surface`] the whole grid is one face on one B-spline surface
//!   instead ([`super::step_one`]); the rest is as above.
//!
//! Reals are written in ISO 10303-21's own syntax with full precision ([`super::real`]).

use std::collections::HashMap;
use std::fmt::Write;

use glam::DVec3;

use super::real::push_real;
use super::{CadOptions, CadUnit, CurveSpline, HeaderTimestamp};
use crate::model::Model;
use crate::surface::{Grid, GridSpline, Topology};

/// The schema written in `FILE_SCHEMA`: AP214 (automotive design).
pub const SCHEMA: &str = "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }";

/// True when a topology's surface is closed (no boundary): written as a solid.
#[must_use]
pub fn is_closed(topology: Topology) -> bool {
    matches!(topology, Topology::Sphere | Topology::Torus)
}

/// The entity instances of the DATA section, numbered in order of writing.
pub(super) struct Data {
    text: String,
    next: usize,
}

impl Data {
    /// Writes `#id=body;` and returns the id.
    pub(super) fn add(&mut self, body: &str) -> usize {
        let id = self.next;
        self.next += 1;
        let _ = writeln!(self.text, "#{id}={body};");
        id
    }
}

/// `(#a,#b,…)`.
pub(super) fn refs(ids: &[usize]) -> String {
    let mut s = String::from("(");
    for (k, id) in ids.iter().enumerate() {
        if k > 0 {
            s.push(',');
        }
        let _ = write!(s, "#{id}");
    }
    s.push(')');
    s
}

/// `(a,b,…)` of reals.
pub(super) fn reals(xs: &[f64]) -> String {
    let mut s = String::from("(");
    for (k, &x) in xs.iter().enumerate() {
        if k > 0 {
            s.push(',');
        }
        push_real(&mut s, x);
    }
    s.push(')');
    s
}

/// A STEP string literal: apostrophes doubled, anything outside printable ASCII (and the
/// backslash, STEP's escape) replaced by `_`.
fn string(text: &str) -> String {
    let mut s = String::from("'");
    for c in text.chars() {
        match c {
            '\'' => s.push_str("''"),
            ' '..='~' if c != '\\' => s.push(c),
            _ => s.push('_'),
        }
    }
    s.push('\'');
    s
}

/// A grid edge: along `u` on grid row `q` of patch column `iu`, or along `v` on grid column
/// `k` of patch row `iv` (indices reduced around closed directions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum EdgeKey {
    U { iu: usize, q: usize },
    V { k: usize, iv: usize },
}

/// The boundary structure being written: points per node, vertices, shared edges.
struct Topo<'g> {
    grid: &'g Grid,
    points: Vec<usize>,
    vertices: HashMap<usize, usize>,
    edges: HashMap<EdgeKey, usize>,
}

impl Topo<'_> {
    fn node(&self, a: usize, b: usize) -> usize {
        // Every lattice point of a patch exists (indices wrap around closed directions).
        self.grid
            .node_id(a as isize, b as isize)
            .unwrap_or_else(|| unreachable!("lattice point ({a}, {b}) of a patch"))
    }

    fn vertex(&mut self, data: &mut Data, node: usize) -> usize {
        let point = self.points[node];
        *self
            .vertices
            .entry(node)
            .or_insert_with(|| data.add(&format!("VERTEX_POINT('',#{point})")))
    }

    /// The edge for `key`, written on first use; `None` for a side collapsed into a pole,
    /// which is left out of the loop as OpenCASCADE writes it (its reader puts a degenerate
    /// edge back).
    fn edge(&mut self, data: &mut Data, key: EdgeKey) -> Option<usize> {
        let (m, n) = (self.grid.patches_u(), self.grid.patches_v());
        let topology = self.grid.topology();
        let key = match key {
            EdgeKey::U { iu, q } if topology.closed_v() => EdgeKey::U { iu, q: q % n },
            EdgeKey::V { k, iv } if topology.closed_u() => EdgeKey::V { k: k % m, iv },
            other => other,
        };
        let nodes: [usize; 4] = match key {
            EdgeKey::U { iu, q } => std::array::from_fn(|i| self.node(3 * iu + i, 3 * q)),
            EdgeKey::V { k, iv } => std::array::from_fn(|j| self.node(3 * k, 3 * iv + j)),
        };
        if nodes.iter().all(|&id| id == nodes[0]) {
            return None;
        }
        if let Some(&id) = self.edges.get(&key) {
            return Some(id);
        }
        let curve = data.add(&format!(
            "B_SPLINE_CURVE_WITH_KNOTS('',3,{},.UNSPECIFIED.,.F.,.F.,(4,4),(0.,1.),.UNSPECIFIED.)",
            refs(&nodes.map(|id| self.points[id]))
        ));
        let start = self.vertex(data, nodes[0]);
        let end = self.vertex(data, nodes[3]);
        let id = data.add(&format!("EDGE_CURVE('',#{start},#{end},#{curve},.T.)"));
        self.edges.insert(key, id);
        Some(id)
    }
}

/// What a STEP file holds, counted while writing (for summaries and tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StepCounts {
    /// `ADVANCED_FACE`s (one per patch, or one per model with the one-surface export).
    pub faces: usize,
    /// `EDGE_CURVE`s.
    pub edges: usize,
    /// Face sides collapsed into a pole, left out of their loops.
    pub pole_sides: usize,
    /// `VERTEX_POINT`s.
    pub vertices: usize,
    /// Curves of the model.
    pub curves: usize,
}

/// The ids every file's shape refers to: the product's shape definition, the geometric
/// context (with the unit), the placement.
pub(super) struct Frame {
    pds: usize,
    ctx: usize,
    axis: usize,
}

/// Writes the product (named `product`), its definition, the geometric context in `unit` and
/// the placement.
pub(super) fn frame(data: &mut Data, product: &str, unit: CadUnit) -> Frame {
    let app = data.add("APPLICATION_CONTEXT('automotive design')");
    data.add(&format!(
        "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
    ));
    let pctx = data.add(&format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
    let name = string(product);
    let product = data.add(&format!("PRODUCT({name},{name},'',(#{pctx}))"));
    data.add(&format!(
        "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{product}))"
    ));
    let formation = data.add(&format!("PRODUCT_DEFINITION_FORMATION('','',#{product})"));
    let pdctx = data.add(&format!(
        "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
    ));
    let pdef = data.add(&format!(
        "PRODUCT_DEFINITION('design','',#{formation},#{pdctx})"
    ));
    let pds = data.add(&format!("PRODUCT_DEFINITION_SHAPE('','',#{pdef})"));
    let length = match unit {
        CadUnit::Inch => {
            let mm = data.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
            let measure = data.add(&format!(
                "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#{mm})"
            ));
            let dims = data.add("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)");
            data.add(&format!(
                "(CONVERSION_BASED_UNIT('INCH',#{measure})LENGTH_UNIT()NAMED_UNIT(#{dims}))"
            ))
        }
        _ => data.add(&format!(
            "(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT({},.METRE.))",
            unit.si_prefix().unwrap_or("$")
        )),
    };
    let rad = data.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
    let sr = data.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
    let uncertainty = data.add(&format!(
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-7),#{length},'distance_accuracy_value','confusion accuracy')"
    ));
    let ctx = data.add(&format!(
        "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{uncertainty}))GLOBAL_UNIT_ASSIGNED_CONTEXT((#{length},#{rad},#{sr}))REPRESENTATION_CONTEXT('nendo','3D'))"
    ));
    let origin = data.add("CARTESIAN_POINT('',(0.,0.,0.))");
    let z = data.add("DIRECTION('',(0.,0.,1.))");
    let x = data.add("DIRECTION('',(1.,0.,0.))");
    let axis = data.add(&format!("AXIS2_PLACEMENT_3D('',#{origin},#{z},#{x})"));
    Frame { pds, ctx, axis }
}

/// The STEP file of `model` with its counts: one face per patch, or with
/// [`CadOptions::one_surface`] the one B-spline surface `spline` ([`super::step_one`]). The
/// model must pass [`super::check`].
#[must_use]
pub fn encode_counted(
    model: &Model,
    options: &CadOptions,
    spline: Option<&GridSpline>,
    file_name: &str,
    stamp: &HeaderTimestamp,
) -> (String, StepCounts) {
    let grid = &model.surface;
    let scale = options.scale;
    let mut data = Data {
        text: String::new(),
        next: 1,
    };
    let frame = frame(&mut data, &options.name, options.unit);

    // The control net, once (with one surface, only the nodes its control points are: the
    // junction points are not written; their slots hold 0, never referred to).
    let mut used = vec![spline.is_none(); grid.nodes().len()];
    if let Some(spline) = spline {
        for &id in &spline.node_ids {
            used[id] = true;
        }
    }
    let points: Vec<usize> = grid
        .nodes()
        .iter()
        .zip(&used)
        .map(|(p, &used)| {
            if used {
                data.add(&cartesian_point(*p * scale))
            } else {
                0
            }
        })
        .collect();
    let mut counts = StepCounts::default();
    let faces = match spline {
        Some(spline) => super::step_one::face(&mut data, &points, spline, &mut counts),
        None => patch_faces(&mut data, grid, points, &mut counts),
    };
    counts.faces = faces.len();
    counts.edges = data.text.matches("=EDGE_CURVE(").count();
    counts.vertices = data.text.matches("=VERTEX_POINT(").count();

    let product = string(&options.name);
    let representation = if is_closed(grid.topology()) {
        let shell = data.add(&format!("CLOSED_SHELL('',{})", refs(&faces)));
        let solid = data.add(&format!("MANIFOLD_SOLID_BREP({product},#{shell})"));
        data.add(&format!(
            "ADVANCED_BREP_SHAPE_REPRESENTATION({product},(#{solid},#{}),#{})",
            frame.axis, frame.ctx
        ))
    } else {
        let shell = data.add(&format!("OPEN_SHELL('',{})", refs(&faces)));
        let model_item = data.add(&format!("SHELL_BASED_SURFACE_MODEL({product},(#{shell}))"));
        data.add(&format!(
            "MANIFOLD_SURFACE_SHAPE_REPRESENTATION({product},(#{model_item},#{}),#{})",
            frame.axis, frame.ctx
        ))
    };
    data.add(&format!(
        "SHAPE_DEFINITION_REPRESENTATION(#{},#{representation})",
        frame.pds
    ));

    if !model.curves.is_empty() {
        let mut curves = Vec::with_capacity(model.curves.len());
        for c in &model.curves {
            let spline = CurveSpline::of(c);
            let pts: Vec<usize> = spline
                .points
                .iter()
                .map(|p| data.add(&cartesian_point(*p * scale)))
                .collect();
            let (values, mults) = spline.knots_with_multiplicities();
            curves.push(data.add(&bspline_curve(spline.degree, &pts, &values, &mults)));
        }
        counts.curves = curves.len();
        let set = data.add(&format!("GEOMETRIC_CURVE_SET('curves',{})", refs(&curves)));
        let wire = data.add(&format!(
            "GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION('curves',(#{set},#{}),#{})",
            frame.axis, frame.ctx
        ));
        data.add(&format!(
            "SHAPE_REPRESENTATION_RELATIONSHIP('curves','',#{representation},#{wire})"
        ));
    }

    let HeaderTimestamp {
        year,
        month,
        day,
        hms: (h, mi, s),
    } = *stamp;
    let mut out = String::with_capacity(data.text.len() + 1024);
    out.push_str("ISO-10303-21;\nHEADER;\n");
    let what = match spline {
        Some(_) => format!(
            "one B-spline surface (the {} bicubic Bezier patches joined)",
            grid.patch_count()
        ),
        None => format!(
            "{} bicubic Bezier patches as B-spline surfaces",
            grid.patch_count()
        ),
    };
    let _ = writeln!(
        out,
        "FILE_DESCRIPTION(('nendo exact surface: {what}, {} curves'),'2;1');",
        model.curves.len()
    );
    let _ = writeln!(
        out,
        "FILE_NAME({},'{year:04}-{month:02}-{day:02}T{h:02}:{mi:02}:{s:02}',(''),(''),'nendo {}','nendo','');",
        string(file_name),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(out, "FILE_SCHEMA(('{SCHEMA}'));\nENDSEC;\nDATA;");
    out.push_str(&data.text);
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    (out, counts)
}

/// One `ADVANCED_FACE` per patch, sewn (see the module docs); returns the faces.
fn patch_faces(
    data: &mut Data,
    grid: &Grid,
    points: Vec<usize>,
    counts: &mut StepCounts,
) -> Vec<usize> {
    let mut topo = Topo {
        grid,
        points,
        vertices: HashMap::new(),
        edges: HashMap::new(),
    };
    let mut faces = Vec::with_capacity(grid.patch_count());
    for iv in 0..grid.patches_v() {
        for iu in 0..grid.patches_u() {
            let ids = grid.patch_node_ids(iu, iv);
            let mut rows = String::from("(");
            for i in 0..4 {
                if i > 0 {
                    rows.push(',');
                }
                let row: [usize; 4] = std::array::from_fn(|j| topo.points[ids[4 * i + j]]);
                rows.push_str(&refs(&row));
            }
            rows.push(')');
            let surface = data.add(&format!(
                "B_SPLINE_SURFACE_WITH_KNOTS('',3,3,{rows},.UNSPECIFIED.,.F.,.F.,.F.,(4,4),(4,4),(0.,1.),(0.,1.),.UNSPECIFIED.)"
            ));
            let sides = [
                (EdgeKey::U { iu, q: iv }, true),
                (EdgeKey::V { k: iu + 1, iv }, true),
                (EdgeKey::U { iu, q: iv + 1 }, false),
                (EdgeKey::V { k: iu, iv }, false),
            ];
            let mut oriented = Vec::with_capacity(4);
            for (key, forward) in sides {
                let Some(edge) = topo.edge(data, key) else {
                    counts.pole_sides += 1;
                    continue;
                };
                let sense = if forward { ".T." } else { ".F." };
                oriented.push(data.add(&format!("ORIENTED_EDGE('',*,*,#{edge},{sense})")));
            }
            faces.push(face(data, &oriented, surface));
        }
    }
    faces
}

/// An `ADVANCED_FACE` (same sense) on `surface` bounded by one loop of `oriented` edges.
pub(super) fn face(data: &mut Data, oriented: &[usize], surface: usize) -> usize {
    let edge_loop = data.add(&format!("EDGE_LOOP('',{})", refs(oriented)));
    let bound = data.add(&format!("FACE_OUTER_BOUND('',#{edge_loop},.T.)"));
    data.add(&format!("ADVANCED_FACE('',(#{bound}),#{surface},.T.)"))
}

/// `B_SPLINE_CURVE_WITH_KNOTS` of degree `degree` on the points `pts` and the distinct knots
/// `values` with their multiplicities.
pub(super) fn bspline_curve(
    degree: usize,
    pts: &[usize],
    values: &[f64],
    mults: &[usize],
) -> String {
    let mults: Vec<String> = mults.iter().map(ToString::to_string).collect();
    format!(
        "B_SPLINE_CURVE_WITH_KNOTS('',{degree},{},.UNSPECIFIED.,.F.,.F.,({}),{},.UNSPECIFIED.)",
        refs(pts),
        mults.join(","),
        reals(values)
    )
}

/// The STEP file of `model` (see [`encode_counted`]).
#[must_use]
pub fn encode(
    model: &Model,
    options: &CadOptions,
    spline: Option<&GridSpline>,
    file_name: &str,
    stamp: &HeaderTimestamp,
) -> String {
    encode_counted(model, options, spline, file_name, stamp).0
}

fn cartesian_point(p: DVec3) -> String {
    format!("CARTESIAN_POINT('',{})", reals(&p.to_array()))
}
