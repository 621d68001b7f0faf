//! The integration suite, one binary so that it builds once: one module per
//! area (`core_*` the maths, `formats_*` and `graph_*` the readers and the frame
//! graph, `cli_*` the binary, `hostile_*` hostile input, `detector_*`,
//! `points_*` and `scene_*` the degeneracy wing), helpers in `common`.

mod architecture;
mod calibrations;
mod check_gate;
mod check_hooks;
mod cli_audit;
mod cli_detector;
mod cli_pipes;
mod cli_survey_check;
mod common;
mod core_alloc;
mod core_edges;
mod core_fixtures;
mod core_props;
mod detector_core;
mod detector_scans;
mod detector_threshold;
mod diff;
mod formats_bad_inputs;
mod formats_bags;
mod formats_detection;
mod formats_extrinsics;
mod formats_launch_conditions;
mod formats_no_panic;
mod formats_rigs;
mod formats_xacro;
mod frames_pictures;
mod graph_basic;
mod graph_urdf_corpus;
mod hostile_atomic;
mod hostile_encodings;
mod hostile_input;
mod hostile_limits;
mod hostile_messages;
mod hostile_numbers;
mod hostile_options;
mod hostile_output;
mod hostile_points;
mod json_schemas;
mod points_las;
mod points_progress;
mod points_readers;
mod points_regressions;
mod points_streaming;
mod readme;
mod rig_toml;
mod scene_simulate;
mod scene_tunnel;
mod snapshots;
mod survey_any;
mod test_data;
mod uncertainty;
mod urdf_conformance;
mod widths;
