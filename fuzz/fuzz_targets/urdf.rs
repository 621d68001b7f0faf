#![no_main]
//! URDF (and xacro text without macros): detection by `.urdf` / `.xml` /
//! no extension, and the format forced.
use extrinsic_audit::Format;
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else {
        return;
    };
    let (path, fmt) = match sel % 4 {
        0 => ("robot.urdf", None),
        1 => ("robot.xml", None),
        2 => ("robot", None),
        _ => ("robot.txt", Some(Format::from_name("urdf").unwrap())),
    };
    load_and_check(&text, path, fmt, sel);
});
