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
    let _ = std::fs::remove_dir_all(&dir);
}
