//! nendo's integration tests, one binary: each module is one area (`cargo test --test it <module>::`).
//! Shared helpers (the binary, temporary directories, near-equality) live in [`support`].

mod analysis_display;
mod bounded_inputs;
mod brush_ops;
mod brushes;
mod closest_cli;
mod closest_fast_paths;
mod curve_edit;
mod curve_edit_cli;
mod curve_properties;
mod curve_queries;
mod curve_refine;
mod curve_refine_svg;
mod curve_warp;
mod data_loss;
mod devices_cli;
mod documents;
mod export_cad;
mod export_roundtrip;
mod export_size;
mod figure_fit;
mod figure_morph;
mod figure_shape;
mod figure_warp;
mod hand_clutch;
mod hand_contact;
mod hand_filter;
mod hand_kinematics;
mod hand_latency;
mod hand_poses;
mod hand_side;
mod hand_skeleton;
mod hand_skeleton_filter;
mod hand_traces;
mod limits_cli;
mod memory_limits;
mod model_cli;
mod model_file;
mod record_survives;
mod record_symmetry;
mod refine;
mod regulation_methods;
mod regulation_strokes;
mod render_cli;
mod render_headless;
mod replay_cli;
mod replay_traces;
mod safe_writer;
mod sculpt_limits;
mod shader_validation;
mod shading;
mod smoothing;
mod support;
mod surface_deform;
mod surface_grid;
mod surface_operations;
mod svg_import;
mod symmetry_group;
mod window_symmetry;
// It measures strokes through `nendo_bench::live`, which times the renderer (`gui`).
#[cfg(feature = "gui")]
mod undo_history;
mod view_modes;
#[cfg(feature = "gui")]
mod view_render;
mod vmc_cli;
