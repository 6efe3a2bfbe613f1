//! STEP and IGES exports read back by small independent readers written here (not nendo's
//! code): ISO 10303-21 parsed into entity instances, every reference resolved, the shell's
//! structure counted (each shared edge used by exactly two oriented edges, once each way, in a
//! closed shell), the control points round-tripped exactly, the reals in the standard's syntax;
//! IGES's fixed format checked record by record (80 columns, section letters and sequence
//! numbers, the terminate counts, directory ↔ parameter pointers and line counts, Hollerith
//! strings) and its entities' parameters decoded. Random models (fixed seeds) with coordinates
//! over many magnitudes, sculpted primitives of every topology, the curves, `--scale`, and the
//! command line.

use std::collections::HashMap;

use glam::DVec3;
use nendo::cad::{CadFormat, CadOptions, CadUnit, CurveSpline};
use nendo::curve::json::DynCurve;
use nendo::curve::{BSpline, Bezier, Curve};
use nendo::model::Model;
use nendo::surface::{
    Grid, ONE_SPLINE_TOLERANCE, Op, Primitive, PrimitiveParams, Regulation, Topology, deform,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::support::{run, temp_dir};

// ------------------------------------------------------------------ a small STEP reader

#[derive(Debug, Clone, PartialEq)]
enum Param {
    Ref(usize),
    Real(f64),
    Int(i64),
    Str(String),
    Enum(String),
    List(Vec<Param>),
    Typed(String, Vec<Param>),
    Unset,
    Derived,
}

impl Param {
    fn list(&self) -> &[Param] {
        match self {
            Param::List(v) => v,
            other => panic!("expected a list, got {other:?}"),
        }
    }
    fn reference(&self) -> usize {
        match self {
            Param::Ref(r) => *r,
            other => panic!("expected a reference, got {other:?}"),
        }
    }
    fn real(&self) -> f64 {
        match self {
            Param::Real(x) => *x,
            other => panic!("expected a real, got {other:?}"),
        }
    }
    fn int(&self) -> i64 {
        match self {
            Param::Int(x) => *x,
            other => panic!("expected an integer, got {other:?}"),
        }
    }
    fn flag(&self) -> bool {
        match self {
            Param::Enum(e) if e == "T" => true,
            Param::Enum(e) if e == "F" => false,
            other => panic!("expected .T. or .F., got {other:?}"),
        }
    }
    fn refs(&self, out: &mut Vec<usize>) {
        match self {
            Param::Ref(r) => out.push(*r),
            Param::List(v) | Param::Typed(_, v) => v.iter().for_each(|p| p.refs(out)),
            _ => {}
        }
    }
}

/// An entity instance: its type (the partial types of a complex instance joined by `+`) and
/// parameters (of a complex instance: one `Typed` per part).
#[derive(Debug, Clone)]
struct Instance {
    kind: String,
    params: Vec<Param>,
}

struct Parser<'a> {
    s: &'a [u8],
    at: usize,
}

impl Parser<'_> {
    fn skip_ws(&mut self) {
        while self.at < self.s.len() && self.s[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
    }
    fn peek(&mut self) -> u8 {
        self.skip_ws();
        self.s[self.at]
    }
    fn expect(&mut self, c: u8) {
        assert_eq!(self.peek() as char, c as char, "at byte {}", self.at);
        self.at += 1;
    }
    fn keyword(&mut self) -> String {
        self.skip_ws();
        let start = self.at;
        while self.s[self.at].is_ascii_alphanumeric() || self.s[self.at] == b'_' {
            self.at += 1;
        }
        String::from_utf8(self.s[start..self.at].to_vec()).expect("ascii")
    }
    fn params(&mut self) -> Vec<Param> {
        self.expect(b'(');
        let mut out = Vec::new();
        if self.peek() == b')' {
            self.at += 1;
            return out;
        }
        loop {
            out.push(self.param());
            match self.peek() {
                b',' => self.at += 1,
                b')' => {
                    self.at += 1;
                    return out;
                }
                c => panic!("unexpected {:?} at byte {}", c as char, self.at),
            }
        }
    }
    fn param(&mut self) -> Param {
        match self.peek() {
            b'#' => {
                self.at += 1;
                let start = self.at;
                while self.s[self.at].is_ascii_digit() {
                    self.at += 1;
                }
                Param::Ref(
                    std::str::from_utf8(&self.s[start..self.at])
                        .expect("ascii")
                        .parse()
                        .expect("a reference number"),
                )
            }
            b'(' => Param::List(self.params()),
            b'$' => {
                self.at += 1;
                Param::Unset
            }
            b'*' => {
                self.at += 1;
                Param::Derived
            }
            b'\'' => {
                self.at += 1;
                let mut text = String::new();
                loop {
                    let c = self.s[self.at];
                    self.at += 1;
                    if c == b'\'' {
                        if self.s[self.at] == b'\'' {
                            text.push('\'');
                            self.at += 1;
                            continue;
                        }
                        return Param::Str(text);
                    }
                    text.push(c as char);
                }
            }
            b'.' => {
                self.at += 1;
                let e = self.keyword();
                self.expect(b'.');
                Param::Enum(e)
            }
            c if c == b'-' || c == b'+' || c.is_ascii_digit() => {
                let start = self.at;
                while self.at < self.s.len()
                    && (self.s[self.at].is_ascii_alphanumeric()
                        || matches!(self.s[self.at], b'.' | b'-' | b'+'))
                {
                    self.at += 1;
                }
                let text = std::str::from_utf8(&self.s[start..self.at]).expect("ascii");
                if text.contains('.') {
                    assert_real_syntax(text);
                    Param::Real(text.parse().expect("a real"))
                } else {
                    Param::Int(text.parse().expect("an integer"))
                }
            }
            c if c.is_ascii_alphabetic() => {
                let name = self.keyword();
                Param::Typed(name, self.params())
            }
            c => panic!("unexpected {:?} at byte {}", c as char, self.at),
        }
    }
}

/// ISO 10303-21's REAL: `[sign] digit {digit} . {digit} [E [sign] digit {digit}]`.
fn assert_real_syntax(text: &str) {
    let body = text.strip_prefix(['-', '+']).unwrap_or(text);
    let (mantissa, exponent) = match body.split_once('E') {
        Some((m, e)) => (m, Some(e)),
        None => (body, None),
    };
    let (int, frac) = mantissa.split_once('.').expect("a decimal point");
    assert!(
        !int.is_empty()
            && int.bytes().all(|b| b.is_ascii_digit())
            && frac.bytes().all(|b| b.is_ascii_digit()),
        "not an ISO 10303-21 real: {text}"
    );
    if let Some(e) = exponent {
        let digits = e.strip_prefix(['-', '+']).unwrap_or(e);
        assert!(
            !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()),
            "not an ISO 10303-21 real: {text}"
        );
    }
}

/// The header's text and the DATA section's instances.
fn parse_step(text: &str) -> (String, HashMap<usize, Instance>) {
    assert!(
        text.starts_with("ISO-10303-21;\nHEADER;\n"),
        "{}",
        &text[..40]
    );
    assert!(text.ends_with("ENDSEC;\nEND-ISO-10303-21;\n"));
    let (header, rest) = text.split_once("DATA;").expect("a DATA section");
    let data = rest.rsplit_once("ENDSEC;").expect("ENDSEC").0;
    let mut p = Parser {
        s: data.as_bytes(),
        at: 0,
    };
    let mut out = HashMap::new();
    loop {
        p.skip_ws();
        if p.at >= p.s.len() {
            break;
        }
        p.expect(b'#');
        let id: usize = match p.param_after_hash() {
            Param::Int(i) => i as usize,
            other => panic!("{other:?}"),
        };
        p.expect(b'=');
        let instance = if p.peek() == b'(' {
            p.at += 1;
            let mut kinds = Vec::new();
            let mut params = Vec::new();
            while p.peek() != b')' {
                let name = p.keyword();
                kinds.push(name.clone());
                params.push(Param::Typed(name, p.params()));
            }
            p.at += 1;
            let mut sorted = kinds.clone();
            sorted.sort();
            assert_eq!(
                kinds, sorted,
                "#{id}: complex instance parts in alphabetical order"
            );
            Instance {
                kind: kinds.join("+"),
                params,
            }
        } else {
            let kind = p.keyword();
            Instance {
                kind,
                params: p.params(),
            }
        };
        p.expect(b';');
        assert!(out.insert(id, instance).is_none(), "#{id} defined twice");
    }
    (header.to_string(), out)
}

impl Parser<'_> {
    fn param_after_hash(&mut self) -> Param {
        let start = self.at;
        while self.s[self.at].is_ascii_digit() {
            self.at += 1;
        }
        Param::Int(
            std::str::from_utf8(&self.s[start..self.at])
                .expect("ascii")
                .parse()
                .expect("an instance number"),
        )
    }
}

fn point(data: &HashMap<usize, Instance>, id: usize) -> DVec3 {
    let inst = &data[&id];
    assert_eq!(inst.kind, "CARTESIAN_POINT");
    let c = inst.params[1].list();
    DVec3::new(c[0].real(), c[1].real(), c[2].real())
}

fn of_kind<'a>(
    data: &'a HashMap<usize, Instance>,
    kind: &'a str,
) -> impl Iterator<Item = (usize, &'a Instance)> + 'a {
    data.iter()
        .filter(move |(_, i)| i.kind == kind)
        .map(|(k, i)| (*k, i))
}

/// Patch sides on an open border (non-degenerate, used by one face).
fn border_sides(grid: &Grid) -> usize {
    let (m, n) = (grid.patches_u(), grid.patches_v());
    match grid.topology() {
        Topology::Plane => 2 * (m + n),
        Topology::Cylinder => 2 * m,
        Topology::Hemisphere => m,
        Topology::Sphere | Topology::Torus => 0,
    }
}

/// Reads a STEP export back and checks it against `model` (coordinates times `scale`).
fn check_step(text: &str, model: &Model, scale: f64, name: &str) {
    let (header, data) = parse_step(text);
    // The product is named after the model.
    let products: Vec<_> = of_kind(&data, "PRODUCT").collect();
    assert_eq!(products.len(), 1);
    assert_eq!(products[0].1.params[0], Param::Str(name.into()));
    assert!(header.contains("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));"));
    // Every reference resolves.
    for (id, inst) in &data {
        let mut r = Vec::new();
        inst.params.iter().for_each(|p| p.refs(&mut r));
        for target in r {
            assert!(
                data.contains_key(&target),
                "#{id} refers to missing #{target}"
            );
        }
    }
    // Units: millimetres.
    let units: Vec<_> = of_kind(&data, "LENGTH_UNIT+NAMED_UNIT+SI_UNIT").collect();
    assert_eq!(units.len(), 1);
    assert_eq!(
        units[0].1.params[2],
        Param::Typed(
            "SI_UNIT".into(),
            vec![Param::Enum("MILLI".into()), Param::Enum("METRE".into())]
        )
    );
    let grid = &model.surface;
    // Faces, surfaces, control points exactly.
    let faces: Vec<_> = of_kind(&data, "ADVANCED_FACE").collect();
    assert_eq!(faces.len(), grid.patch_count(), "one face per patch");
    let mut by_points: HashMap<Vec<u64>, usize> = HashMap::new();
    for k in 0..grid.patch_count() {
        let key = grid
            .patch_at(k)
            .iter()
            .flat_map(|p| (*p * scale).to_array().map(f64::to_bits))
            .collect();
        by_points.insert(key, k);
    }
    let mut seen = vec![false; grid.patch_count()];
    let mut uses: HashMap<usize, Vec<bool>> = HashMap::new();
    let mut pole_faces = 0;
    for (id, face) in &faces {
        assert!(face.params[3].flag(), "#{id} same sense");
        let surface = &data[&face.params[2].reference()];
        assert_eq!(surface.kind, "B_SPLINE_SURFACE_WITH_KNOTS");
        let p = &surface.params;
        assert_eq!((p[1].int(), p[2].int()), (3, 3), "degree 3x3");
        assert_eq!(p[8], Param::List(vec![Param::Int(4), Param::Int(4)]));
        assert_eq!(p[9], Param::List(vec![Param::Int(4), Param::Int(4)]));
        assert_eq!(p[10], Param::List(vec![Param::Real(0.0), Param::Real(1.0)]));
        assert_eq!(p[11], Param::List(vec![Param::Real(0.0), Param::Real(1.0)]));
        let rows = p[3].list();
        assert_eq!(rows.len(), 4);
        let pts: Vec<DVec3> = rows
            .iter()
            .flat_map(|r| r.list().iter().map(|q| point(&data, q.reference())))
            .collect();
        let key: Vec<u64> = pts
            .iter()
            .flat_map(|q| q.to_array().map(f64::to_bits))
            .collect();
        let k = *by_points
            .get(&key)
            .unwrap_or_else(|| panic!("#{id}'s control points are no patch's, bit for bit"));
        assert!(!seen[k], "patch {k} twice");
        seen[k] = true;
        // The loop: four oriented edges, head to tail, starting at P00 towards P30.
        let bounds = face.params[1].list();
        assert_eq!(bounds.len(), 1);
        let bound = &data[&bounds[0].reference()];
        assert_eq!(bound.kind, "FACE_OUTER_BOUND");
        let edge_loop = &data[&bound.params[1].reference()];
        assert_eq!(edge_loop.kind, "EDGE_LOOP");
        let oriented = edge_loop.params[1].list();
        // A side collapsed into a pole is left out, as OpenCASCADE writes it.
        let pole_start = pts[0] == pts[12];
        let pole_end = pts[3] == pts[15];
        assert_eq!(
            oriented.len(),
            4 - usize::from(pole_start) - usize::from(pole_end)
        );
        if pole_start || pole_end {
            pole_faces += 1;
        }
        let mut ends = Vec::new();
        for oe in oriented {
            let oe = &data[&oe.reference()];
            assert_eq!(oe.kind, "ORIENTED_EDGE");
            let edge_id = oe.params[3].reference();
            let forward = oe.params[4].flag();
            let edge = &data[&edge_id];
            assert_eq!(edge.kind, "EDGE_CURVE");
            let vertex = |k: usize| {
                let v = &data[&edge.params[k].reference()];
                assert_eq!(v.kind, "VERTEX_POINT");
                point(&data, v.params[1].reference())
            };
            let (a, b) = (vertex(1), vertex(2));
            let curve = &data[&edge.params[3].reference()];
            assert_eq!(curve.kind, "B_SPLINE_CURVE_WITH_KNOTS");
            assert_eq!(curve.params[1].int(), 3);
            let cps: Vec<DVec3> = curve.params[2]
                .list()
                .iter()
                .map(|q| point(&data, q.reference()))
                .collect();
            assert_eq!(
                (cps[0], cps[3]),
                (a, b),
                "the edge's curve joins its vertices"
            );
            assert!(
                cps.iter().any(|&q| q != cps[0]),
                "#{id}: no zero-length edge"
            );
            uses.entry(edge_id).or_default().push(forward);
            ends.push(if forward { (a, b) } else { (b, a) });
        }
        let first = if pole_start {
            (pts[12], pts[15])
        } else {
            (pts[0], pts[12])
        };
        assert_eq!(
            ends[0], first,
            "#{id}: the loop starts along v = 0 (u = 1 from a pole)"
        );
        for (this, next) in ends.iter().zip(ends.iter().cycle().skip(1)) {
            assert_eq!(this.1, next.0, "#{id}: the loop is connected");
        }
    }
    assert!(seen.iter().all(|&s| s));
    let closed = matches!(grid.topology(), Topology::Sphere | Topology::Torus);
    let once = uses.values().filter(|u| u.len() == 1).count();
    for (edge, senses) in &uses {
        assert!(
            senses.len() <= 2,
            "edge #{edge} used {} times",
            senses.len()
        );
        if senses.len() == 2 {
            assert_ne!(senses[0], senses[1], "edge #{edge}: once each way");
        }
    }
    assert_eq!(
        once,
        border_sides(grid),
        "edges used once = the open border"
    );
    let poles =
        usize::from(grid.topology().pole_at_start()) + usize::from(grid.topology().pole_at_end());
    assert_eq!(
        pole_faces,
        poles * grid.patches_u(),
        "three edges on each pole patch"
    );
    assert_eq!(
        of_kind(&data, "EDGE_CURVE").count(),
        uses.len(),
        "each edge written once"
    );
    if closed {
        assert_eq!(
            once, 0,
            "closed: every edge used by exactly two oriented edges"
        );
        let shells: Vec<_> = of_kind(&data, "CLOSED_SHELL").collect();
        assert_eq!(shells.len(), 1);
        assert_eq!(shells[0].1.params[1].list().len(), grid.patch_count());
        assert_eq!(of_kind(&data, "MANIFOLD_SOLID_BREP").count(), 1);
        assert_eq!(
            of_kind(&data, "ADVANCED_BREP_SHAPE_REPRESENTATION").count(),
            1
        );
        assert_eq!(of_kind(&data, "OPEN_SHELL").count(), 0);
    } else {
        assert_eq!(of_kind(&data, "OPEN_SHELL").count(), 1);
        assert_eq!(of_kind(&data, "SHELL_BASED_SURFACE_MODEL").count(), 1);
        assert_eq!(of_kind(&data, "CLOSED_SHELL").count(), 0);
    }
    // Curves: B-splines with the model's degree, knots and points.
    let sets: Vec<_> = of_kind(&data, "GEOMETRIC_CURVE_SET").collect();
    assert_eq!(sets.len(), usize::from(!model.curves.is_empty()));
    if let Some((_, set)) = sets.first() {
        let items = set.params[1].list();
        assert_eq!(items.len(), model.curves.len());
        for (c, item) in model.curves.iter().zip(items) {
            let want = CurveSpline::of(c);
            let curve = &data[&item.reference()];
            assert_eq!(curve.kind, "B_SPLINE_CURVE_WITH_KNOTS");
            assert_eq!(curve.params[1].int() as usize, want.degree);
            let pts: Vec<DVec3> = curve.params[2]
                .list()
                .iter()
                .map(|q| point(&data, q.reference()))
                .collect();
            let scaled: Vec<DVec3> = want.points.iter().map(|p| *p * scale).collect();
            assert_eq!(pts, scaled);
            let mults = curve.params[6].list();
            let values = curve.params[7].list();
            let mut knots = Vec::new();
            for (m, v) in mults.iter().zip(values) {
                knots.extend(std::iter::repeat_n(v.real(), m.int() as usize));
            }
            assert_eq!(knots, want.knots);
        }
    }
}

// ------------------------------------------------------------------ a small IGES reader

struct Iges {
    global: Vec<String>,
    /// (type, parameters after the type, form, label, subscript)
    entities: Vec<(u32, Vec<String>, String, String)>,
}

fn parse_iges(text: &str) -> Iges {
    let lines: Vec<&str> = text.lines().collect();
    let mut sections: HashMap<char, Vec<&str>> = HashMap::new();
    let mut order = Vec::new();
    for (k, line) in lines.iter().enumerate() {
        assert_eq!(line.len(), 80, "record {} is {} columns", k + 1, line.len());
        assert!(line.is_ascii());
        let letter = line.as_bytes()[72] as char;
        let seq: usize = line[73..].trim().parse().expect("a sequence number");
        let section = sections.entry(letter).or_default();
        section.push(line);
        assert_eq!(seq, section.len(), "{letter} records numbered from 1");
        if order.last() != Some(&letter) {
            order.push(letter);
        }
    }
    assert_eq!(
        order,
        vec!['S', 'G', 'D', 'P', 'T'],
        "sections in order, once each"
    );
    let t = sections[&'T'][0];
    let counts: Vec<usize> = [0, 8, 16, 24]
        .map(|at| t[at + 1..at + 8].trim().parse().expect("a count"))
        .to_vec();
    for (k, letter) in ['S', 'G', 'D', 'P'].into_iter().enumerate() {
        assert_eq!(&t[8 * k..8 * k + 1], letter.to_string());
        assert_eq!(counts[k], sections[&letter].len(), "T counts {letter}");
    }
    // Global: Hollerith strings and numbers, `,` and `;`.
    let g: String = sections[&'G'].iter().map(|l| l[..72].trim_end()).collect();
    let global = split_params(g.trim_end());
    // Directory pairs and their parameter lines.
    let d = &sections[&'D'];
    assert_eq!(d.len() % 2, 0);
    let p = &sections[&'P'];
    let mut entities = Vec::new();
    let mut next_p = 1;
    for pair in d.chunks(2) {
        let field = |line: &str, k: usize| line[8 * k..8 * k + 8].trim().to_string();
        let kind: u32 = field(pair[0], 0).parse().expect("type");
        assert_eq!(
            field(pair[1], 0),
            kind.to_string(),
            "both lines name the type"
        );
        let pointer: usize = field(pair[0], 1).parse().expect("pointer");
        let count: usize = field(pair[1], 3).parse().expect("line count");
        assert_eq!(pointer, next_p, "parameter data follows in order");
        next_p += count;
        let de: usize = pair[0][73..].trim().parse().expect("seq");
        let mut data = String::new();
        for line in &p[pointer - 1..pointer - 1 + count] {
            assert_eq!(
                line[64..72].trim().parse::<usize>().ok(),
                Some(de),
                "P back pointer"
            );
            data.push_str(line[..64].trim_end());
        }
        assert!(data.ends_with(';'));
        let mut params = split_params(&data);
        assert_eq!(params.remove(0), kind.to_string());
        entities.push((kind, params, field(pair[1], 7), field(pair[1], 8)));
    }
    assert_eq!(
        next_p - 1,
        p.len(),
        "every parameter line belongs to an entity"
    );
    Iges { global, entities }
}

/// Splits free-format parameters at `,` and the final `;`, reading Hollerith strings by their
/// counts (they may hold `,` and `;`).
fn split_params(s: &str) -> Vec<String> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut at = 0;
    loop {
        let start = at;
        while b[at].is_ascii_digit() {
            at += 1;
        }
        if at > start && b[at] == b'H' {
            let n: usize = s[start..at].parse().expect("count");
            out.push(s[at + 1..at + 1 + n].to_string());
            at += 1 + n;
        } else {
            while b[at] != b',' && b[at] != b';' {
                at += 1;
            }
            out.push(s[start..at].to_string());
        }
        match b[at] {
            b',' => at += 1,
            b';' => {
                assert_eq!(at + 1, b.len(), "nothing after the record delimiter");
                return out;
            }
            c => panic!("expected a delimiter, got {:?}", c as char),
        }
    }
}

fn iges_real(s: &str) -> f64 {
    assert!(s.contains('.') && !s.contains('e'), "IGES real {s}");
    s.parse().expect("a real")
}

fn check_iges(text: &str, model: &Model, scale: f64, name: &str) {
    let iges = parse_iges(text);
    assert_eq!(iges.global[3], name, "the file name is the model's");
    assert_eq!(iges.global[0], ",");
    assert_eq!(iges.global[1], ";");
    assert_eq!(iges.global[13], "2", "unit flag: millimetres");
    assert_eq!(iges.global[14], "MM");
    assert_eq!(iges.global[22], "11", "IGES 5.3");
    let grid = &model.surface;
    let members = grid.patch_count() + model.curves.len();
    assert_eq!(iges.entities.len(), members + 1);
    // The last entity is the group of all the others (directory lines 1, 3, 5, …).
    let (kind, group, label, _) = &iges.entities[members];
    assert_eq!((*kind, label.as_str()), (402, "MODEL"));
    let want: Vec<String> = std::iter::once(members.to_string())
        .chain((0..members).map(|k| (2 * k + 1).to_string()))
        .collect();
    assert_eq!(group, &want);
    for (k, (kind, p, label, subscript)) in iges.entities[..members].iter().enumerate() {
        if k < grid.patch_count() {
            assert_eq!((*kind, label.as_str()), (128, "PATCH"));
            assert_eq!(subscript, &k.to_string());
            assert_eq!(p.len(), 9 + 16 + 16 + 48 + 4);
            assert_eq!(&p[..9], ["3", "3", "3", "3", "0", "0", "1", "0", "0"]);
            let knots: Vec<f64> = p[9..25].iter().map(|s| iges_real(s)).collect();
            assert_eq!(
                knots,
                [
                    0., 0., 0., 0., 1., 1., 1., 1., 0., 0., 0., 0., 1., 1., 1., 1.
                ]
            );
            assert!(p[25..41].iter().all(|w| iges_real(w) == 1.0));
            let patch = grid.patch_at(k);
            for j in 0..4 {
                for i in 0..4 {
                    let at = 41 + 3 * (4 * j + i);
                    let got = DVec3::new(
                        iges_real(&p[at]),
                        iges_real(&p[at + 1]),
                        iges_real(&p[at + 2]),
                    );
                    assert_eq!(got, patch[4 * i + j] * scale, "patch {k} point ({i}, {j})");
                }
            }
            let range: Vec<f64> = p[89..].iter().map(|s| iges_real(s)).collect();
            assert_eq!(range, [0., 1., 0., 1.]);
        } else {
            let c = &model.curves[k - grid.patch_count()];
            let want = CurveSpline::of(c);
            let n = want.points.len();
            assert_eq!((*kind, label.as_str()), (126, "CURVE"));
            assert_eq!(p[0], (n - 1).to_string());
            assert_eq!(p[1], want.degree.to_string());
            let knots: Vec<f64> = p[6..6 + n + want.degree + 1]
                .iter()
                .map(|s| iges_real(s))
                .collect();
            assert_eq!(knots, want.knots);
            let at = 6 + n + want.degree + 1 + n;
            for (q, w) in want.points.iter().enumerate() {
                let got = DVec3::new(
                    iges_real(&p[at + 3 * q]),
                    iges_real(&p[at + 3 * q + 1]),
                    iges_real(&p[at + 3 * q + 2]),
                );
                assert_eq!(got, *w * scale);
            }
            assert_eq!(p.len(), at + 3 * n + 5);
        }
    }
}

// ------------------------------------------------------------------ the models

/// A primitive pushed in and pulled out at random places (fixed seed).
fn sculpted(primitive: Primitive, seed: u64) -> Model {
    let mut grid = primitive
        .build(&PrimitiveParams::default())
        .expect("primitive");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for _ in 0..3 {
        let k = rng.gen_range(0..grid.patch_count());
        let at = grid.eval(
            k % grid.patches_u(),
            k / grid.patches_u(),
            rng.r#gen(),
            rng.r#gen(),
        );
        let dir = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        let op = Op::Push {
            at,
            dir: dir.try_normalize().unwrap_or(DVec3::Z),
            depth: rng.gen_range(-0.3..0.3),
            radius: rng.gen_range(0.8..1.5),
        };
        // A push the exact regulation refuses leaves the grid as it was: fine here.
        let _ = deform(&mut grid, &op, Default::default());
    }
    Model::new(grid)
}

/// A plane whose control points have random magnitudes from 1e-300 to 1e29 (the coordinate
/// limit is 1e30) and signs: every real's text must read back to the same bits.
fn wild_plane(seed: u64) -> Model {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (m, n) = (3, 2);
    let nodes: Vec<DVec3> = (0..Grid::net_len(Topology::Plane, m, n))
        .map(|_| {
            DVec3::from_array(std::array::from_fn(|_| {
                let mantissa: f64 = rng.gen_range(-1.0..1.0);
                let exponent = rng.gen_range(-300..29);
                if rng.gen_bool(0.1) {
                    0.0
                } else {
                    mantissa * 10f64.powi(exponent)
                }
            }))
        })
        .collect();
    Model::new(Grid::from_net(Topology::Plane, m, n, nodes).expect("a plane"))
}

fn with_curves(mut model: Model) -> Model {
    let bez = Bezier::try_new(vec![
        DVec3::new(0.0, 0.0, 4.0),
        DVec3::new(1.0, 2.0, 5.0),
        DVec3::new(2.0, 0.0, 4.5),
        DVec3::new(3.0, 1.0, 4.0),
    ])
    .expect("bezier");
    let spline = BSpline::try_new(
        2,
        vec![0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0],
        vec![
            glam::DVec2::new(0.0, 0.0),
            glam::DVec2::new(1.0, 1.0),
            glam::DVec2::new(2.0, -0.5),
            glam::DVec2::new(3.0, 0.25),
        ],
    )
    .expect("bspline");
    model.curves.push(DynCurve::D3(Curve::Bezier(bez)));
    model.curves.push(DynCurve::D2(Curve::BSpline(spline)));
    model
}

/// Per patch, millimetres, for the model called `x`.
fn options(scale: f64) -> CadOptions {
    CadOptions {
        scale,
        ..CadOptions::named("x")
    }
}

#[test]
fn step_and_iges_of_every_topology_read_back_exactly() {
    let primitives = [
        Primitive::Sphere,
        Primitive::Torus,
        Primitive::Cylinder,
        Primitive::Hemisphere,
        Primitive::Plane,
        Primitive::Tube,
    ];
    for (seed, primitive) in primitives.into_iter().enumerate() {
        let model = with_curves(sculpted(primitive, seed as u64));
        for scale in [1.0, 25.4] {
            let step = CadFormat::Step
                .encode(&model, &options(scale), "x.step")
                .expect("STEP");
            check_step(&String::from_utf8(step).expect("ASCII"), &model, scale, "x");
            let iges = CadFormat::Iges
                .encode(&model, &options(scale), "x.igs")
                .expect("IGES");
            check_iges(&String::from_utf8(iges).expect("ASCII"), &model, scale, "x");
        }
    }
    for seed in 0..8 {
        let model = wild_plane(100 + seed);
        let step = CadFormat::Step
            .encode(&model, &options(1.0), "wild.step")
            .expect("STEP");
        check_step(&String::from_utf8(step).expect("ASCII"), &model, 1.0, "x");
        let iges = CadFormat::Iges
            .encode(&model, &options(1.0), "wild.igs")
            .expect("IGES");
        check_iges(&String::from_utf8(iges).expect("ASCII"), &model, 1.0, "x");
    }
}

#[test]
fn export_command_writes_step_and_iges_and_refuses_bad_options() {
    let dir = temp_dir("cad");
    let model_path = dir.join("sphere.json");
    let model = with_curves(sculpted(Primitive::Sphere, 7));
    model.write(&model_path).expect("write model");
    let m = model_path.to_str().expect("utf-8");
    // The file as read back from its JSON (the same numbers: JSON round-trips).
    let read = Model::read(&model_path).expect("read").model;
    for (name, step) in [
        ("a.step", true),
        ("b.STP", true),
        ("c.igs", false),
        ("d.iges", false),
    ] {
        let out = dir.join(name);
        let o = run(&["export", m, out.to_str().expect("utf-8"), "--scale", "2"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let summary = String::from_utf8_lossy(&o.stdout);
        assert!(
            summary.contains("32 patches") && summary.contains("2 curves"),
            "{summary}"
        );
        let text = std::fs::read_to_string(&out).expect("written");
        if step {
            check_step(&text, &read, 2.0, "sphere");
        } else {
            check_iges(&text, &read, 2.0, "sphere");
        }
    }
    for (args, code) in [
        (vec!["export", m, "x.step", "--scale", "0"], 2),
        (vec!["export", m, "x.igs", "--scale", "nan"], 2),
        (vec!["export", m, "x.step", "--up", "y"], 2),
        (vec!["export", m, "x.ply"], 2),
        (vec!["export", m, "x.step", "--scale", "1e308"], 2),
        (vec!["export", "/nonexistent/model.json", "x.step"], 1),
        // An option for the other kind of format is still checked, not silently ignored.
        (vec!["export", m, "x.step", "--tolerance", "nan"], 2),
        (vec!["export", m, "x.igs", "--tolerance", "-1"], 2),
        (vec!["export", m, "x.obj", "--scale", "inf"], 2),
        (vec!["export", m, "x.stl", "--scale", "0"], 2),
        (vec!["export", m, "x.obj", "--one-surface"], 2),
        (vec!["export", m, "x.stl", "--units", "cm"], 2),
        (vec!["export", m, "x.step", "--units", "ft"], 2),
    ] {
        let o = crate::support::nendo()
            .args(&args)
            .current_dir(&dir)
            .output()
            .expect("runs");
        assert_eq!(
            o.status.code(),
            Some(code),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.is_empty(), "{args:?} explains itself");
        // Numbers in the message are compact: `1e308`, not its 309 digits.
        assert!(err.len() < 300, "{args:?}: {err}");
        for name in ["x.step", "x.igs", "x.obj", "x.stl"] {
            assert!(!dir.join(name).exists(), "{args:?} wrote {name}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ------------------------------------------------------------------ one surface per model

/// Checks a one-surface STEP file: one face on one B-spline whose control points are the
/// grid's spline's (bit for bit, times the scale) on its knots, a loop of the grid's sides
/// (pole sides left out, a closed direction's seam used once each way), a solid when closed.
fn check_step_one(text: &str, model: &Model, scale: f64) {
    let (_, data) = parse_step(text);
    let grid = &model.surface;
    let spline = grid
        .one_spline(ONE_SPLINE_TOLERANCE)
        .expect("an exact grid is one spline");
    let faces: Vec<_> = of_kind(&data, "ADVANCED_FACE").collect();
    assert_eq!(faces.len(), 1, "one face");
    let face = faces[0].1;
    let surface = &data[&face.params[2].reference()];
    assert_eq!(surface.kind, "B_SPLINE_SURFACE_WITH_KNOTS");
    let p = &surface.params;
    assert_eq!((p[1].int(), p[2].int()), (3, 3));
    let rows = p[3].list();
    assert_eq!(rows.len(), 2 * grid.patches_u() + 2);
    for (i, row) in rows.iter().enumerate() {
        let row = row.list();
        assert_eq!(row.len(), 2 * grid.patches_v() + 2);
        for (j, q) in row.iter().enumerate() {
            assert_eq!(point(&data, q.reference()), spline.point(i, j) * scale);
        }
    }
    let closed = |b: bool| Param::Enum(if b { "T" } else { "F" }.into());
    assert_eq!(p[5], closed(grid.topology().closed_u()));
    assert_eq!(p[6], closed(grid.topology().closed_v()));
    for (mults, values, breaks) in [
        (&p[8], &p[10], &spline.breaks_u),
        (&p[9], &p[11], &spline.breaks_v),
    ] {
        let m: Vec<i64> = mults.list().iter().map(Param::int).collect();
        let mut want = vec![2; breaks.len()];
        want[0] = 4;
        want[breaks.len() - 1] = 4;
        assert_eq!(m, want);
        let v: Vec<f64> = values.list().iter().map(Param::real).collect();
        assert_eq!(&v, breaks);
    }
    let bound = &data[&face.params[1].list()[0].reference()];
    let edge_loop = &data[&bound.params[1].reference()];
    let oriented = edge_loop.params[1].list();
    let t = grid.topology();
    assert_eq!(oriented.len(), 4 - t.pole_count());
    let mut uses: HashMap<usize, Vec<bool>> = HashMap::new();
    for oe in oriented {
        let oe = &data[&oe.reference()];
        uses.entry(oe.params[3].reference())
            .or_default()
            .push(oe.params[4].flag());
    }
    let seams = usize::from(t.closed_u()) + usize::from(t.closed_v());
    assert_eq!(uses.values().filter(|u| u.len() == 2).count(), seams);
    for senses in uses.values().filter(|u| u.len() == 2) {
        assert_ne!(senses[0], senses[1], "a seam is used once each way");
    }
    let solid = matches!(t, Topology::Sphere | Topology::Torus);
    assert_eq!(
        of_kind(&data, "MANIFOLD_SOLID_BREP").count(),
        usize::from(solid)
    );
    assert_eq!(of_kind(&data, "OPEN_SHELL").count(), usize::from(!solid));
}

/// Checks a one-surface IGES file: one entity 128 with the spline, the curves, the group.
fn check_iges_one(text: &str, model: &Model, scale: f64) {
    let iges = parse_iges(text);
    let grid = &model.surface;
    let spline = grid
        .one_spline(ONE_SPLINE_TOLERANCE)
        .expect("an exact grid is one spline");
    assert_eq!(iges.entities.len(), 1 + model.curves.len() + 1);
    let (kind, p, label, _) = &iges.entities[0];
    assert_eq!((*kind, label.as_str()), (128, "SURFACE"));
    let (cu, cv) = (spline.count_u(), spline.count_v());
    let t = grid.topology();
    assert_eq!(
        &p[..9],
        [
            (cu - 1).to_string(),
            (cv - 1).to_string(),
            "3".into(),
            "3".into(),
            u32::from(t.closed_u()).to_string(),
            u32::from(t.closed_v()).to_string(),
            "1".into(),
            "0".into(),
            "0".into()
        ]
    );
    let knots: Vec<f64> = p[9..9 + cu + 4].iter().map(|s| iges_real(s)).collect();
    let mut want = Vec::new();
    for (k, &b) in spline.breaks_u.iter().enumerate() {
        let copies = if k == 0 || k + 1 == spline.breaks_u.len() {
            4
        } else {
            2
        };
        want.extend(std::iter::repeat_n(b, copies));
    }
    assert_eq!(knots, want);
    let at = 9 + cu + 4 + cv + 4 + cu * cv;
    for j in 0..cv {
        for i in 0..cu {
            let k = at + 3 * (j * cu + i);
            let got = DVec3::new(iges_real(&p[k]), iges_real(&p[k + 1]), iges_real(&p[k + 2]));
            assert_eq!(got, spline.point(i, j) * scale, "({i}, {j})");
        }
    }
    assert_eq!(p.len(), at + 3 * cu * cv + 4);
    let (kind, _, label, _) = iges.entities.last().expect("the group");
    assert_eq!((*kind, label.as_str()), (402, "MODEL"));
}

#[test]
fn one_surface_step_and_iges_of_every_topology() {
    let primitives = [
        Primitive::Sphere,
        Primitive::Torus,
        Primitive::Cylinder,
        Primitive::Hemisphere,
        Primitive::Plane,
        Primitive::Tube,
    ];
    for (seed, primitive) in primitives.into_iter().enumerate() {
        let model = with_curves(sculpted(primitive, 40 + seed as u64));
        let spline = model
            .surface
            .one_spline(ONE_SPLINE_TOLERANCE)
            .expect("one spline");
        assert!(spline.max_deviation < 1e-12, "{primitive:?}");
        for scale in [1.0, 25.4] {
            let opts = CadOptions {
                one_surface: true,
                ..options(scale)
            };
            let step = CadFormat::Step
                .encode(&model, &opts, "x.step")
                .expect("STEP");
            check_step_one(&String::from_utf8(step).expect("ASCII"), &model, scale);
            let iges = CadFormat::Iges
                .encode(&model, &opts, "x.igs")
                .expect("IGES");
            check_iges_one(&String::from_utf8(iges).expect("ASCII"), &model, scale);
        }
    }
}

#[test]
fn units_are_declared_as_chosen() {
    let model = sculpted(Primitive::Sphere, 3);
    for (unit, step_unit, flag, name) in [
        (CadUnit::Millimetre, "SI_UNIT(.MILLI.,.METRE.)", "2", "MM"),
        (CadUnit::Centimetre, "SI_UNIT(.CENTI.,.METRE.)", "10", "CM"),
        (CadUnit::Metre, "SI_UNIT($,.METRE.)", "6", "M"),
        (CadUnit::Inch, "CONVERSION_BASED_UNIT('INCH',", "1", "IN"),
    ] {
        let opts = CadOptions {
            unit,
            ..options(1.0)
        };
        let step = String::from_utf8(
            CadFormat::Step
                .encode(&model, &opts, "u.step")
                .expect("STEP"),
        )
        .expect("ASCII");
        assert!(step.contains(step_unit), "{unit}");
        let iges = parse_iges(
            &String::from_utf8(
                CadFormat::Iges
                    .encode(&model, &opts, "u.igs")
                    .expect("IGES"),
            )
            .expect("ASCII"),
        );
        assert_eq!(
            (iges.global[13].as_str(), iges.global[14].as_str()),
            (flag, name)
        );
        assert_eq!(unit.name().parse::<CadUnit>().ok(), Some(unit));
    }
    assert!("ft".parse::<CadUnit>().is_err());
}

#[test]
fn one_surface_of_a_grid_not_regulated_exactly_is_refused() {
    let dir = temp_dir("cad-one");
    let mut grid = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane");
    let op = Op::Push {
        at: DVec3::new(0.3, 0.2, 0.0),
        dir: DVec3::NEG_Z,
        depth: 0.5,
        radius: 1.3,
    };
    deform(&mut grid, &op, Regulation::None).expect("push");
    let path = dir.join("dented.json");
    Model::new(grid).write(&path).expect("write");
    let m = path.to_str().expect("utf-8");
    for out in ["x.step", "x.igs"] {
        let o = crate::support::nendo()
            .args(["export", m, out, "--one-surface"])
            .current_dir(&dir)
            .output()
            .expect("runs");
        assert_eq!(o.status.code(), Some(1));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("not one B-spline") && err.contains("line"),
            "{err}"
        );
        assert!(!dir.join(out).exists());
        // Per patch it is written.
        let o = run(&["export", m, dir.join(out).to_str().expect("utf-8")]);
        assert!(o.status.success());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
