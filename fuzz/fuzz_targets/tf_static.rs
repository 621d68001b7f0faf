#![no_main]
//! `rostopic echo /tf_static` / `ros2 topic echo /tf_static` dumps.
use extrinsic_audit::Format;
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else {
        return;
    };
    let (path, fmt) = match sel % 3 {
        0 => ("tf_static.yaml", None),
        1 => ("tf_static.txt", None),
        _ => (
            "tf_static.yaml",
            Some(Format::from_name("tf-static-echo").unwrap()),
        ),
    };
    load_and_check(&text, path, fmt, sel);
});
