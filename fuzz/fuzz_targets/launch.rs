#![no_main]
//! ROS 1 / ROS 2 launch XML, LIO-Livox launch, launch YAML, launch.py and saved
//! static_transform_publisher command lines.
use extrinsic_audit::Format;
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else {
        return;
    };
    let (path, fmt) = match sel % 8 {
        0 => ("robot.launch", None),
        1 => ("robot.launch.xml", None),
        2 => ("robot.launch.yaml", None),
        3 => ("robot.launch.py", None),
        4 => ("commands.txt", None),
        5 => (
            "robot.launch",
            Some(Format::from_name("lio-livox-launch").unwrap()),
        ),
        6 => (
            "commands.sh",
            Some(Format::from_name("static-tf-commands").unwrap()),
        ),
        _ => ("robot.xml", Some(Format::from_name("launch-xml").unwrap())),
    };
    load_and_check(&text, path, fmt, sel);
});
