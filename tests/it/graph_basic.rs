//! Frame graph behaviour: duplicates, two parents, cycles, unknown frames,
//! composition through the common ancestor, several files in one graph, and the
//! URDF details (joints, mimic, quat_xyzw, axes, xacro).

use extrinsic_audit::internals::formats::{load_file, load_str};
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::Transform;
use extrinsic_audit::{Assume, Edge, Format, LoadOptions};
use extrinsic_audit::{Code, Location};
use std::path::Path;

fn edge(p: &str, c: &str, t: Transform, line: usize) -> Edge {
    Edge::new(
        p,
        c,
        t,
        Location::at("test.txt", line, None),
        Format::from_name("static-tf-commands").unwrap(),
        "k",
    )
}

fn tr(x: f64, y: f64, z: f64) -> Transform {
    Transform::from_translation([x, y, z]).expect("t")
}

fn urdf(body: &str, opts: &LoadOptions) -> extrinsic_audit::Result<FrameGraph> {
    let text = format!("<?xml version=\"1.0\"?>\n<robot name=\"r\">\n{body}</robot>\n");
    let l = load_str(&text, Path::new("t.urdf"), opts)?;
    let mut g = FrameGraph::new();
    g.add(l)?;
    Ok(g)
}

#[test]
fn composes_up_then_down() {
    let mut g = FrameGraph::new();
    let rz =
        Transform::from_rpy([0.0, 0.0, std::f64::consts::FRAC_PI_2], [1.0, 0.0, 0.0]).expect("rpy");
    g.add_edge(edge("base", "imu", rz, 1)).expect("e");
    g.add_edge(edge("base", "lidar", tr(0.0, 2.0, 0.0), 2))
        .expect("e");
    let c = g.transform("imu", "lidar").expect("chain");
    // lidar origin in imu: R^T (p - d) with p = (0,2,0), d = (1,0,0), R = Rz(90)
    let d = c.transform.translation();
    assert!(
        (d.x - 2.0).abs() < 1e-12 && (d.y - 1.0).abs() < 1e-12 && d.z.abs() < 1e-12,
        "{d:?}"
    );
    assert_eq!(c.steps.len(), 2);
    assert!(c.steps[0].inverted && !c.steps[1].inverted);
    assert_eq!(c.steps[0].edge.child, "imu");
    // inverse path
    let back = g.transform("lidar", "imu").expect("chain");
    let id = back.transform.compose(&c.transform);
    assert!(id.translation().norm() < 1e-12);
    // same frame
    assert!(g.transform("imu", "imu").expect("id").steps.is_empty());
}

#[test]
fn duplicate_edges() {
    let mut g = FrameGraph::new();
    g.add_edge(edge("a", "b", tr(0.1, 0.0, 0.0), 1)).expect("e");
    // Agreeing (and the reverse pair agreeing): notes, not errors.
    g.add_edge(edge("a", "b", tr(0.1 + 1e-12, 0.0, 0.0), 2))
        .expect("dup");
    g.add_edge(edge("b", "a", tr(-0.1, 0.0, 0.0), 3))
        .expect("reverse dup");
    let dups = g
        .warnings()
        .iter()
        .filter(|w| w.code == Code::DuplicateEdge)
        .count();
    assert_eq!(dups, 2);
    assert!(g.warnings()[0].message.contains("test.txt:1"));
    // Disagreeing: an error naming both places.
    let e = g
        .add_edge(edge("a", "b", tr(0.2, 0.0, 0.0), 4))
        .expect_err("conflict");
    assert_eq!(e.code, Code::Frame);
    let m = e.to_string();
    assert!(m.contains("test.txt:1") && m.contains("test.txt:4"), "{m}");
    let e = g
        .add_edge(edge("b", "a", tr(0.2, 0.0, 0.0), 5))
        .expect_err("conflict");
    assert!(e.to_string().contains("reverse"), "{e}");
}

#[test]
fn two_parents_cycle_unknown_not_connected() {
    let mut g = FrameGraph::new();
    g.add_edge(edge("base", "arm", tr(1.0, 0.0, 0.0), 1))
        .expect("e");
    g.add_edge(edge("arm", "lidar", tr(1.0, 0.0, 0.0), 2))
        .expect("e");
    let e = g
        .add_edge(edge("base", "lidar", tr(1.0, 0.0, 0.0), 3))
        .expect_err("two parents");
    assert!(
        e.message.contains("two parents")
            && e.message.contains("test.txt:2")
            && e.message.contains("test.txt:3"),
        "{e}"
    );
    let e = g
        .add_edge(edge("lidar", "base", tr(1.0, 0.0, 0.0), 4))
        .expect_err("cycle");
    assert!(e.message.contains("cycle"), "{e}");
    let e = g
        .add_edge(edge("x", "x", tr(1.0, 0.0, 0.0), 5))
        .expect_err("self");
    assert!(e.message.contains("its own parent"));
    let e = g.transform("base", "lidr").expect_err("unknown");
    assert!(e.message.contains("closest: 'lidar'"), "{e}");
    g.add_edge(edge("odom", "imu", tr(1.0, 0.0, 0.0), 6))
        .expect("e");
    let e = g.transform("lidar", "imu").expect_err("not connected");
    assert!(
        e.message.contains("'base'") && e.message.contains("'odom'"),
        "{e}"
    );
    assert_eq!(g.roots(), vec!["base".to_string(), "odom".to_string()]);
    assert_eq!(g.closest_frames("Base", 1), vec!["base".to_string()]);
    let tree = g.tree();
    assert!(
        tree.contains("base\n└── arm  [test.txt:1]\n    └── lidar  [test.txt:2]\n"),
        "{tree}"
    );
}

#[test]
fn several_files_in_one_graph() {
    // A URDF plus a calibration file that hangs the LiDAR under its IMU link.
    let urdf = crate::real!(crate::common::testdata::ANYMAL_D);
    let mut g = FrameGraph::new();
    g.add(load_file(&urdf, &LoadOptions::default()).expect("urdf"))
        .expect("add");
    let text = "ros2 run tf2_ros static_transform_publisher --x 0.04165 --y 0.02326 --z -0.0284 --frame-id imu_link --child-frame-id livox_frame\n";
    g.add(load_str(text, Path::new("cmd.txt"), &LoadOptions::default()).expect("cmd"))
        .expect("add");
    let c = g.transform("base", "livox_frame").expect("chain");
    let last = c.steps.last().expect("step");
    assert_eq!(last.edge.provenance.format, "static-tf-commands");
    assert_eq!(c.steps[0].edge.provenance.format, "urdf");
    assert_eq!(g.files().len(), 2);
    let e = g.transform("base", "nowhere").expect_err("unknown");
    assert!(e.message.contains("files: "), "{e}");
}

#[test]
fn urdf_joints_mimic_and_axes() {
    let links = "<link name=\"a\"/><link name=\"b\"/><link name=\"c\"/><link name=\"d\"/>\n";
    let body = format!(
        "{links}<joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 2\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n\
         <joint name=\"j2\" type=\"prismatic\"><origin xyz=\"1 0 0\"/><parent link=\"b\"/><child link=\"c\"/><axis xyz=\"1 0 0\"/><mimic joint=\"j1\" multiplier=\"2\" offset=\"0.5\"/></joint>\n\
         <joint name=\"j3\" type=\"fixed\"><parent link=\"c\"/><child link=\"d\"/><axis xyz=\"0 0 0\"/></joint>\n"
    );
    let g = urdf(&body, &LoadOptions::default()).expect("load");
    assert!(g
        .warnings()
        .iter()
        .any(|w| w.code == Code::NonUnitAxis && w.message.contains("j1")));
    let c = g.transform("a", "d").expect("chain");
    // j1 at 0, j2 = 2*0 + 0.5 -> x = 1.5
    assert!((c.transform.translation().x - 1.5).abs() < 1e-12);
    assert_eq!(
        c.warnings
            .iter()
            .filter(|w| w.code == Code::JointAtDefault)
            .count(),
        2
    );
    let mut opts = LoadOptions::default();
    opts.joints.insert("j1".into(), std::f64::consts::FRAC_PI_2);
    let g = urdf(&body, &opts).expect("load");
    let c = g.transform("a", "d").expect("chain");
    // j1 rotates 90 deg about z; j2 = 2*pi/2 + 0.5 along b's x, which is a's y
    let d = c.transform.translation();
    assert!(
        d.x.abs() < 1e-12 && (d.y - (1.0 + std::f64::consts::PI + 0.5)).abs() < 1e-12,
        "{d:?}"
    );
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
}

/// urdfdom 5.1 (urdf_schema_quaternion_test.cpp): `quat_xyzw` is applied from
/// URDF 1.1; in a 1.0 file (declared or by default) ROS ignores it.
#[test]
fn urdf_quat_xyzw_follows_the_version() {
    let body = "<link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"fixed\"><origin xyz=\"0 0 0.1\" quat_xyzw=\"0 0 0.7071067811865476 0.7071067811865476\"/><parent link=\"a\"/><child link=\"b\"/></joint>\n";
    let load = |version: &str, opts: &LoadOptions| {
        let text = format!("<robot name=\"r\"{version}>\n{body}</robot>\n");
        let mut g = FrameGraph::new();
        g.add(load_str(&text, Path::new("t.urdf"), opts).expect("load"))
            .expect("add");
        let r = g.transform("a", "b").expect("chain").transform;
        (r, g.warnings().to_vec())
    };
    let codes = |ws: &[extrinsic_audit::Warning]| ws.iter().map(|w| w.code).collect::<Vec<_>>();
    // 1.0, by default or declared: the identity, with a warning naming the cause.
    for v in ["", " version=\"1.0\""] {
        let (r, ws) = load(v, &LoadOptions::default());
        assert!((r.rotation()[(0, 0)] - 1.0).abs() < 1e-15, "{v}: identity");
        assert!((r.translation().z - 0.1).abs() < 1e-15);
        assert_eq!(codes(&ws), vec![Code::QuatXyzwIgnored], "{v}");
        assert!(
            ws[0].message.contains("version=\"1.1\""),
            "{}",
            ws[0].message
        );
    }
    // 1.1: a 90 deg yaw, nothing to warn about.
    let (r, ws) = load(" version=\"1.1\"", &LoadOptions::default());
    assert!((r.rotation()[(1, 0)] - 1.0).abs() < 1e-12, "a 90 deg yaw");
    assert!(ws.is_empty(), "{ws:?}");
    // --urdf-version 1.1 on a 1.0 file: applied, and the warning says ROS differs.
    let mut opts = LoadOptions::default();
    opts.urdf_version = Some(extrinsic_audit::UrdfVersion::V1_1);
    let (r, ws) = load("", &opts);
    assert!((r.rotation()[(1, 0)] - 1.0).abs() < 1e-12, "a 90 deg yaw");
    assert_eq!(codes(&ws), vec![Code::AssumedConvention]);
    assert!(
        ws[0].message.contains("ROS ignores it"),
        "{}",
        ws[0].message
    );
}

#[test]
#[allow(clippy::approx_constant)] // Husky's imu_joint writes 1.5708 and 3.1416
fn urdf_rounded_pi_and_gimbal_lock_follow_rpy() {
    let g = urdf(
        "<link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"fixed\"><origin xyz=\"0 0 0\" rpy=\"0 -1.5708 3.1416\"/><parent link=\"a\"/><child link=\"b\"/></joint>\n",
        &LoadOptions::default(),
    )
    .expect("load");
    let t = g.transform("a", "b").expect("c").transform;
    let want = Transform::from_rpy([0.0, -1.5708, 3.1416], [0.0; 3]).expect("rpy");
    assert!((t.matrix4() - want.matrix4()).abs().max() < 1e-15);
}

#[test]
fn floating_joint_needs_setting() {
    let body = "<link name=\"w\"/><link name=\"b\"/>\n<joint name=\"free\" type=\"floating\"><parent link=\"w\"/><child link=\"b\"/></joint>\n";
    let g = urdf(body, &LoadOptions::default()).expect("load");
    let e = g.transform("w", "b").expect_err("floating");
    assert!(e.message.contains("--joint free=0"), "{e}");
    let mut opts = LoadOptions::default();
    opts.joints.insert("free".into(), 0.0);
    let g = urdf(body, &opts).expect("load");
    assert!(g.transform("w", "b").is_ok());
    assert_eq!(g.joint_names(), vec!["free".to_string()]);
}

#[test]
fn xacro_in_urdf_refused_with_advice() {
    let e = urdf("<link name=\"${prefix}base\"/>\n", &LoadOptions::default()).expect_err("xacro");
    assert!(
        e.message.contains("xacro") && e.message.contains("--input-format xacro"),
        "{e}"
    );
}

#[test]
fn invert_key_format_and_size_options() {
    let p = Path::new("tests/fixtures/formats/fastlio_avia.yaml");
    let l = load_file(p, &{
        let mut o = LoadOptions::default();
        o.invert = true;
        o
    })
    .expect("load");
    // The frames stay; the numbers are read as the pose of imu in lidar.
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("imu", "lidar")
    );
    assert!((l.edges[0].transform.translation().x + 0.04165).abs() < 1e-15);
    let e = load_file(p, &{
        let mut o = LoadOptions::default();
        o.max_file_size = 10;
        o
    })
    .expect_err("cap");
    assert_eq!(e.code, Code::Limit);
    // --input-format skips detection.
    let e = load_file(p, &{
        let mut o = LoadOptions::default();
        o.format = Some(Format::from_name("urdf").unwrap());
        o
    })
    .expect_err("not xml");
    assert!(e.message.contains("XML"), "{e}");
    for (f, _) in extrinsic_audit::internals::formats::all_formats() {
        assert_eq!(Format::from_name(f.name()).expect("name"), f);
        assert!(!f.description().is_empty());
    }
    assert!(Format::from_name("fastlio").is_err());
    assert_eq!(
        Format::from_name("FAST_LIO").expect("alias"),
        Format::from_name("fast-lio").unwrap()
    );
}

#[test]
fn ouster_is_millimetres_and_lio_sam_direction() {
    use crate::common::testdata::{LIOSAM_MID360, OUSTER_OS0_JSON};
    let (Some(ouster), Some(liosam)) = (
        crate::common::testdata::file(OUSTER_OS0_JSON),
        crate::common::testdata::file(LIOSAM_MID360),
    ) else {
        return;
    };
    let l = load_file(&ouster, &LoadOptions::default()).expect("ouster");
    let lidar = l
        .edges
        .iter()
        .find(|e| e.child == "os_lidar")
        .expect("os_lidar");
    assert!((lidar.transform.translation().z - 0.03618).abs() < 1e-15);
    assert_eq!(lidar.parent, "os_sensor");
    let l = load_file(&liosam, &LoadOptions::default()).expect("liosam");
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("lidar", "imu")
    );
}

#[test]
fn millimetres_in_metre_field_and_trailing_commas() {
    let text = "mapping:\n  extrinsic_T: [41.65, 23.26, -28.4]\n  extrinsic_R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n";
    let l = load_str(text, Path::new("x.yaml"), &LoadOptions::default()).expect("load");
    assert!(l
        .warnings
        .iter()
        .any(|w| w.code == Code::MillimetresInMetreField));
    let l = load_file(
        Path::new("tests/fixtures/formats/kr_quadrotor_publish_tf.launch"),
        &LoadOptions::default(),
    )
    .expect("launch");
    assert_eq!(l.edges.len(), 2);
    assert!(l
        .warnings
        .iter()
        .any(|w| w.code == Code::Ignored && w.message.contains("trailing comma")));
}

#[test]
fn kalibr_and_t_xyz_q_xyzw_keys() {
    let text = "cam0:\n  T_cam_imu:\n  - [1, 0, 0, 0.1]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\ncam1:\n  T_cn_cnm1:\n  - [1, 0, 0, -0.1]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n";
    let l = load_str(
        text,
        Path::new("camchain-imucam.yaml"),
        &LoadOptions::default(),
    )
    .expect("kalibr");
    let names: Vec<(String, String)> = l
        .edges
        .iter()
        .map(|e| (e.parent.clone(), e.child.clone()))
        .collect();
    // Issue 14: the IMU is the root (T_cam_imu inverted); cam1's only edge,
    // T_cn_cnm1, joins it to the tree reversed (cam0 already has a parent).
    assert_eq!(
        names,
        vec![
            ("imu".into(), "cam0".into()),
            ("cam0".into(), "cam1".into())
        ]
    );
    let text = "T_cam_front_lidar_t_xyz_q_xyzw: [0.1, 0.2, 0.3, 0, 0, 0, 1]\n";
    let l = load_str(text, Path::new("sensor.yaml"), &{
        let mut o = LoadOptions::default();
        o.key = Some("T_cam_front_lidar_t_xyz_q_xyzw".into());
        o
    });
    // `cam_front` has an underscore: the name is ambiguous unless written
    // A_T_B, so it is refused unless --assume says which (e3480dc).
    let e = l.expect_err("an ambiguous --key is refused");
    assert!(
        e.message
            .contains("says neither the frames nor the direction")
            && e.message.contains("--assume child-in-parent:PARENT,CHILD"),
        "{e}"
    );
    let text = "cam_front_T_lidar_t_xyz_q_xyzw: [0.1, 0.2, 0.3, 0, 0, 0, 1]\n";
    let l = load_str(text, Path::new("sensor.yaml"), &LoadOptions::default()).expect("A_T_B");
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("cam_front", "lidar")
    );
}

#[test]
fn keyed_reads_stacked_millimetres_and_json_matrices() {
    let slict = Path::new("tests/fixtures/formats/slict_mcdviral_hhs.yaml");
    let whole = load_file(slict, &LoadOptions::default()).expect("slict");
    let picked = load_file(slict, &{
        let mut o = LoadOptions::default();
        o.key = Some("lidar_extr[0]".into());
        // The key's name gives no frames (issue 28: --assume gives them).
        o.assume = Assume::parse("child-in-parent:body,lidar").ok();
        o
    })
    .expect("slict[0]");
    assert!(
        (picked.edges[0].transform.matrix4() - whole.edges[0].transform.matrix4())
            .abs()
            .max()
            < 1e-15
    );
    let e = load_file(slict, &{
        let mut o = LoadOptions::default();
        o.key = Some("lidar_extr[1]".into());
        o.assume = Assume::parse("child-in-parent:body,lidar").ok();
        o
    })
    .expect_err("only one");
    assert!(e.message.contains("expected at least 2"), "{e}");
    // GEODE's millimetre block, picked by --key, is converted to metres.
    let geode = Path::new("tests/fixtures/formats/geode_gamma_opencv.yaml");
    let l = load_file(geode, &{
        let mut o = LoadOptions::default();
        o.key = Some("T_CamL_CamR".into());
        o
    })
    .expect("mm");
    assert!((l.edges[0].transform.translation().x + 0.1884272993645592).abs() < 1e-12);
    assert!(l.warnings.iter().any(|w| w.message.contains("millimetres")));
    // Without --key, GEODE's duplicate key blocks only its own edge (issue 14).
    let l = load_file(geode, &LoadOptions::default()).expect("dup");
    assert!(l
        .warnings
        .iter()
        .any(|w| w.code == Code::AmbiguousKey && w.message.contains("T_LiDAR_CamL")));
    assert!(l.edges.iter().all(|e| e.provenance.key != "T_LiDAR_CamL"));
    // A JSON file with T_A_B keys.
    let text = "{\"T_imu_lidar\": [[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0.2], [0, 0, 0, 1]]}";
    let l = load_str(text, Path::new("calib.json"), &LoadOptions::default()).expect("json");
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("imu", "lidar")
    );
    assert_eq!(l.edges[0].provenance.location.line, Some(1));
}

#[test]
fn tree_of_a_deep_chain_stays_linear() {
    let mut g = FrameGraph::new();
    for i in 1..3000 {
        g.add_edge(edge(
            &format!("f{}", i - 1),
            &format!("f{i}"),
            tr(0.01, 0.0, 0.0),
            i,
        ))
        .expect("e");
    }
    g.add_edge(edge("f0", "side", tr(0.0, 1.0, 0.0), 9999))
        .expect("e");
    let t = g.tree();
    assert!(t.len() < 3000 * 250, "{}", t.len());
    assert!(t.contains("[depth 2999] f2999"));
    assert!(
        t.starts_with("f0\n├── f1  [test.txt:1]\n│   └── f2  [test.txt:2]\n"),
        "{}",
        &t[..200]
    );
    assert!(t.ends_with("└── side  [test.txt:9999]\n"));
    let c = g.transform("f2999", "side").expect("chain");
    assert_eq!(c.steps.len(), 3000);
    assert!((c.transform.translation().x + 29.99).abs() < 1e-9);
}
