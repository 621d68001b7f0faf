#![no_main]
//! xacro: the built-in expander on whole documents, and (odd selectors) the
//! `${...}` evaluator on one expression placed in a joint origin. Includes and
//! `$(find)` resolve against a path that does not exist.
use extrinsic_audit::Format;
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else {
        return;
    };
    let doc = if sel & 1 == 1 {
        format!(
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\
             <xacro:property name=\"w\" value=\"0.5\"/><link name=\"a\"/><link name=\"b\"/>\
             <joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/>\
             <origin xyz=\"0 0 ${{{}}}\"/></joint></robot>",
            text.replace(['"', '<', '&', '}'], " ")
        )
    } else {
        text
    };
    load_and_check(
        &doc,
        "/nonexistent/robot.urdf.xacro",
        Some(Format::from_name("xacro").unwrap()),
        sel & !1,
    );
});
