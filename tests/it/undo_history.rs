//! Deep undo (issue 12): every edit the document supports undoes to the bit-identical model
//! and redoes to the bit-identical model, through 1 000 random strokes; the history stores
//! what each edit changed, so 1 000 typical strokes on a 256 × 256 grid fit in 100 MB.

use glam::DVec3;
use nendo::curve::json::DynCurve;
use nendo::curve::{Bezier, Curve};
use nendo::editor::Document;
use nendo::editor::curve_edit::straight_cubic;
use nendo::editor::history::History;
use nendo::model::Model;
use nendo::surface::{Op, Primitive, PrimitiveParams, Regulation};
use nendo_bench::live::{LiveStrokes, typical_stroke};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn plane(n: usize) -> Model {
    Model::new(
        Primitive::Plane
            .build(&PrimitiveParams {
                patches: Some((n, n)),
                ..PrimitiveParams::default()
            })
            .expect("plane"),
    )
}

/// The model's every number, as bits (`==` on floats would take -0.0 for 0.0).
fn bits(model: &Model) -> Vec<u64> {
    model
        .surface
        .nodes()
        .iter()
        .flat_map(|p| p.to_array())
        .chain(model.surface.ratios_u().iter().copied())
        .chain(model.surface.ratios_v().iter().copied())
        .map(f64::to_bits)
        .collect()
}

fn assert_identical(got: &Model, want: &Model, what: &str) {
    assert_eq!(got, want, "{what}: models differ");
    assert!(bits(got) == bits(want), "{what}: some bit differs");
}

/// A random point on the plane of `n × n` unit patches.
fn point(rng: &mut ChaCha8Rng, n: usize) -> DVec3 {
    let h = n as f64 / 2.0;
    DVec3::new(rng.gen_range(-h..h), rng.gen_range(-h..h), 0.0)
}

#[test]
fn a_thousand_random_edits_undo_to_the_start_and_redo_to_the_end_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(1000);
    let mut strokes = LiveStrokes::new(1000);
    let n = 12;
    let start = plane(n);
    let mut doc = Document::new(start.clone());
    let mut steps = 0usize;
    for k in 0..1000 {
        match k % 100 {
            // Every edit the document supports, among the strokes.
            10 => doc.set_regulation(Regulation::G1),
            11 => doc.set_regulation(Regulation::Exact),
            20 => {
                doc.begin_edit("add curve");
                let a = point(&mut rng, n) + DVec3::Z;
                doc.curves_mut()
                    .push(DynCurve::D3(straight_cubic(a, a + DVec3::X)));
            }
            21 if !doc.model().curves.is_empty() => {
                doc.begin_edit("grab curve");
                for _ in 0..3 {
                    if let Some(DynCurve::D3(c)) = doc.curves_mut().last_mut() {
                        let moved: Vec<DVec3> =
                            c.points().iter().map(|p| *p + 0.1 * DVec3::Z).collect();
                        *c = Curve::Bezier(Bezier::new(moved));
                    }
                }
            }
            // A change of shape (a refinement, a new primitive): kept whole.
            50 => doc.replace(
                "new plane",
                plane(if doc.model().surface.patches_u() == n {
                    n + 2
                } else {
                    n
                }),
            ),
            // A cancelled stroke records nothing.
            60 => {
                let before = doc.model().clone();
                doc.begin_stroke("push");
                let _ = doc.apply(&Op::Push {
                    at: point(&mut rng, n),
                    dir: -DVec3::Z,
                    depth: 0.3,
                    radius: 1.25,
                });
                assert!(doc.cancel_stroke());
                assert_identical(doc.model(), &before, "cancelled stroke");
                continue;
            }
            _ => typical_stroke(&mut doc, &mut strokes, n),
        }
        steps += 1;
    }
    let end = doc.model().clone();
    assert_ne!(end, start);
    assert_eq!(doc.history().undo_len(), steps, "every edit is one step");
    for _ in 0..steps {
        assert!(doc.undo());
    }
    assert!(!doc.undo(), "nothing left to undo");
    assert_identical(doc.model(), &start, "after undoing everything");
    for _ in 0..steps {
        assert!(doc.redo());
    }
    assert!(!doc.redo());
    assert_identical(doc.model(), &end, "after redoing everything");
    // Half way back and forth again, from the middle.
    for _ in 0..steps / 2 {
        assert!(doc.undo());
    }
    let middle = doc.model().clone();
    for _ in 0..steps / 2 {
        assert!(doc.redo());
    }
    assert_identical(doc.model(), &end, "redo from the middle");
    for _ in 0..steps / 2 {
        assert!(doc.undo());
    }
    assert_identical(doc.model(), &middle, "undo to the middle again");
}

#[test]
fn a_stroke_undo_changes_only_the_patches_it_touched() {
    let mut doc = Document::new(plane(64));
    let mut strokes = LiveStrokes::new(7);
    typical_stroke(&mut doc, &mut strokes, 8);
    let revision = doc.revision();
    assert!(doc.undo());
    let changed = doc
        .surface_changes_since(revision)
        .expect("undo says which patches it put back");
    assert!(
        !changed.is_empty() && changed.len() < 100,
        "{} of 4 096 patches",
        changed.len()
    );
    assert_eq!(doc.history().undo_len(), 0);
}

#[test]
fn a_thousand_typical_strokes_on_256_by_256_fit_in_100_mb() {
    let n = 256;
    let mut doc = Document::new(plane(n));
    let mut strokes = LiveStrokes::new(256);
    for _ in 0..1000 {
        typical_stroke(&mut doc, &mut strokes, n);
    }
    let history = doc.history();
    assert_eq!(history.undo_len(), 1000, "no step was dropped");
    let per_step = history.bytes() / 1000;
    eprintln!(
        "256 x 256: {} bytes per stroke, {:.1} MB for 1 000 (base model {:.1} MB)",
        per_step,
        history.bytes() as f64 / 1e6,
        history.base_bytes() as f64 / 1e6
    );
    assert!(history.bytes() < History::DEFAULT_LIMIT_BYTES);
}
