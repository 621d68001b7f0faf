//! Table-driven: every format of the published rigs (the real files, read in
//! place from the test-data folder, and the project's own fixtures in
//! tests/fixtures/formats) yields the `T_body_lidar` recorded for its rig
//! (tests/fixtures/formats/expected_rigs.json, copied from rigs.json).

use extrinsic_audit::internals::formats::load_file;
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::LoadOptions;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/formats";

/// The path of case `file`: `test-data/...` in the test-data folder (`None`
/// where absent: the case is skipped), else in DIR.
fn fixture(file: &str) -> Option<PathBuf> {
    match file.strip_prefix("test-data/") {
        Some(real) => crate::common::testdata::file(real),
        None => Some(Path::new(DIR).join(file)),
    }
}

struct Case {
    file: &'static str,
    key: Option<&'static str>,
    from: &'static str,
    to: &'static str,
    rig: &'static str,
    /// The id of the format that reads it (`--input-format`).
    format: &'static str,
    /// Max abs difference per matrix entry. rigs.json prints 9 decimals; files
    /// whose rotation is projected to SO(3) (rounded published values) differ more.
    tol: f64,
}

const fn c(
    file: &'static str,
    key: Option<&'static str>,
    from: &'static str,
    to: &'static str,
    rig: &'static str,
    format: &'static str,
    tol: f64,
) -> Case {
    Case {
        file,
        key,
        from,
        to,
        rig,
        format,
        tol,
    }
}

const CASES: &[Case] = &[
    c(
        "fastlio_avia.yaml",
        None,
        "imu",
        "lidar",
        "fastlio-avia",
        "fast-lio",
        1e-9,
    ),
    c(
        "fastlivo2_hilti22.yaml",
        None,
        "imu",
        "lidar",
        "hilti2022-hesai",
        // Its camera Rcl/Pcl make it a FAST-LIVO2 file (issue 28).
        "fast-livo",
        1e-9,
    ),
    c(
        "test-data/TixiaoShan__LIO-SAM/config/params.yaml",
        None,
        "imu",
        "lidar",
        "liosam-default",
        "lio-sam",
        1e-9,
    ),
    c(
        "test-data/nkymzsy__LIO-SAM-MID360/config/params9axisIMU.yaml",
        None,
        "imu",
        "lidar",
        "liosam-mid360-9axis",
        "lio-sam",
        1e-9,
    ),
    c(
        "test-data/ouster-lidar__ouster-sdk/tests/pcaps/OS-0-128-U1_v2.3.0_1024x10.json",
        None,
        "os_imu",
        "os_lidar",
        "ouster-os0-128-fw2.3",
        "ouster-json",
        1e-9,
    ),
    c(
        "test-data/ouster-lidar__ouster-sdk/tests/metadata/3_0_1_os-122246000293-128.json",
        None,
        "os_imu",
        "os_lidar",
        "ouster-os1-128-fw3.0",
        "ouster-json",
        1e-9,
    ),
    c(
        "test-data/leggedrobotics__grand_tour_box/box_calibration/box_calibration/calibration/tf/calibration_latest.yaml",
        None,
        "box_base",
        "hesai_lidar",
        "grandtour-hesai-cpt7",
        "tf-tree-yaml",
        1e-9,
    ),
    c(
        "test-data/leggedrobotics__grand_tour_box/box_calibration/box_calibration/calibration/tf/calibration_latest.yaml",
        None,
        "livox_imu",
        "livox_lidar",
        "grandtour-mid360-internal",
        "tf-tree-yaml",
        1e-9,
    ),
    // rigs.json records the Extrinsic_Tlb numbers as written (it took them for
    // the LiDAR in the IMU); LIO-Livox's code reads them as the IMU in the
    // LiDAR (formats::launch), so the numbers are the lidar -> imu pose.
    c(
        "test-data/Livox-SDK__LIO-Livox/launch/mid360.launch",
        None,
        "lidar",
        "imu",
        "liolivox-mid360",
        "lio-livox-launch",
        2e-5,
    ),
    c(
        "geode_gamma_opencv.yaml",
        Some("T_IMU_LiDAR"),
        "IMU",
        "LiDAR",
        "geode-gamma-avia",
        "matrix-yaml",
        2e-6,
    ),
    c(
        "urbannav_20190428.yaml",
        None,
        "body",
        "LiDAR",
        "urbannav-hk-20190428-hdl32e",
        "matrix-yaml",
        1e-9,
    ),
    // rigs.json reads CENTER_LiDAR_T_IMU against its name (the file's comment says
    // "from Center Lidar to IMU"): the tool follows the name rule (pose of IMU in
    // CENTER_LiDAR), so the rig's T_body_lidar is the CENTER_LiDAR -> IMU transform.
    c(
        "urbannav_medium_fixed.yaml",
        None,
        "CENTER_LiDAR",
        "IMU",
        "urbannav-hk-medium-hdl32e",
        "matrix-yaml",
        1e-9,
    ),
    c(
        "test-data/SJTU-ViSYS__M2DGR/calibration_results.txt",
        None,
        "handsfree_imu",
        "velodyne",
        "m2dgr-vlp32c-handsfree",
        "m2dgr-txt",
        1e-9,
    ),
    c(
        "test-data/SJTU-ViSYS__M2DGR/calibration_results.txt",
        None,
        "xsens_imu",
        "velodyne",
        "m2dgr-vlp32c-xsens",
        "m2dgr-txt",
        1e-9,
    ),
    c(
        "fusionportable_ouster00.yaml",
        None,
        "body_imu",
        "sensor",
        "fusionportable-os1-128-stim300",
        "quaternion-yaml",
        1e-8,
    ),
    c(
        "slict_mcdviral_hhs.yaml",
        None,
        "body",
        "lidar",
        "mcdviral-hhs-ouster",
        "slict",
        1e-8,
    ),
    c(
        "cocolic_viral_lidar.yaml",
        None,
        "imu",
        "lidar1",
        "ntuviral-vert-os1-16",
        "coco-lic",
        1e-9,
    ),
    c(
        "cocolic_viral_lidar.yaml",
        None,
        "imu",
        "lidar0",
        "ntuviral-horz-os1-16",
        "coco-lic",
        1e-9,
    ),
    c(
        "calib_imu_to_velo.txt",
        None,
        "imu",
        "velo",
        "kitti-velo64-oxts",
        "kitti-calib",
        1e-6,
    ),
    c(
        "warthog_expanded.urdf",
        None,
        "mti10",
        "rslidar32",
        "norlab-warthog-rs32-mti10",
        "urdf",
        1e-9,
    ),
    c(
        "warthog_expanded.urdf",
        None,
        "mti10",
        "rslidar16_left",
        "norlab-warthog-rs16left-mti10",
        "urdf",
        1e-8,
    ),
    c(
        "test-data/ANYbotics__anymal_d_simple_description/urdf/anymal.urdf",
        None,
        "imu_link",
        "lidar",
        "anymal-d-lidar-imu",
        "urdf",
        1e-8,
    ),
    c(
        "ros1_tf_static_echo.yaml",
        None,
        "imu",
        "os_sensor",
        "ntnu-os0-128-vn100",
        "tf-static-echo",
        1e-6,
    ),
    c(
        "ros2_tf_static_echo.yaml",
        None,
        "box_base",
        "hesai_lidar",
        "grandtour-hesai-cpt7",
        "tf-static-echo",
        1e-8,
    ),
    c(
        "ros2_tf_static_echo.yaml",
        None,
        "body",
        "livox_frame",
        "fastlio-mid360",
        "tf-static-echo",
        1e-9,
    ),
    c(
        "ros2_static_tf_commands.txt",
        None,
        "box_base",
        "hesai_lidar",
        "grandtour-hesai-cpt7",
        "static-tf-commands",
        1e-8,
    ),
    c(
        "ros2_static_tf_commands.txt",
        None,
        "imu",
        "os_sensor",
        "ntnu-os0-128-vn100",
        "static-tf-commands",
        1e-6,
    ),
    c(
        "ros2_static_tf_commands.txt",
        None,
        "body",
        "avia_frame",
        "fastlio-avia",
        "static-tf-commands",
        1e-9,
    ),
    c(
        "ros1_static_tf.launch",
        None,
        "box_base",
        "hesai_lidar",
        "grandtour-hesai-cpt7",
        "launch-xml",
        1e-8,
    ),
    c(
        "ros1_static_tf.launch",
        None,
        "imu",
        "os_sensor",
        "ntnu-os0-128-vn100",
        "launch-xml",
        1e-6,
    ),
    c(
        "ros2_static_tf.launch.xml",
        None,
        "box_base",
        "hesai_lidar",
        "grandtour-hesai-cpt7",
        "launch-xml",
        1e-8,
    ),
    c(
        "ros2_static_tf.launch.yaml",
        None,
        "imu",
        "os_sensor",
        "ntnu-os0-128-vn100",
        "launch-yaml",
        1e-6,
    ),
    c(
        "ros2_static_tf.launch.py",
        None,
        "box_base",
        "hesai_lidar",
        "grandtour-hesai-cpt7",
        "launch-py",
        1e-8,
    ),
    c(
        "ros2_static_tf.launch.py",
        None,
        "imu",
        "os_sensor",
        "ntnu-os0-128-vn100",
        "launch-py",
        1e-6,
    ),
    c(
        "kr_quadrotor_publish_tf.launch",
        None,
        "quadrotor/base_link",
        "quadrotor/lidar",
        "kr-quadrotor-lidar-base",
        "launch-xml",
        1e-9,
    ),
];

fn expected() -> serde_json::Value {
    let text =
        std::fs::read_to_string(format!("{DIR}/expected_rigs.json")).expect("expected_rigs.json");
    serde_json::from_str(&text).expect("json")
}

#[test]
fn every_fixture_yields_its_rig() {
    let exp = expected();
    let mut failures = Vec::new();
    for case in CASES {
        let Some(path) = fixture(case.file) else {
            continue;
        };
        let mut opts = LoadOptions::default();
        opts.key = case.key.map(String::from);
        let loaded = match load_file(&path, &opts) {
            Ok(l) => l,
            Err(e) => {
                failures.push(format!("{}: load error {e}", case.file));
                continue;
            }
        };
        assert!(
            loaded
                .edges
                .iter()
                .all(|e| e.provenance.format == case.format),
            "{}: expected format {}",
            case.file,
            case.format
        );
        assert!(
            loaded
                .edges
                .iter()
                .all(|e| e.provenance.location.line.is_some()),
            "{}: every edge knows its line",
            case.file
        );
        let mut g = FrameGraph::new();
        g.add(loaded).expect("graph");
        let chain = g.transform(case.from, case.to).expect("transform");
        let m = chain.transform.matrix4();
        let want = &exp["rigs"][case.rig]["T_body_lidar"];
        let mut worst = 0.0f64;
        for i in 0..4 {
            for j in 0..4 {
                let w = want[i][j].as_f64().expect("number");
                worst = worst.max((m[(i, j)] - w).abs());
            }
        }
        if worst > case.tol {
            failures.push(format!(
                "{} {} -> {} ({}): max entry error {worst:e} > {:e}",
                case.file, case.from, case.to, case.rig, case.tol
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The same transforms in the four ROS syntaxes of authored/ (plus ROS 2 launch
/// XML/YAML/Python) read identically.
#[test]
fn ros_syntaxes_agree() {
    let files = [
        "ros1_static_tf.launch",
        "ros2_static_tf_commands.txt",
        "ros2_tf_static_echo.yaml",
        "ros2_static_tf.launch.xml",
        "ros2_static_tf.launch.yaml",
        "ros2_static_tf.launch.py",
    ];
    let mut reference = None;
    for f in files {
        let l = load_file(&Path::new(DIR).join(f), &LoadOptions::default()).expect(f);
        let mut g = FrameGraph::new();
        g.add(l).expect(f);
        let t = g
            .transform("box_base", "hesai_lidar")
            .expect(f)
            .transform
            .matrix4();
        match &reference {
            None => reference = Some(t),
            Some(r) => {
                let diff = (t - r).abs().max();
                assert!(diff < 1e-12, "{f}: differs from {} by {diff:e}", files[0]);
            }
        }
    }
    let mut refs = Vec::new();
    for f in [
        "ros1_static_tf.launch",
        "ros1_tf_static_echo.yaml",
        "ros2_static_tf_commands.txt",
    ] {
        let l = load_file(&Path::new(DIR).join(f), &LoadOptions::default()).expect(f);
        let mut g = FrameGraph::new();
        g.add(l).expect(f);
        refs.push(
            g.transform("imu", "os_sensor")
                .expect(f)
                .transform
                .matrix4(),
        );
    }
    for r in &refs[1..] {
        assert!((r - refs[0]).abs().max() < 1e-12);
    }
}
