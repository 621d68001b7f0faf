#![no_main]
//! YAML dialects: sniffed from content, and each dialect forced; also the text
//! formats (KITTI raw and object, M2DGR) that share the `.txt` / `.yaml` detection path.
use extrinsic_audit::Format;
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

/// The dialects forced by selectors 6 and up (looked up by name: `Format`
/// values come from the registry at run time).
const FORCED: &[&str] = &[
    "fast-lio",
    "lio-sam",
    "coco-lic",
    "slict",
    "tf-tree-yaml",
    "matrix-yaml",
    "quaternion-yaml",
    "kitti-calib",
    "m2dgr-txt",
    "ig-lio",
    "dlio",
    "vins-mono",
    "kitti-object",
];

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else {
        return;
    };
    let k = (sel & 0x1f) as usize;
    let (path, fmt) = match k {
        0..=3 => ("calib.yaml", None),
        4 => ("calib.yml", None),
        5 => ("calib.txt", None),
        _ => {
            let name = FORCED[(k - 6) % FORCED.len()];
            (
                "calib.yaml",
                Some(Format::from_name(name).expect("a registered format")),
            )
        }
    };
    load_and_check(&text, path, fmt, sel);
});
