#![no_main]
//! The tool's own TOML rig files.
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else {
        return;
    };
    load_and_check(&text, "rig.toml", None, sel);
});
