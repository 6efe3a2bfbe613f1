//! Fitting metacircles to the shipped figures' contours (P0 §4.2 1)): residuals, the
//! shipped metacircles' own residual, and the pictures.

use std::path::{Path, PathBuf};

use glam::DVec2;
use nendo::figure::fit::{FitOptions, FitReport, fit_contour, measure};
use nendo::figure::optimise::{Optimiser, Stopping};
use nendo::figure::{Contour, FigureDocument, PictureOptions, picture};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/figures")
        .join(name)
}

fn load(name: &str) -> FigureDocument {
    FigureDocument::from_json(&std::fs::read_to_string(data(name)).unwrap()).unwrap()
}

/// The residual bounds every shipped figure meets, in figure units (pixels of a 512 × 512
/// picture): samples within 2 px of the iso-curve, RMS under 0.5 px, no stray part of the
/// boundary farther than 6 px from the contour (metacircles round the contour's sharp
/// corners: hooves, ears), no guard point on the wrong side.
fn assert_good_fit(name: &str, r: &FitReport) {
    eprintln!("{name}: {r:?}");
    assert!(r.rms_distance < 0.5, "{name}: {r:?}");
    assert!(r.max_distance < 2.0, "{name}: {r:?}");
    assert!(r.boundary_distance < 6.0, "{name}: {r:?}");
    assert_eq!(r.guards_violated, 0, "{name}: {r:?}");
    assert!(r.final_cost < 1e-3 * r.initial_cost, "{name}: {r:?}");
}

#[test]
fn shipped_contours_fit_within_a_pixel() {
    for name in ["horse.json", "tiger.json"] {
        let doc = load(name);
        let contour = doc.contour.as_ref().unwrap();
        let (fig, report) = fit_contour(contour, &FitOptions::default()).unwrap();
        assert_good_fit(name, &report);
        assert!(
            fig.metacircles.len() > 100,
            "{name}: {}",
            fig.metacircles.len()
        );
    }
}

#[test]
fn shipped_metacircles_fit_their_contours() {
    for name in ["horse.json", "tiger.json"] {
        let doc = load(name);
        let d = FitOptions::default();
        let mut r = measure(
            &doc.figure,
            doc.contour.as_ref().unwrap(),
            d.samples,
            d.guard_resolution,
        );
        r.initial_cost = 1.0; // measured only: no optimisation to compare with
        assert_good_fit(name, &r);
    }
}

#[test]
fn steepest_descent_lowers_the_residual_too() {
    let ellipse = Contour::new(
        (0..60)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 60.0;
                DVec2::new(120.0 * t.cos(), 50.0 * t.sin() + 10.0 * (2.0 * t).sin())
            })
            .collect(),
        "ellipse",
    )
    .unwrap();
    let opts = |optimiser| FitOptions {
        optimiser,
        stopping: Stopping {
            max_iterations: 300,
            relative_decrease: 0.0,
        },
        ..FitOptions::default()
    };
    let (_, sd) = fit_contour(&ellipse, &opts(Optimiser::SteepestDescent)).unwrap();
    let (_, lm) = fit_contour(&ellipse, &opts(Optimiser::LevenbergMarquardt)).unwrap();
    eprintln!("descent {sd:?}\nLM {lm:?}");
    assert!(sd.final_cost < 0.01 * sd.initial_cost, "{sd:?}");
    assert!(lm.max_distance < 0.005 * lm.size, "{lm:?}");
    assert_eq!(sd.guards_violated + lm.guards_violated, 0);
}

#[test]
fn shipped_figures_draw_inside_their_contours() {
    for name in ["horse.json", "tiger.json"] {
        let doc = load(name);
        let pic = picture(&doc, &PictureOptions::default()).unwrap();
        assert_eq!((pic.image.size.width, pic.image.size.height), (512, 512));
        // Pixels well inside / outside the contour are filled / background.
        let contour = doc.contour.as_ref().unwrap();
        let (mut checked, mut wrong) = (0, 0);
        for y in (0..512).step_by(4) {
            for x in (0..512).step_by(4) {
                let p = pic
                    .view
                    .to_figure(DVec2::new(x as f64 + 0.5, y as f64 + 0.5));
                if contour.distance(p) < 4.0 {
                    continue;
                }
                let filled = pic.image.pixel(x, y) != [255, 255, 255, 255];
                checked += 1;
                wrong += usize::from(filled != contour.contains(p));
            }
        }
        assert!(checked > 10_000);
        assert_eq!(wrong, 0, "{name}");
        // One boundary loop, and the SVG holds it.
        let loops = pic.boundary.iter().filter(|l| l.closed).count();
        assert_eq!(loops, 1, "{name}");
        assert!(pic.svg.contains("fill-rule=\"evenodd\""));
    }
}
