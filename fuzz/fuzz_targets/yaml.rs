#![no_main]
//! YAML dialects: sniffed from content, and each dialect forced; also the text
//! formats (KITTI, M2DGR) that share the `.txt` / `.yaml` detection path.
use extrinsic_audit::formats::Format;
use fuzz_common::{load_and_check, split};
use libfuzzer_sys::fuzz_target;

const FORCED: &[Format] = &[
    Format::from_name("fast-lio").unwrap(),
    Format::from_name("lio-sam").unwrap(),
    Format::from_name("coco-lic").unwrap(),
    Format::from_name("slict").unwrap(),
    Format::from_name("tf-tree-yaml").unwrap(),
    Format::from_name("matrix-yaml").unwrap(),
    Format::from_name("quaternion-yaml").unwrap(),
    Format::from_name("kitti-calib").unwrap(),
    Format::from_name("m2dgr-txt").unwrap(),
];

fuzz_target!(|data: &[u8]| {
    let Some((sel, text)) = split(data) else { return };
    let k = (sel & 0x1f) as usize;
    let (path, fmt) = match k {
        0..=3 => ("calib.yaml", None),
        4 => ("calib.yml", None),
        5 => ("calib.txt", None),
        _ => ("calib.yaml", Some(FORCED[(k - 6) % FORCED.len()])),
    };
    load_and_check(&text, path, fmt, sel);
});
