//! Every shader program the renderer builds validates with naga as compiled (its `.wgsl` file,
//! preceded by `modeller/shaders/globals.wgsl` where it reads the per-frame uniform), every file
//! in `modeller/shaders/` is used, the `Globals` block is declared once (in `globals.wgsl`), and
//! that block matches `render::gpu_data::Globals` member by member.
#![cfg(feature = "gui")]

use std::collections::BTreeSet;
use std::mem::{offset_of, size_of};
use std::path::Path;

use nendo::render::gpu_data::Globals;
use nendo::render::{GLOBALS_WGSL, SHADERS};

/// The shared block, not a program of its own.
const GLOBALS_FILE: &str = "globals.wgsl";

fn shader_files() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("modeller/shaders");
    let mut files: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("modeller/shaders/ exists")
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
    // Each program as the renderer compiles it.
    for (name, source) in SHADERS {
        let module = validate(name, source);
        for entry in ["vs_main", "fs_main"] {
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{name} lacks {entry}"
            );
        }
    }
    let on_disk: BTreeSet<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    let mut used: BTreeSet<&str> = SHADERS.iter().map(|(n, _)| *n).collect();
    used.insert(GLOBALS_FILE);
    assert_eq!(
        on_disk, used,
        "modeller/shaders/ and render::SHADERS disagree"
    );
    let file = |name: &str| {
        files
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, s)| s.as_str())
            .expect("listed shader exists")
    };
    assert_eq!(
        file(GLOBALS_FILE),
        GLOBALS_WGSL,
        "the embedded globals block"
    );
    // The renderer embeds the files' text, the globals block first where it is used.
    for (name, source) in SHADERS {
        let expected = if source.starts_with(GLOBALS_WGSL) {
            format!("{GLOBALS_WGSL}{}", file(name))
        } else {
            file(name).to_string()
        };
        assert_eq!(expected, source, "{name} differs from the embedded copy");
    }
}

/// `Globals` in a naga module: `(member, offset)` and the struct's size.
fn globals_layout(name: &str, module: &naga::Module) -> Option<(Vec<(String, usize)>, usize)> {
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("Globals"))?;
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{name}: Globals is not a struct");
    };
    let members = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
        .collect();
    Some((members, *span as usize))
}

#[test]
fn globals_layout_matches_the_rust_struct() {
    let rust: Vec<(String, usize)> = [
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
        ("eye_w", offset_of!(Globals, eye_w)),
        ("view_right", offset_of!(Globals, view_right)),
        ("matcap", offset_of!(Globals, matcap)),
        ("view_up", offset_of!(Globals, view_up)),
        ("pad", offset_of!(Globals, pad)),
    ]
    .into_iter()
    .map(|(n, o)| (n.to_string(), o))
    .collect();
    // The one WGSL block.
    let module = validate(GLOBALS_FILE, GLOBALS_WGSL);
    let (members, size) =
        globals_layout(GLOBALS_FILE, &module).expect("globals.wgsl declares Globals");
    assert_eq!(size, size_of::<Globals>(), "size of Globals");
    assert_eq!(members, rust, "Globals members and offsets");
    // Declared nowhere else on disk: the block is defined once.
    for (name, source) in shader_files() {
        if name != GLOBALS_FILE {
            assert!(
                !source.contains("struct Globals"),
                "{name} declares its own Globals"
            );
        }
    }
    // And every compiled program that reads it has that very layout.
    let mut reading = 0;
    for (name, source) in SHADERS {
        let module = validate(name, source);
        if let Some(layout) = globals_layout(name, &module) {
            reading += 1;
            assert_eq!(
                layout,
                (rust.clone(), size_of::<Globals>()),
                "{name}: Globals"
            );
        }
    }
    assert_eq!(reading, 4, "analysis, clay, lines and spheres read Globals");
}
