//! Issue 14's formats (tests/fixtures/extrinsics): every case of
//! `expected.json` (computed by `gen_expected.py` with numpy and
//! pytransform3d) matched to 1e-9, and the redundancy, ambiguity and naming
//! rules.

use crate::common::audit;
use crate::common::testdata;
use extrinsic_audit::internals::formats::load_file;
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::Code;
use extrinsic_audit::LoadOptions;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/extrinsics";

/// The real third-party files among the cases, by the name expected.json
/// gives them, and their path in the test-data folder (docs/test-data.md).
const REAL: &[(&str, &str)] = &[
    (
        "ouster_sdk_extrinsic_parameters.json",
        "ouster-lidar__ouster-sdk/tests/pcap_with_extrinsics/extrinsic_parameters.json",
    ),
    (
        "dlio_default.yaml",
        "vectr-ucla__direct_lidar_inertial_odometry/cfg/dlio.yaml",
    ),
    (
        "dlio_ros2_params.yaml",
        "vectr-ucla__direct_lidar_inertial_odometry@c8acc37/cfg/dlio.yaml",
    ),
    (
        "dlio_livox_support.yaml",
        "vectr-ucla__direct_lidar_inertial_odometry@5b123df/cfg/dlio.yaml",
    ),
    (
        "guardian_start_projection.bash",
        "inesc-tec-robotics__guardian_config/projection/guardian_start_projection.bash",
    ),
    (
        "guardian_stop_projection.bash",
        "inesc-tec-robotics__guardian_config/projection/guardian_stop_projection.bash",
    ),
    (
        "lvisam_params_camera.yaml",
        "TixiaoShan__LVI-SAM/config/params_camera.yaml",
    ),
    (
        "kalibr_voxblox_euroc_camchain.yaml",
        "ethz-asl__voxblox/voxblox_ros/cfg/calibrations/euroc_camchain.yaml",
    ),
];

/// The path of case `file`: in DIR, or a real file in the test-data folder
/// (`None` where it is absent: the case is skipped).
fn fixture(file: &str) -> Option<PathBuf> {
    match REAL.iter().find(|(name, _)| *name == file) {
        Some((_, real)) => testdata::file(real),
        None => Some(Path::new(DIR).join(file)),
    }
}

/// The frame graph of case `file` (`None`: a real file, absent).
fn real_graph(file: &str, key: Option<&str>) -> Option<FrameGraph> {
    let mut opts = LoadOptions::default();
    opts.key = key.map(str::to_string);
    let path = fixture(file)?;
    let loaded = load_file(&path, &opts).unwrap_or_else(|e| panic!("{file}: {e}"));
    let mut g = FrameGraph::new();
    g.add(loaded).unwrap_or_else(|e| panic!("{file}: {e}"));
    Some(g)
}

/// The frame graph of the project's own fixture `file`.
fn graph(file: &str, key: Option<&str>) -> FrameGraph {
    assert!(
        REAL.iter().all(|(name, _)| *name != file),
        "{file}: a real file, read with real_graph"
    );
    real_graph(file, key).expect("own fixture")
}

#[test]
fn expected_transforms_match_numpy() {
    let text = std::fs::read_to_string(Path::new(DIR).join("expected.json")).expect("expected");
    let cases: serde_json::Value = serde_json::from_str(&text).expect("json");
    let cases = cases.as_array().expect("list");
    assert!(!cases.is_empty());
    for c in cases {
        let file = c["file"].as_str().expect("file");
        let (from, to) = (
            c["from"].as_str().expect("from"),
            c["to"].as_str().expect("to"),
        );
        let Some(g) = real_graph(file, c["key"].as_str()) else {
            continue;
        };
        let chain = g
            .transform(from, to)
            .unwrap_or_else(|e| panic!("{file} {from} -> {to}: {e}"));
        let m = chain.transform.matrix4();
        for i in 0..4 {
            for j in 0..4 {
                let want = c["matrix"][i][j].as_f64().expect("number");
                assert!(
                    (m[(i, j)] - want).abs() <= 1e-9,
                    "{file} {from} -> {to} ({:?}) entry ({i},{j}): {} vs numpy {want}",
                    c["key"],
                    m[(i, j)]
                );
            }
        }
    }
}

#[test]
fn kalibr_stereo_is_a_tree_with_a_checked_redundant_edge() {
    let g = graph("kalibr_padrl_camchain-imucam.yaml", None);
    assert_eq!(g.roots(), vec!["imu".to_string()]);
    for cam in ["cam0", "cam1"] {
        assert_eq!(g.parent_edge(cam).expect("edge").parent, "imu");
    }
    let r = g.redundant();
    assert_eq!(r.len(), 1);
    assert_eq!(
        (r[0].edge.parent.as_str(), r[0].edge.child.as_str()),
        ("cam1", "cam0")
    );
    assert!(r[0].agrees(), "{:?}", r[0]);
    assert_eq!(r[0].path, "cam1 <- imu -> cam0");
    assert_eq!(g.notes().len(), 1);
    assert!(g
        .warnings()
        .iter()
        .all(|w| w.code != Code::RedundantEdgeDisagrees));
    let chain = g.transform("cam0", "cam1").expect("chain");
    assert_eq!(chain.notes.len(), 1);
    assert!(
        chain.notes[0].contains("path used: cam0 <- imu -> cam1"),
        "{}",
        chain.notes[0]
    );
    assert!(
        chain.notes[0].contains("--key cam1.T_cn_cnm1"),
        "{}",
        chain.notes[0]
    );
}

#[test]
fn kalibr_key_names_the_camera_and_the_imu() {
    let g = graph("kalibr_padrl_camchain-imucam.yaml", Some("cam1.T_cn_cnm1"));
    assert_eq!(g.edges()[0].parent, "cam1");
    assert_eq!(g.edges()[0].child, "cam0");
    let g = graph("kalibr_padrl_camchain-imucam.yaml", Some("cam1.T_cam_imu"));
    assert_eq!(
        (g.edges()[0].parent.as_str(), g.edges()[0].child.as_str()),
        ("cam1", "imu")
    );
}

#[test]
fn from_and_to_take_a_leading_slash() {
    let g = graph("kalibr_padrl_camchain-imucam.yaml", None);
    let a = g.transform("/cam0", "/imu").expect("slash");
    let b = g.transform("cam0", "imu").expect("plain");
    assert_eq!(a.transform, b.transform);
    assert_eq!((a.from.as_str(), a.to.as_str()), ("cam0", "imu"));
}

#[test]
fn cli_says_which_path_it_used() {
    let f = format!("{DIR}/kalibr_padrl_camchain-imucam.yaml");
    let out = audit()
        .args([f.as_str(), "--from", "/cam0", "--to", "cam1"])
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("note: path used: cam0 <- imu -> cam1"),
        "{err}"
    );
    let out = audit()
        .args([f.as_str(), "--frames"])
        .output()
        .expect("run");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("redundant cam1 -> cam0"), "{text}");
}

#[test]
fn a_duplicated_key_blocks_only_its_own_edge() {
    let g = graph("geode_style_ambiguous.yaml", None);
    let amb: Vec<_> = g
        .warnings()
        .iter()
        .filter(|w| w.code == Code::AmbiguousKey)
        .collect();
    assert_eq!(amb.len(), 1, "{:?}", g.warnings());
    assert!(
        amb[0]
            .message
            .contains("`T_LiDAR_CamL` given 2 times with different values (lines 11 and 21)"),
        "{}",
        amb[0].message
    );
    assert_eq!(amb[0].location.line, Some(21));
    assert!(!g.contains("CamL"));
    assert!(g.transform("IMU", "LiDAR").is_ok());
}

#[test]
fn a_disagreeing_redundant_edge_is_a_warning_with_both_values() {
    let g = graph("geode_style_ambiguous.yaml", None);
    let r = g.redundant();
    assert_eq!(r.len(), 1);
    assert!(!r[0].agrees());
    assert!(
        (r[0].translation_gap - 0.005).abs() < 1e-12,
        "{}",
        r[0].translation_gap
    );
    assert!(r[0].rotation_gap < 1e-12);
    let w: Vec<_> = g
        .warnings()
        .iter()
        .filter(|w| w.code == Code::RedundantEdgeDisagrees)
        .collect();
    assert_eq!(w.len(), 1);
    assert!(
        w[0].message
            .contains("the file gives translation [0.055000000, -0.120000000, 0.120000000]"),
        "{}",
        w[0].message
    );
    assert!(
        w[0].message
            .contains("the tree [0.050000000, -0.120000000, 0.120000000]"),
        "{}",
        w[0].message
    );
    assert!(g.notes().is_empty());
}

#[test]
fn no_transform_lists_the_keys_seen_and_the_layouts_known() {
    let dir = tempfile::tempdir().expect("tmp");
    let p = dir.path().join("unknown.yaml");
    std::fs::write(&p, "camera_fps: 30\nlidar_topic: /points\n").expect("write");
    let e = load_file(&p, &LoadOptions::default()).expect_err("refused");
    assert!(
        e.message.contains("found keys camera_fps, lidar_topic"),
        "{}",
        e.message
    );
    assert!(
        e.message.contains("Kalibr `camN: {T_cam_imu, T_cn_cnm1}`"),
        "{}",
        e.message
    );
}

#[test]
fn each_fixture_is_detected_as_its_format() {
    use extrinsic_audit::internals::formats::detect_format;
    for (file, id) in [
        ("kalibr_padrl_camchain-imucam.yaml", "matrix-yaml"),
        ("kalibr_openvins_euroc_imucam_chain.yaml", "matrix-yaml"),
        ("kalibr_wiki_example_chain.yaml", "matrix-yaml"),
        ("kalibr_voxblox_euroc_camchain.yaml", "matrix-yaml"),
        ("geode_style_ambiguous.yaml", "matrix-yaml"),
        ("iglio_ncd.yaml", "ig-lio"),
        ("iglio_nclt.yaml", "ig-lio"),
        ("dlio_default.yaml", "dlio"),
        ("dlio_ros2_params.yaml", "dlio"),
        ("vins_mono_realsense_color.yaml", "vins-mono"),
        ("vins_mono_euroc.yaml", "vins-mono"),
        ("lvisam_params_camera.yaml", "vins-mono"),
        ("vins_fusion_euroc_stereo.yaml", "matrix-yaml"),
        ("static_tf_script.sh", "static-tf-commands"),
        ("kitti_object_000000.txt", "kitti-object"),
        ("kitti_tracking_style.txt", "kitti-object"),
        ("nuscenes/calibrated_sensor.json", "nuscenes-json"),
        ("nuscenes_two_logs/calibrated_sensor.json", "nuscenes-json"),
        ("ouster_sdk_extrinsic_parameters.json", "ouster-extrinsics"),
        ("ouster_extrinsics_example.json", "ouster-extrinsics"),
        ("guardian_start_projection.bash", "static-tf-commands"),
        ("guardian_stop_projection.bash", "static-tf-commands"),
        ("dlio_livox_support.yaml", "dlio"),
        (
            "av2/av2_val_7fab2350_egovehicle_SE3_sensor.json",
            "av2-json",
        ),
        ("av2/av2_test_log_egovehicle_SE3_sensor.json", "av2-json"),
    ] {
        let Some(path) = fixture(file) else {
            continue;
        };
        let text = std::fs::read_to_string(&path).expect("read");
        let f = detect_format(&path, &text).expect("detect");
        assert_eq!(f.name(), id, "{file}");
    }
}

#[test]
fn fixed_frame_names_per_format() {
    let names = |g: FrameGraph| -> Vec<(String, String)> {
        g.edges()
            .iter()
            .map(|e| (e.parent.clone(), e.child.clone()))
            .collect()
    };
    let pair = |a: &str, b: &str| (a.to_string(), b.to_string());
    assert_eq!(
        names(graph("iglio_ncd.yaml", None)),
        vec![pair("imu", "lidar")]
    );
    assert_eq!(
        names(graph("vins_mono_euroc.yaml", None)),
        vec![pair("imu", "camera")]
    );
    assert_eq!(
        names(graph("vins_fusion_euroc_stereo.yaml", None)),
        vec![pair("body", "cam0"), pair("body", "cam1")]
    );
    let Some(dlio) = real_graph("dlio_default.yaml", None) else {
        return;
    };
    assert_eq!(
        names(dlio),
        vec![pair("base_link", "imu"), pair("base_link", "lidar")]
    );
}

#[test]
fn shell_script_gives_one_edge_per_publisher_command() {
    let g = graph("static_tf_script.sh", None);
    let edges: Vec<(String, String, Option<usize>, Option<usize>)> = g
        .edges()
        .iter()
        .map(|e| {
            let l = &e.provenance.location;
            (e.parent.clone(), e.child.clone(), l.line, l.column)
        })
        .collect();
    let e =
        |p: &str, c: &str, l: usize, col: usize| (p.to_string(), c.to_string(), Some(l), Some(col));
    assert_eq!(
        edges,
        vec![
            e("body", "avia_frame", 9, 1),
            e("imu", "os_sensor", 10, 2),
            e("base_link", "imu", 13, 12),
            e("base_link", "camera", 15, 1),
        ]
    );
}

#[test]
fn kitti_object_frames_and_the_raw_calib_rename_hint() {
    let g = graph("kitti_object_000000.txt", None);
    assert_eq!(g.roots(), vec!["cam0_rect".to_string()]);
    let mut frames = g.frames();
    frames.sort();
    assert_eq!(
        frames,
        [
            "cam0",
            "cam0_rect",
            "cam1_rect",
            "cam2_rect",
            "cam3_rect",
            "imu",
            "velo"
        ]
    );
    // P1: K [I | t] with t = (-387.5744 / 721.5377, 0, 0): cam1 sits 0.537 m to
    // the right of cam0 (x points right).
    let c1 = g.transform("cam0_rect", "cam1_rect").expect("cam1");
    assert!((c1.transform.translation().x - 387.5744 / 721.5377).abs() < 1e-12);
    // KITTI raw calib under another name: the warning says how to name frames.
    let dir = tempfile::tempdir().expect("tmp");
    let p = dir.path().join("imu2velo.txt");
    std::fs::copy("tests/fixtures/formats/calib_imu_to_velo.txt", &p).expect("copy");
    let l = load_file(&p, &LoadOptions::default()).expect("kitti raw");
    let w = l
        .warnings
        .iter()
        .find(|w| w.code == Code::AssumedConvention)
        .expect("warning");
    assert!(
        w.message
            .contains("--rename imu2velo.txt:source=imu --rename imu2velo.txt:target=velo"),
        "{}",
        w.message
    );
}

#[test]
fn nuscenes_names_from_sensor_json_and_blocks_a_sensor_calibrated_twice() {
    let g = graph("nuscenes/calibrated_sensor.json", None);
    assert_eq!(
        g.frames(),
        ["CAM_BACK_LEFT", "LIDAR_TOP", "RADAR_FRONT", "ego"]
    );
    assert!(g.warnings().is_empty(), "{:?}", g.warnings());
    let g = graph("nuscenes_two_logs/calibrated_sensor.json", None);
    assert_eq!(g.frames(), ["ego", "sensor_a0000000"]);
    let codes: Vec<Code> = g.warnings().iter().map(|w| w.code).collect();
    assert!(codes.contains(&Code::AssumedConvention), "{codes:?}");
    let amb = g
        .warnings()
        .iter()
        .find(|w| w.code == Code::AmbiguousKey)
        .expect("ambiguous");
    assert!(
        amb.message.contains("sensor_dc8b3966 is calibrated 2 times with different values (records 7a0cd258d096410eb68251b4b87febf5, f0000000000000000000000000000009)"),
        "{}",
        amb.message
    );
}

#[test]
fn kalibr_t_imu_cam_variant_and_imu0_naming() {
    let g = graph("kalibr_openvins_euroc_imucam_chain.yaml", None);
    assert_eq!(g.roots(), vec!["imu".to_string()]);
    assert!(g.redundant().is_empty());
    // A file with an `imu0` block names the IMU imu0 (Kalibr's IMU naming).
    let text = "imu0:\n  update_rate: 200.0\ncam0:\n  T_cam_imu:\n  - [1, 0, 0, 0.1]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n";
    let l = extrinsic_audit::internals::formats::load_str(
        text,
        Path::new("camchain-imucam.yaml"),
        &LoadOptions::default(),
    )
    .expect("imu0");
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("imu0", "cam0")
    );
    assert!((l.edges[0].transform.translation().x + 0.1).abs() < 1e-15);
}

#[test]
fn a_redundant_edge_between_unconnected_frames_joins_the_tree() {
    use extrinsic_audit::internals::frames::EdgeSet;
    use extrinsic_audit::Edge;
    use extrinsic_audit::Location;
    use extrinsic_audit::Transform;
    let t = |x: f64| Transform::from_translation([x, 0.0, 0.0]).expect("t");
    let e = |p: &str, c: &str, x: f64| {
        Edge::new(
            p,
            c,
            t(x),
            Location::default(),
            "matrix-yaml",
            format!("T_{p}_{c}"),
        )
    };
    let mut g = FrameGraph::new();
    g.add(EdgeSet {
        edges: vec![e("imu", "cam0", 0.1)],
        redundant: vec![e("cam1", "cam0", -0.2), e("cam1", "cam0", -0.2)],
        ..EdgeSet::default()
    })
    .expect("add");
    // The first joins cam1 to the tree (reversed: cam0 already has a parent);
    // the second is then checked against it and agrees.
    assert_eq!(g.parent_edge("cam1").expect("edge").parent, "cam0");
    assert_eq!(g.redundant().len(), 1);
    assert!(g.redundant()[0].agrees());
    let c = g.transform("imu", "cam1").expect("chain");
    assert!((c.transform.translation().x - 0.3).abs() < 1e-15);
}

#[test]
fn ouster_extrinsics_names_sensors_by_their_serials_under_world() {
    let Some(g) = real_graph("ouster_sdk_extrinsic_parameters.json", None) else {
        return;
    };
    assert_eq!(g.roots(), vec!["world".to_string()]);
    let edges: Vec<(&str, &str, Option<usize>)> = g
        .edges()
        .iter()
        .map(|e| {
            (
                e.parent.as_str(),
                e.child.as_str(),
                e.provenance.location.line,
            )
        })
        .collect();
    assert_eq!(
        edges,
        vec![
            ("world", "122150000150", Some(3)),
            ("world", "992313000353", Some(14)),
            ("world", "992225001114", Some(25)),
        ]
    );
    // The site frame puts sensors 55 m away: no millimetre warning.
    assert!(g.warnings().is_empty(), "{:?}", g.warnings());
    let g = real_graph("ouster_sdk_extrinsic_parameters.json", Some("992225001114")).unwrap();
    assert_eq!(g.edges().len(), 1);
    assert_eq!(g.edges()[0].child, "992225001114");
}

fn ouster_load(text: &str) -> extrinsic_audit::Result<extrinsic_audit::internals::formats::Parsed> {
    extrinsic_audit::internals::formats::load_str(
        text,
        Path::new("extrinsic_parameters.json"),
        &LoadOptions::default(),
    )
}

#[test]
fn ouster_extrinsics_bare_record_default_destination_and_duplicates() {
    // One record, as the sensor's Perception API returns it; no destination.
    let l = ouster_load(
        "{\"p_x\": 1.0, \"p_y\": 2.0, \"p_z\": 3.0, \"q_w\": 0.0, \"q_x\": 0.0, \"q_y\": 0.0, \"q_z\": 1.0, \"source_frame\": \"os_a\"}",
    )
    .expect("bare record");
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("world", "os_a")
    );
    assert_eq!(l.warnings[0].code, Code::AssumedConvention);
    // q = (w 0, z 1): a half-turn about z, p_dest = R p_src + p.
    let p = l.edges[0]
        .transform
        .apply(&nalgebra::Vector3::new(1.0, 0.0, 0.0));
    assert!(
        (p - nalgebra::Vector3::new(0.0, 2.0, 3.0)).norm() < 1e-15,
        "{p}"
    );
    // A sensor given twice with different values blocks only its own edge.
    let rec = |sn: &str, x: f64| {
        format!("{{\"destination_frame\": \"world\", \"p_x\": {x}, \"p_y\": 0, \"p_z\": 0, \"q_w\": 1, \"q_x\": 0, \"q_y\": 0, \"q_z\": 0, \"source_frame\": \"{sn}\"}}")
    };
    let text = format!(
        "{{\"transforms\": [\n{},\n{},\n{}\n]}}",
        rec("A", 1.0),
        rec("B", 2.0),
        rec("A", 1.5)
    );
    let l = ouster_load(&text).expect("one sensor left");
    assert_eq!(l.edges.len(), 1);
    assert_eq!(l.edges[0].child, "B");
    let w = &l.warnings[0];
    assert_eq!(w.code, Code::AmbiguousKey);
    assert!(
        w.message
            .contains("source_frame A is given 2 times with different values (line 2 and line 4)"),
        "{}",
        w.message
    );
    let e = ouster_load("{\"transforms\": [{\"source_frame\": \"A\", \"p_x\": 1}]}")
        .expect_err("no p_y");
    assert!(
        e.message
            .contains("record: expected `p_y` (a number), found none"),
        "{}",
        e.message
    );
}

#[test]
fn cli_reads_ouster_extrinsics_between_two_sensors() {
    let Some(f) = fixture("ouster_sdk_extrinsic_parameters.json") else {
        return;
    };
    let out = audit()
        .args([
            f.to_str().unwrap(),
            "--from",
            "122150000150",
            "--to",
            "992313000353",
            "--format",
            "json",
        ])
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("ouster-extrinsics"), "{stdout}");
}

#[test]
fn kalibr_wiki_example_redundant_edge_agrees() {
    // The wiki's T_cn_cnm1 matches T_c1_i inv(T_c0_i) to 1.7e-8 m (numpy);
    // voxblox's EuRoC camchain (Kalibr output) to 4e-17 m.
    for f in [
        "kalibr_wiki_example_chain.yaml",
        "kalibr_voxblox_euroc_camchain.yaml",
    ] {
        let Some(g) = real_graph(f, None) else {
            continue;
        };
        assert_eq!(g.roots(), vec!["imu".to_string()], "{f}");
        let r = g.redundant();
        assert_eq!(r.len(), 1, "{f}");
        assert!(r[0].agrees(), "{f}: {:?}", r[0]);
        assert!(g
            .warnings()
            .iter()
            .all(|w| w.code != Code::RedundantEdgeDisagrees));
    }
}

#[test]
fn av2_rows_are_sensor_poses_under_egovehicle() {
    let g = graph("av2/av2_val_7fab2350_egovehicle_SE3_sensor.json", None);
    assert_eq!(g.roots(), vec!["egovehicle".to_string()]);
    assert_eq!(g.edges().len(), 11);
    assert!(g.edges().iter().all(|e| e.parent == "egovehicle"));
    assert!(g.warnings().is_empty(), "{:?}", g.warnings());
    // up_lidar: qw 0.99998707, qz -0.00508497: a yaw of -0.5826 deg.
    let up = g.transform("egovehicle", "up_lidar").expect("up_lidar");
    let yaw = up.transform.rotation()[(1, 0)].atan2(up.transform.rotation()[(0, 0)]);
    assert!((yaw - 2.0 * (-0.005084966495157445f64).atan2(0.9999870714742982)).abs() < 1e-15);
    let text = "[\n{\"sensor_name\": \"up_lidar\", \"qw\": 1, \"qx\": 0, \"qy\": 0, \"qz\": 0, \"tx_m\": 1, \"ty_m\": 0, \"tz_m\": 1},\n{\"sensor_name\": \"up_lidar\", \"qw\": 1, \"qx\": 0, \"qy\": 0, \"qz\": 0, \"tx_m\": 1.2, \"ty_m\": 0, \"tz_m\": 1},\n{\"sensor_name\": \"down_lidar\", \"qw\": 1, \"qx\": 0, \"qy\": 0, \"qz\": 0, \"tx_m\": 1, \"ty_m\": 0, \"tz_m\": 0.5}\n]";
    let l = extrinsic_audit::internals::formats::load_str(
        text,
        Path::new("egovehicle_SE3_sensor.json"),
        &LoadOptions::default(),
    )
    .expect("one row left");
    assert_eq!(l.edges.len(), 1);
    assert_eq!(l.edges[0].child, "down_lidar");
    assert!(
        l.warnings[0]
            .message
            .contains("sensor up_lidar is listed 2 times with different values (lines 2 and 3)"),
        "{}",
        l.warnings[0].message
    );
}

/// The `.feather` fixtures written by `av2/json_to_feather.py` (pyarrow) from
/// the JSON rows, with the JSON file each came from.
const AV2_FEATHER: [(&str, &str); 8] = [
    (
        "av2/av2_val_7fab2350_egovehicle_SE3_sensor.uncompressed.feather",
        "av2/av2_val_7fab2350_egovehicle_SE3_sensor.json",
    ),
    (
        "av2/av2_val_7fab2350_egovehicle_SE3_sensor.lz4.feather",
        "av2/av2_val_7fab2350_egovehicle_SE3_sensor.json",
    ),
    (
        "av2/av2_val_7fab2350_egovehicle_SE3_sensor.zstd.feather",
        "av2/av2_val_7fab2350_egovehicle_SE3_sensor.json",
    ),
    (
        "av2/av2_test_log_egovehicle_SE3_sensor.uncompressed.feather",
        "av2/av2_test_log_egovehicle_SE3_sensor.json",
    ),
    (
        "av2/av2_test_log_egovehicle_SE3_sensor.lz4.feather",
        "av2/av2_test_log_egovehicle_SE3_sensor.json",
    ),
    (
        "av2/av2_test_log_egovehicle_SE3_sensor.zstd.feather",
        "av2/av2_test_log_egovehicle_SE3_sensor.json",
    ),
    (
        "av2/av2_test_log_large_utf8.zstd.feather",
        "av2/av2_test_log_egovehicle_SE3_sensor.json",
    ),
    // Three record batches of 4, 4 and 3 rows.
    (
        "av2/av2_val_7fab2350_batches_of_4.lz4.feather",
        "av2/av2_val_7fab2350_egovehicle_SE3_sensor.json",
    ),
];

fn load(file: &str, opts: &LoadOptions) -> extrinsic_audit::internals::formats::Parsed {
    load_file(&Path::new(DIR).join(file), opts).unwrap_or_else(|e| panic!("{file}: {e}"))
}

#[test]
fn av2_feather_gives_the_json_rows_edges() {
    for (feather, json) in AV2_FEATHER {
        let (f, j) = (
            load(feather, &LoadOptions::default()),
            load(json, &LoadOptions::default()),
        );
        assert_eq!(f.edges.len(), 11, "{feather}");
        assert!(f.warnings.is_empty(), "{feather}: {:?}", f.warnings);
        for (a, b) in f.edges.iter().zip(&j.edges) {
            assert_eq!((&a.parent, &a.child), (&b.parent, &b.child), "{feather}");
            assert_eq!(a.provenance.format, "av2-feather");
            assert_eq!(b.provenance.format, "av2-json");
            let (ma, mb) = (a.transform.matrix4(), b.transform.matrix4());
            assert!(
                (ma - mb).abs().max() <= 1e-12,
                "{feather} {}: {ma} vs {mb}",
                a.child
            );
            assert_eq!(a.precision, b.precision, "{feather} {}", a.child);
        }
    }
}

#[test]
fn av2_feather_matches_the_numpy_expected_transforms() {
    let text = std::fs::read_to_string(Path::new(DIR).join("expected.json")).expect("expected");
    let cases: serde_json::Value = serde_json::from_str(&text).expect("json");
    let mut n = 0;
    for c in cases.as_array().expect("list") {
        let json = c["file"].as_str().expect("file");
        for (feather, _) in AV2_FEATHER.iter().filter(|(_, j)| *j == json) {
            let (from, to) = (c["from"].as_str().unwrap(), c["to"].as_str().unwrap());
            let g = graph(feather, c["key"].as_str());
            let m = g.transform(from, to).expect("chain").transform.matrix4();
            for i in 0..4 {
                for k in 0..4 {
                    let want = c["matrix"][i][k].as_f64().expect("number");
                    assert!(
                        (m[(i, k)] - want).abs() <= 1e-9,
                        "{feather} {from} -> {to} ({i},{k}): {} vs {want}",
                        m[(i, k)]
                    );
                }
            }
            n += 1;
        }
    }
    assert_eq!(n, 40, "5 cases per JSON file, 4 feather files each");
}

#[test]
fn av2_feather_is_detected_by_its_magic_and_reads_one_key() {
    use extrinsic_audit::internals::formats::load_bytes;
    let bytes = std::fs::read(Path::new(DIR).join(AV2_FEATHER[1].0)).expect("read");
    // No `.feather` name: the `ARROW1` magic decides.
    let l = load_bytes(
        bytes.clone(),
        Path::new("calib.bin"),
        &LoadOptions::default(),
    )
    .expect("magic");
    assert_eq!(l.edges[0].provenance.format, "av2-feather");
    let mut opts = LoadOptions::default();
    opts.key = Some("up_lidar".into());
    let l = load_bytes(bytes.clone(), Path::new("x.feather"), &opts).expect("key");
    assert_eq!(l.edges.len(), 1);
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("egovehicle", "up_lidar")
    );
    let mut opts = LoadOptions::default();
    opts.key = Some("no_such".into());
    let e = load_bytes(bytes, Path::new("x.feather"), &opts).expect_err("no row");
    assert!(e.message.contains("no row with sensor_name no_such"), "{e}");
    // A `.feather` name without the magic, and Feather version 1.
    for (b, want) in [
        (
            b"sensor_name,qw\n".to_vec(),
            "expected the magic `ARROW1` at the start",
        ),
        (b"FEA1\0\0\0\0".to_vec(), "a Feather version 1 file"),
    ] {
        let e =
            load_bytes(b, Path::new("x.feather"), &LoadOptions::default()).expect_err("refused");
        assert!(e.message.contains(want), "{e}");
    }
}

#[test]
fn av2_feather_null_names_its_row() {
    let e = load_file(
        &Path::new(DIR).join("av2/av2_null_qw_row3.uncompressed.feather"),
        &LoadOptions::default(),
    )
    .expect_err("null");
    assert_eq!(e.code, Code::Parse);
    assert!(
        e.message
            .starts_with("row 3: `qw` is null: expected a value"),
        "{e}"
    );
}

/// Every prefix of a fixture is refused, never accepted or panicking.
#[test]
fn av2_feather_every_truncation_is_an_error() {
    use extrinsic_audit::internals::formats::load_bytes;
    for (file, _) in &AV2_FEATHER[..3] {
        let bytes = std::fs::read(Path::new(DIR).join(file)).expect("read");
        for cut in 0..bytes.len() {
            let r = load_bytes(
                bytes[..cut].to_vec(),
                Path::new("t.feather"),
                &LoadOptions::default(),
            );
            assert!(r.is_err(), "{file} cut at {cut}: accepted");
        }
    }
}

/// The mutation test that broke `arrow-ipc` 60.1 (85 panics, 21 aborts in
/// 1,500 copies): 1,500 copies of each fixture with 1 to 8 random bytes
/// changed, seeded. No panic, no abort, no hang; every copy read is sane.
#[test]
fn av2_feather_survives_random_byte_changes() {
    use extrinsic_audit::internals::formats::load_bytes;
    use rand_core::RngCore;
    let start = std::time::Instant::now();
    let mut rng = rand_pcg::Pcg64::new(0xa2f3_0014, 0x5eed);
    let (mut ok, mut refused) = (0, 0);
    for (file, _) in &AV2_FEATHER[..3] {
        let clean = std::fs::read(Path::new(DIR).join(file)).expect("read");
        for _ in 0..1500 {
            let mut b = clean.clone();
            for _ in 0..1 + rng.next_u32() % 8 {
                let i = rng.next_u32() as usize % b.len();
                b[i] = rng.next_u32() as u8;
            }
            match load_bytes(b, Path::new("m.feather"), &LoadOptions::default()) {
                Ok(l) => {
                    ok += 1;
                    assert!(!l.edges.is_empty() && l.edges.len() <= 11);
                    for e in &l.edges {
                        let m = e.transform.matrix4();
                        assert!(m.iter().all(|x| x.is_finite()), "{file}: {m}");
                    }
                }
                Err(e) => {
                    refused += 1;
                    assert!(
                        matches!(e.code, Code::Parse | Code::Invalid | Code::Limit),
                        "{file}: {:?} {e}",
                        e.code
                    );
                }
            }
        }
    }
    assert_eq!(ok + refused, 4500);
    let secs = start.elapsed().as_secs_f64();
    eprintln!("4,500 mutated feather files: {ok} read, {refused} refused, {secs:.2} s");
    assert!(secs < 20.0, "{secs} s");
}

/// A compressed buffer's 8-byte length header: a claim beyond the
/// `--max-file-size` budget is refused before decompressing; a wrong claim
/// is an error, never a short or padded column.
#[test]
fn av2_feather_compressed_lengths_are_checked() {
    use extrinsic_audit::internals::formats::load_bytes;
    for (file, magic) in [
        (AV2_FEATHER[2].0, [0x28u8, 0xb5, 0x2f, 0xfd]),
        (AV2_FEATHER[1].0, [0x04, 0x22, 0x4d, 0x18]),
    ] {
        let clean = std::fs::read(Path::new(DIR).join(file)).expect("read");
        let at = clean
            .windows(4)
            .position(|w| w == magic)
            .expect("a compressed frame");
        let claim = i64::from_le_bytes(clean[at - 8..at].try_into().unwrap());
        let with = |v: i64| {
            let mut b = clean.clone();
            b[at - 8..at].copy_from_slice(&v.to_le_bytes());
            load_bytes(b, Path::new("c.feather"), &LoadOptions::default())
        };
        let e = with(1 << 40).expect_err("huge claim");
        assert_eq!(e.code, Code::Limit, "{file}: {e}");
        assert!(
            e.message
                .contains("claims 1099511627776 bytes uncompressed"),
            "{e}"
        );
        let e = with(claim + 1).expect_err("claim too long");
        assert!(
            e.message.contains(&format!(
                "decompresses to {claim} bytes, its header says {}",
                claim + 1
            )),
            "{file}: {e}"
        );
        let e = with(claim - 1).expect_err("claim too short");
        assert!(
            e.message
                .contains(&format!("decompresses to {claim}+ bytes")),
            "{file}: {e}"
        );
        // Every decompressed byte counts against the --max-file-size cap.
        let mut opts = LoadOptions::default();
        opts.max_file_size = 500;
        let e = load_bytes(clean.clone(), Path::new("c.feather"), &opts).expect_err("cap");
        assert_eq!(e.code, Code::Limit, "{file}: {e}");
    }
}

#[test]
fn av2_feather_duplicate_sensor_names_both_rows() {
    let l = load(
        "av2/av2_up_lidar_twice.uncompressed.feather",
        &LoadOptions::default(),
    );
    assert_eq!(l.edges.len(), 10);
    assert!(l.edges.iter().all(|e| e.child != "up_lidar"));
    assert_eq!(l.warnings.len(), 1);
    assert_eq!(l.warnings[0].code, Code::AmbiguousKey);
    assert!(
        l.warnings[0]
            .message
            .contains("sensor up_lidar is listed 2 times with different values (rows 10 and 12)"),
        "{}",
        l.warnings[0].message
    );
}

#[test]
fn cli_reads_a_feather_file_and_feather_on_stdin() {
    let f = format!("{DIR}/{}", AV2_FEATHER[2].0);
    let out = audit()
        .args([f.as_str(), "--frames"])
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("egovehicle") && text.contains("down_lidar"),
        "{text}"
    );
    // Standard input has no name: the ARROW1 magic selects the reader.
    let out = audit()
        .args([
            "-",
            "--from",
            "egovehicle",
            "--to",
            "up_lidar",
            "--format",
            "json",
        ])
        .write_stdin(std::fs::read(&f).expect("read"))
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn av2_feather_key_reads_past_a_null_in_another_row() {
    // Row 3 (ring_front_right) has a null qw; --key up_lidar does not read it.
    let mut opts = LoadOptions::default();
    opts.key = Some("up_lidar".into());
    let l = load("av2/av2_null_qw_row3.uncompressed.feather", &opts);
    assert_eq!(l.edges.len(), 1);
    assert_eq!(l.edges[0].child, "up_lidar");
}

#[test]
fn av2_feather_bad_quaternion_names_the_row() {
    use extrinsic_audit::internals::formats::load_bytes;
    let mut b = std::fs::read(Path::new(DIR).join(AV2_FEATHER[0].0)).expect("read");
    // Row 1 (ring_front_center): qw qx qy qz as in the JSON, set to zero.
    for v in [
        0.5016454083000883f64,
        -0.49861992463738697,
        0.5010700093854159,
        -0.4986570973931321,
    ] {
        let at = b
            .windows(8)
            .position(|w| w == v.to_le_bytes())
            .expect("the value");
        b[at..at + 8].copy_from_slice(&0f64.to_le_bytes());
    }
    let e = load_bytes(b, Path::new("q.feather"), &LoadOptions::default()).expect_err("zero");
    assert!(e.message.starts_with("row 1 (ring_front_center): "), "{e}");
}
