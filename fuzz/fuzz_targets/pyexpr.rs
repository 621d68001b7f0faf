#![no_main]
//! pyexpr, the Python-expression reader: the text as a whole launch.py file
//! (even selectors), or (odd) as one `$(eval ...)` expression in a ROS 1
//! launch arg that a static_transform_publisher's args use.
use extrinsic_audit::Format;
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else { return };
    if sel & 1 == 0 {
        load_and_check(&text, "robot.launch.py", None, sel);
        return;
    }
    let doc = format!(
        "<launch><arg name=\"v\" value=\"$(eval {})\"/>\
         <node pkg=\"tf\" type=\"static_transform_publisher\" name=\"s\" \
         args=\"$(arg v) 0 0 0 0 0 base_link lidar 100\"/></launch>",
        text.replace(['"', '<', '&', ')'], " ")
    );
    load_and_check(&doc, "robot.launch", Some(Format::from_name("launch-xml").unwrap()), sel & !1);
});
