//! IGES 5.3 export: the surface's patches as entity 128 and the model's curves as entity 126,
//! all in one group, entity 402.
//!
//! ## What becomes what
//! - Patch `(iu, iv)` (in index order `iv·M + iu`) is a rational B-spline surface, entity 128
//!   form 0: degree 3×3 (`K1 = K2 = M1 = M2 = 3`), knots `0,0,0,0,1,1,1,1` both ways, all 16
//!   weights 1 (`PROP3 = 1`, polynomial), control points `P[4i + j]` listed with `i` (nendo's
//!   `u`, IGES's first parameter `s`) varying fastest as the standard orders `X(i, j)`,
//!   parameter range `[0,1]²`. Entity label `PATCH`, subscript the patch index.
//! - Curve `k` is a rational B-spline curve, entity 126 form 0: `K = n − 1`, `M` the degree,
//!   its knot vector (a Bezier curve's `d+1` zeros and `d+1` ones), weights 1, the control
//!   points (a planar curve at `z = 0`, flagged planar with normal `+z`), the parameter range
//!   its domain. Entity label `CURVE`, subscript `k`.
//! - With [`super::CadOptions::one_surface`] the whole grid is one entity 128 instead
//!   ([`GridSpline`]): `K1 = 2M + 1`, `K2 = 2N + 1`, the knots the break points with
//!   multiplicities `4, 2, …, 2, 4`, `PROP1` / `PROP2` = 1 along a closed direction (clamped,
//!   its first and last control columns the same points, so `PROP4` / `PROP5` = 0: not
//!   periodic), the parameter range `[0, M] × [0, N]`. Label `SURFACE`, subscript 0.
//! - **One group** (entity 402 form 7, an unordered group without back pointers, label
//!   `MODEL`) holds every surface and curve, which are flagged logically dependent
//!   (subordinate switch `02`): a reader finds one root, as in OpenCASCADE's own files
//!   (headless FreeCAD 0.20 crashed on files of loose top-level patches).
//! - The unit is the one chosen ([`super::CadUnit`]: flag 2 `MM`, 10 `CM`, 6 `M`, 1 `IN`),
//!   coordinates times the scale; the global section's file name and product identifications
//!   are the model's name.
//!
//! No topology entities (186/514 shells) are written: a reader gets one face per patch (one
//! in all with the one-surface export).
//!
//! ## The fixed format
//! Every record is 80 columns: data in 1–72, the section letter (`S`, `G`, `D`, `P`, `T`) in 73
//! and a sequence number right-justified in 74–80. The global section's strings are Hollerith
//! (`5Hnendo`); its parameter and record delimiters are `,` and `;`. Each entity has two
//! directory lines of nine 8-column fields (type, parameter pointer, …, status `00000000`;
//! type, weight, colour, parameter line count, form, label, subscript), and parameter lines
//! holding data in columns 1–64 and the entity's directory sequence number in 66–72. No
//! number or string is split across records. Reals use [`super::real`]'s syntax (`3.`,
//! `2.08E-17`).

use std::fmt::Write;

use super::real::{push_real, real};
use super::{CadOptions, CurveSpline, HeaderTimestamp};
use crate::model::Model;
use crate::surface::GridSpline;

/// One record line of 80 columns: `data` (at most 72 columns) padded, the section letter, the
/// sequence number.
fn record(out: &mut String, data: &str, section: char, seq: usize) {
    let _ = writeln!(out, "{data:<72}{section}{seq:>7}");
}

/// Packs `tokens` (each ending in its delimiter) into lines of at most `width` columns without
/// splitting a token.
fn pack(tokens: &[String], width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for t in tokens {
        let last = lines
            .last_mut()
            .unwrap_or_else(|| unreachable!("never empty"));
        if !last.is_empty() && last.len() + t.len() > width {
            lines.push(t.clone());
        } else {
            last.push_str(t);
        }
    }
    lines
}

/// Tokens of `values` each followed by `,`, the last by `;`.
fn delimited(values: Vec<String>) -> Vec<String> {
    let n = values.len();
    values
        .into_iter()
        .enumerate()
        .map(|(k, v)| format!("{v}{}", if k + 1 == n { ';' } else { ',' }))
        .collect()
}

/// A Hollerith string of printable ASCII (anything else becomes `_`).
fn hollerith(text: &str) -> String {
    let clean: String = text
        .chars()
        .map(|c| if (' '..='~').contains(&c) { c } else { '_' })
        .collect();
    format!("{}H{clean}", clean.len())
}

/// An entity to write: type number, label, subscript and parameters (after the type).
struct Entity {
    kind: u32,
    label: &'static str,
    subscript: usize,
    params: Vec<String>,
}

fn reals(out: &mut Vec<String>, xs: impl IntoIterator<Item = f64>) {
    out.extend(xs.into_iter().map(real));
}

/// Knots `4, 2, …, 2, 4` copies of the break points.
fn full_knots(breaks: &[f64]) -> Vec<f64> {
    let n = breaks.len();
    let mut knots = Vec::with_capacity(2 * n + 4);
    for (k, &b) in breaks.iter().enumerate() {
        let copies = if k == 0 || k + 1 == n { 4 } else { 2 };
        knots.extend(std::iter::repeat_n(b, copies));
    }
    knots
}

/// Entity 128 of the whole grid as one B-spline (see the module docs).
fn one_surface(spline: &GridSpline, scale: f64, max_coord: &mut f64) -> Entity {
    let (cu, cv) = (spline.count_u(), spline.count_v());
    let mut params: Vec<String> = vec![
        (cu - 1).to_string(),
        (cv - 1).to_string(),
        "3".into(),
        "3".into(),
        u32::from(spline.closed_u).to_string(),
        u32::from(spline.closed_v).to_string(),
        "1".into(),
        "0".into(),
        "0".into(),
    ];
    reals(&mut params, full_knots(&spline.breaks_u));
    reals(&mut params, full_knots(&spline.breaks_v));
    reals(&mut params, std::iter::repeat_n(1.0, cu * cv));
    for j in 0..cv {
        for i in 0..cu {
            let x = spline.point(i, j) * scale;
            *max_coord = max_coord.max(x.abs().max_element());
            reals(&mut params, x.to_array());
        }
    }
    let (bu, bv) = (&spline.breaks_u, &spline.breaks_v);
    reals(
        &mut params,
        [bu[0], bu[bu.len() - 1], bv[0], bv[bv.len() - 1]],
    );
    Entity {
        kind: 128,
        label: "SURFACE",
        subscript: 0,
        params,
    }
}

/// The IGES file of `model` as `options` say (one entity 128 per patch, or `spline` as one).
/// The model must pass [`super::check`].
#[must_use]
pub fn encode(
    model: &Model,
    options: &CadOptions,
    spline: Option<&GridSpline>,
    stamp: &HeaderTimestamp,
) -> String {
    let grid = &model.surface;
    let scale = options.scale;
    let mut entities = Vec::with_capacity(grid.patch_count() + model.curves.len() + 1);
    let mut max_coord = 0.0f64;
    if let Some(spline) = spline {
        entities.push(one_surface(spline, scale, &mut max_coord));
    }
    for index in (0..grid.patch_count()).filter(|_| spline.is_none()) {
        let p = grid.patch_at(index);
        let mut params: Vec<String> = ["3", "3", "3", "3", "0", "0", "1", "0", "0"]
            .map(String::from)
            .to_vec();
        for _ in 0..2 {
            reals(&mut params, [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
        }
        reals(&mut params, [1.0; 16]);
        for j in 0..4 {
            for i in 0..4 {
                let x = p[4 * i + j] * scale;
                max_coord = max_coord.max(x.abs().max_element());
                reals(&mut params, x.to_array());
            }
        }
        reals(&mut params, [0.0, 1.0, 0.0, 1.0]);
        entities.push(Entity {
            kind: 128,
            label: "PATCH",
            subscript: index,
            params,
        });
    }
    for (k, c) in model.curves.iter().enumerate() {
        let s = CurveSpline::of(c);
        let n = s.points.len();
        let planar = s.planar_z();
        let mut params = vec![
            (n - 1).to_string(),
            s.degree.to_string(),
            u32::from(planar).to_string(),
            "0".into(),
            "1".into(),
            "0".into(),
        ];
        reals(&mut params, s.knots.iter().copied());
        reals(&mut params, std::iter::repeat_n(1.0, n));
        for p in &s.points {
            let x = *p * scale;
            max_coord = max_coord.max(x.abs().max_element());
            reals(&mut params, x.to_array());
        }
        reals(&mut params, [s.knots[s.degree], s.knots[n]]);
        reals(&mut params, if planar { [0.0, 0.0, 1.0] } else { [0.0; 3] });
        entities.push(Entity {
            kind: 126,
            label: "CURVE",
            subscript: k,
            params,
        });
    }
    // The group of them all, last: members are entities 1, 3, 5, … (directory lines).
    let members = entities.len();
    let mut group = vec![members.to_string()];
    group.extend((0..members).map(|k| (2 * k + 1).to_string()));
    entities.push(Entity {
        kind: 402,
        label: "MODEL",
        subscript: 0,
        params: group,
    });

    let mut out = String::new();
    // Start section.
    let start = match spline {
        Some(_) => format!(
            "nendo exact surface: one B-spline surface (entity 128) joining {} bicubic Bezier patches, {} curves (126), in a group (402)",
            grid.patch_count(),
            model.curves.len()
        ),
        None => format!(
            "nendo exact surface: {} bicubic Bezier patches (entity 128), {} curves (126), in a group (402)",
            grid.patch_count(),
            model.curves.len()
        ),
    };
    let start_lines = pack(
        &start
            .split(' ')
            .map(|w| format!("{w} "))
            .collect::<Vec<_>>(),
        72,
    );
    for (k, line) in start_lines.iter().enumerate() {
        record(&mut out, line.trim_end(), 'S', k + 1);
    }
    // Global section.
    let HeaderTimestamp {
        year,
        month,
        day,
        hms: (h, mi, s),
    } = *stamp;
    let date = format!("{year:04}{month:02}{day:02}.{h:02}{mi:02}{s:02}");
    let name: String = options.name.chars().take(60).collect();
    let (unit_flag, unit_name) = options.unit.iges_flag();
    let mut resolution = String::new();
    push_real(&mut resolution, 1e-7);
    let global = delimited(vec![
        "1H,".into(),
        "1H;".into(),
        hollerith(&name),
        hollerith(&name),
        hollerith("nendo"),
        hollerith(&format!("nendo {}", env!("CARGO_PKG_VERSION"))),
        "32".into(),
        "38".into(),
        "6".into(),
        "308".into(),
        "15".into(),
        hollerith(&name),
        real(1.0),
        unit_flag.to_string(),
        hollerith(unit_name),
        "1".into(),
        real(1.0),
        hollerith(&date),
        resolution,
        real(max_coord),
        hollerith("nendo"),
        hollerith("nendo"),
        "11".into(),
        "0".into(),
        hollerith(&date),
    ]);
    let global_lines = pack(&global, 72);
    for (k, line) in global_lines.iter().enumerate() {
        record(&mut out, line, 'G', k + 1);
    }
    // Parameter lines first (their pointers go into the directory).
    let mut directory = String::new();
    let mut parameters = String::new();
    let mut p_seq = 1;
    for (k, e) in entities.iter().enumerate() {
        let de = 2 * k + 1;
        let mut values = vec![e.kind.to_string()];
        values.extend(e.params.iter().cloned());
        let lines = pack(&delimited(values), 64);
        let first = p_seq;
        for line in &lines {
            let _ = writeln!(parameters, "{line:<64}{de:>8}P{p_seq:>7}");
            p_seq += 1;
        }
        // The group is the one independent entity; its members depend on it logically.
        let (status, form) = if e.kind == 402 {
            ("00000000", 7)
        } else {
            ("00020000", 0)
        };
        let _ = writeln!(
            directory,
            "{:>8}{first:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{de:>7}",
            e.kind, 0, 0, 0, 0, 0, 0, status
        );
        let _ = writeln!(
            directory,
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            e.kind,
            0,
            0,
            lines.len(),
            form,
            "",
            "",
            e.label,
            e.subscript,
            de + 1
        );
    }
    out.push_str(&directory);
    out.push_str(&parameters);
    let terminate = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        start_lines.len(),
        global_lines.len(),
        2 * entities.len(),
        p_seq - 1
    );
    record(&mut out, &terminate, 'T', 1);
    out
}
