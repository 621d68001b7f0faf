#![no_main]
//! Ouster metadata JSON (legacy flat and nested), Ouster extrinsic_parameters.json,
//! Argoverse 2 egovehicle_SE3_sensor rows, nuScenes calibrated_sensor.json and
//! matrix JSON; selector 7: Argoverse 2 `egovehicle_SE3_sensor.feather` (the
//! raw bytes, Arrow IPC, through `load_bytes`).
use extrinsic_audit::Format;
use fuzz_common::{load_and_check, load_bytes_and_check, split};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else {
        return;
    };
    if sel % 8 == 7 {
        // Binary: the bytes as they are, not the lossy text.
        load_bytes_and_check(&data[1..], "egovehicle_SE3_sensor.feather", None, sel);
        return;
    }
    let (path, fmt) = match sel % 8 {
        0 | 1 => ("metadata.json", None),
        2 => ("metadata", None),
        // JSON is YAML: the matrix-YAML reader must take JSON matrices too.
        3 => (
            "calib.json",
            Some(Format::from_name("matrix-yaml").unwrap()),
        ),
        4 => (
            "calibrated_sensor.json",
            Some(Format::from_name("nuscenes-json").unwrap()),
        ),
        5 => (
            "extrinsic_parameters.json",
            Some(Format::from_name("ouster-extrinsics").unwrap()),
        ),
        _ => (
            "egovehicle_SE3_sensor.json",
            Some(Format::from_name("av2-json").unwrap()),
        ),
    };
    load_and_check(&text, path, fmt, sel);
});
