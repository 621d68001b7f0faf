//! Issue 12: encodings. A UTF-8 byte-order mark is stripped in every text
//! format (rig files and point CSV), lone CR line endings read as line breaks,
//! and a NUL or a line break inside a frame name is an error naming the file
//! and the line.

use crate::common::run_cli;
use std::path::Path;

const FORMATS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/formats");

/// (fixture, extra arguments) covering every text format the readers detect;
/// `test-data/...` is a real file of the test-data folder.
const FIXTURES: &[(&str, &[&str])] = &[
    ("ros1_tf_static_echo.yaml", &[]),
    ("ros2_tf_static_echo.yaml", &[]),
    (
        "test-data/ouster-lidar__ouster-sdk/tests/pcaps/OS-0-128-U1_v2.3.0_1024x10.json",
        &[],
    ),
    ("geode_gamma_opencv.yaml", &["--key", "T_IMU_LiDAR"]),
    ("fastlio_avia.yaml", &[]),
    ("test-data/TixiaoShan__LIO-SAM/config/params.yaml", &[]),
    ("ros2_static_tf_commands.txt", &[]),
    ("calib_imu_to_velo.txt", &[]),
    ("ros1_static_tf.launch", &[]),
    ("ros2_static_tf.launch.xml", &[]),
    ("ros2_static_tf.launch.yaml", &[]),
    ("ros2_static_tf.launch.py", &[]),
    ("warthog_expanded.urdf", &[]),
];

/// `audit FILE --frames ARGS` on `text` written as `dir/NAME`, the directory
/// removed from the output so that two copies compare.
fn frames(dir: &Path, name: &str, text: &[u8], args: &[&str]) -> (i32, String) {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    let mut a = vec![p.to_str().unwrap(), "--frames"];
    a.extend_from_slice(args);
    let (code, out, err) = run_cli(&a);
    let d = format!("{}/", dir.display());
    (code, format!("{out}{err}").replace(&d, ""))
}

/// The fixtures there are: (file name, bytes, arguments).
fn fixtures() -> Vec<(String, Vec<u8>, &'static [&'static str])> {
    let mut out = Vec::new();
    for (file, args) in FIXTURES {
        let text = match file.strip_prefix("test-data/") {
            Some(real) => match crate::common::testdata::read(real) {
                Some(t) => t,
                None => continue,
            },
            None => std::fs::read(Path::new(FORMATS).join(file)).unwrap(),
        };
        let name = file.rsplit('/').next().unwrap().to_string();
        out.push((name, text, *args));
    }
    out
}

#[test]
fn a_byte_order_mark_is_stripped_in_every_text_format() {
    for (name, text, args) in fixtures() {
        let name = name.as_str();
        let plain = tempfile::tempdir().unwrap();
        let bom = tempfile::tempdir().unwrap();
        let (c0, want) = frames(plain.path(), name, &text, args);
        assert_eq!(c0, 0, "{name}: {want}");
        let with_bom = [b"\xef\xbb\xbf".as_slice(), &text].concat();
        let (c1, got) = frames(bom.path(), name, &with_bom, args);
        assert_eq!((c1, &got), (0, &want), "{name} with a BOM");
    }
}

#[test]
fn lone_cr_line_endings_read_as_line_breaks() {
    for (name, text, args) in fixtures() {
        let (name, text) = (name.as_str(), String::from_utf8(text).unwrap());
        let plain = tempfile::tempdir().unwrap();
        let cr = tempfile::tempdir().unwrap();
        let (c0, want) = frames(plain.path(), name, text.as_bytes(), args);
        let mac = text.replace("\r\n", "\n").replace('\n', "\r");
        let (c1, got) = frames(cr.path(), name, mac.as_bytes(), args);
        assert_eq!((c1, &got), (c0, &want), "{name} with CR line endings");
    }
}

#[test]
fn a_byte_order_mark_in_csv_points_is_stripped() {
    let src = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/detector/tunnel_small.csv"
    );
    let text = std::fs::read(src).unwrap();
    let d = tempfile::tempdir().unwrap();
    let (p0, p1) = (d.path().join("a.csv"), d.path().join("b.csv"));
    std::fs::write(&p0, &text).unwrap();
    std::fs::write(&p1, [b"\xef\xbb\xbf".as_slice(), &text].concat()).unwrap();
    let (c0, want, e0) = run_cli(&["degeneracy", p0.to_str().unwrap(), "--format", "json"]);
    let (c1, got, e1) = run_cli(&["degeneracy", p1.to_str().unwrap(), "--format", "json"]);
    assert_eq!(c0, 0, "{e0}");
    assert_eq!(c1, 0, "{e1}");
    assert_eq!(got.replace("b.csv", "a.csv"), want);
}

#[test]
fn a_nul_in_a_frame_name_is_an_error_at_its_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("tf.txt");
    std::fs::write(
        &p,
        "# static transforms\nros2 run tf2_ros static_transform_publisher 0 0 0.1 0 0 0 body lidar\0x\n",
    )
    .unwrap();
    let (code, out, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(err.contains("tf.txt:2"), "{err}");
    assert!(err.contains("contains a NUL"), "{err}");
    assert!(err.contains("lidar\\0x"), "{err}");
    assert!(out.is_empty(), "{out}");
}

#[test]
fn a_line_break_in_a_link_name_is_an_error_at_its_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("r.urdf");
    std::fs::write(
        &p,
        "<robot name=\"r\">\n<link name=\"base\"/>\n<link name=\"lidar&#10;::error file=README.md,line=1::FORGED\"/>\n<joint name=\"j\" type=\"fixed\">\n<parent link=\"base\"/><child link=\"lidar&#10;::error file=README.md,line=1::FORGED\"/>\n</joint>\n</robot>\n",
    )
    .unwrap();
    let (code, out, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(err.contains("r.urdf:4"), "{err}");
    assert!(err.contains("contains a line break"), "{err}");
    assert!(err.contains("lidar\\n::error"), "{err}");
    assert!(
        !err.lines().chain(out.lines()).any(|l| l.starts_with("::")),
        "{err}"
    );
}
