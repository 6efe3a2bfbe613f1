//! Every `.wgsl` in `shaders/` parses and validates with naga, every one is used by the
//! renderer, and the `Globals` uniform they declare matches `render::gpu_data::Globals` field by
//! field.
#![cfg(feature = "gui")]

use std::collections::BTreeSet;
use std::mem::{offset_of, size_of};
use std::path::Path;

use nendo::render::SHADERS;
use nendo::render::gpu_data::Globals;

fn shader_files() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("shaders/ exists")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .map(|p| {
            let name = p
                .file_name()
                .expect("a file name")
                .to_string_lossy()
                .into_owned();
            let source = std::fs::read_to_string(&p).expect("readable shader");
            (name, source)
        })
        .collect();
    files.sort();
    files
}

fn validate(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name} does not parse:\n{}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name} does not validate:\n{}", e.emit_to_string(source)));
    module
}

#[test]
fn every_shader_validates_and_is_used() {
    let files = shader_files();
    assert!(!files.is_empty(), "no shaders found");
    for (name, source) in &files {
        let module = validate(name, source);
        for entry in ["vs_main", "fs_main"] {
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{name} lacks {entry}"
            );
        }
    }
    let on_disk: BTreeSet<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    let used: BTreeSet<&str> = SHADERS.iter().map(|(n, _)| *n).collect();
    assert_eq!(on_disk, used, "shaders/ and render::SHADERS disagree");
    // The renderer embeds the same text as the files.
    for (name, source) in SHADERS {
        let file = files
            .iter()
            .find(|(n, _)| n == name)
            .expect("listed shader exists");
        assert_eq!(file.1, source, "{name} differs from the embedded copy");
    }
}

#[test]
fn globals_layout_matches_the_rust_struct() {
    let rust: Vec<(&str, usize)> = vec![
        ("clip_from_world", offset_of!(Globals, clip_from_world)),
        ("eye", offset_of!(Globals, eye)),
        ("heat_max_deg", offset_of!(Globals, heat_max_deg)),
        ("key_light", offset_of!(Globals, key_light)),
        ("heat_on", offset_of!(Globals, heat_on)),
        ("clay", offset_of!(Globals, clay)),
        ("tool_center", offset_of!(Globals, tool_center)),
        ("tool_radius", offset_of!(Globals, tool_radius)),
        ("tool_axis", offset_of!(Globals, tool_axis)),
        ("tool_on", offset_of!(Globals, tool_on)),
        ("viewport", offset_of!(Globals, viewport)),
        ("line_depth_bias", offset_of!(Globals, line_depth_bias)),
        ("pad", offset_of!(Globals, pad)),
    ];
    let mut declaring = 0;
    for (name, source) in shader_files() {
        let module = validate(&name, &source);
        let Some(ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("Globals"))
        else {
            continue;
        };
        declaring += 1;
        let naga::TypeInner::Struct { members, span } = &ty.1.inner else {
            panic!("{name}: Globals is not a struct");
        };
        assert_eq!(
            *span as usize,
            size_of::<Globals>(),
            "{name}: size of Globals"
        );
        let wgsl: Vec<(&str, usize)> = members
            .iter()
            .map(|m| (m.name.as_deref().unwrap_or("?"), m.offset as usize))
            .collect();
        assert_eq!(wgsl, rust, "{name}: Globals members and offsets");
    }
    assert_eq!(declaring, 3, "clay, lines and spheres declare Globals");
}
