//! `nendo render` end to end: a model file in, a PNG of the asked size out, drawn by the same
//! renderer as the window; bad arguments are refused with a message.
#![cfg(feature = "gui")]

use std::process::Command;

use nendo::model::Model;
use nendo::render::RgbaImage;
use nendo::surface::{Primitive, PrimitiveParams};

#[test]
fn renders_a_model_to_png_and_refuses_bad_arguments() {
    let dir = std::env::temp_dir().join(format!("nendo-render-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let model = dir.join("torus.nendo.json");
    Model::new(
        Primitive::Torus
            .build(&PrimitiveParams::default())
            .expect("torus"),
    )
    .write(&model)
    .expect("write");
    let png = dir.join("torus.png");
    let out = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args([
            "render",
            model.to_str().expect("utf-8"),
            "--png",
            png.to_str().expect("utf-8"),
        ])
        .args(["--size", "200x120", "--view", "top", "--heat"])
        .output()
        .expect("nendo runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let image = RgbaImage::read_png(&std::fs::read(&png).expect("the PNG exists")).expect("a PNG");
    assert_eq!((image.width, image.height), (200, 120));
    // From the top, the torus's hole shows the background at the centre, clay around it.
    let px = |x: u32, y: u32| {
        let i = 4 * (y * image.width + x) as usize;
        [image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]]
    };
    let [r, g, b] = px(100, 60);
    assert!(r.abs_diff(b) < 40, "background in the hole: {r} {g} {b}");
    let [r, g, b] = px(100, 60 - 45);
    assert!(r > g && g > b && r > 100, "clay on the ring: {r} {g} {b}");

    for (args, code) in [
        (vec!["--size", "0x10"], 2),
        (vec!["--view", "sideways"], 2),
        (vec!["--samples", "3"], 2),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_nendo"))
            .args(["render", model.to_str().unwrap_or(""), "--png", "x.png"])
            .args(&args)
            .output()
            .expect("nendo runs");
        assert_eq!(o.status.code(), Some(code), "{args:?}");
        assert!(!o.stderr.is_empty());
    }
    let o = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["render", "/nonexistent.json", "--png", "x.png"])
        .output()
        .expect("nendo runs");
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent.json"));

    // A PNG that cannot be written: the message names the path and says why, once.
    let missing = dir.join("no-such-folder").join("out.png");
    let o = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["render", model.to_str().expect("utf-8"), "--png"])
        .arg(&missing)
        .args(["--size", "32x24"])
        .output()
        .expect("nendo runs");
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&missing.display().to_string()),
        "the path is named: {err}"
    );
    assert_eq!(
        err.matches("os error 2").count(),
        1,
        "the cause once: {err}"
    );

    // With the control net drawn, the framing takes it in: the net of a coarse torus, which
    // stands well outside the surface, is drawn whole, clear of the image's border.
    let coarse = dir.join("coarse.nendo.json");
    Model::new(
        Primitive::Torus
            .build(&PrimitiveParams {
                patches: Some((4, 2)),
                ..PrimitiveParams::default()
            })
            .expect("torus"),
    )
    .write(&coarse)
    .expect("write");
    let net_png = dir.join("net.png");
    let o = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["render", coarse.to_str().expect("utf-8"), "--png"])
        .arg(&net_png)
        .args(["--size", "320x180", "--view", "iso", "--control-net"])
        .output()
        .expect("nendo runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let image =
        RgbaImage::read_png(&std::fs::read(&net_png).expect("the PNG exists")).expect("a PNG");
    // The net is drawn blue (Rgba::CONTROL_NET).
    let blue = |x: u32, y: u32| {
        let i = 4 * (y * image.width + x) as usize;
        let [r, g, b] = [image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]];
        b > 120 && b > r.saturating_add(50) && b > g.saturating_add(20)
    };
    let (w, h) = (image.width, image.height);
    let net_pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| blue(x, y))
        .count();
    let on_border = (0..w)
        .flat_map(|x| [(x, 0), (x, h - 1)])
        .chain((0..h).flat_map(|y| [(0, y), (w - 1, y)]))
        .filter(|&(x, y)| blue(x, y))
        .count();
    assert!(net_pixels > 200, "the net is drawn ({net_pixels} pixels)");
    assert_eq!(on_border, 0, "the net is cut off at the border");
    let _ = std::fs::remove_dir_all(&dir);
}
