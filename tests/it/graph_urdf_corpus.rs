//! Every URDF of the corpus loads, and transforms between frame pairs (several
//! going up and then down the tree) equal values from an independent
//! implementation (pytransform3d; see tests/fixtures/urdf/gen_expected.py) to 1e-12.
//! The real robots are read in place from the test-data folder
//! (`testdata::URDFS`); the kinematic trees written here are in tests/fixtures/urdf.

use crate::common::testdata::{self, URDFS};
use extrinsic_audit::internals::formats::load_file;
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::Code;
use extrinsic_audit::LoadOptions;

/// The project's own kinematic trees (names and numbers of real robots).
const OWN: [&str; 3] = [
    "husky_kinematics.urdf",
    "velodyne_vlp16_hdl32e_kinematics.urdf",
    "ouster_os1_64_kinematics.urdf",
];

/// The frame graph of corpus file `file` (`None`: a real one, absent).
fn graph(file: &str) -> Option<FrameGraph> {
    let path = testdata::urdf(file)?;
    let l = load_file(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{file}: {e}"));
    let mut g = FrameGraph::new();
    g.add(l).unwrap_or_else(|e| panic!("{file}: {e}"));
    Some(g)
}

#[test]
fn every_corpus_urdf_loads() {
    let mut n = 0;
    for f in URDFS.iter().map(|(name, _)| *name).chain(OWN) {
        let Some(g) = graph(f) else { continue };
        assert!(g.edges().len() >= 5, "{f}");
        assert_eq!(g.roots().len(), 1, "{f}: one tree");
        n += 1;
    }
    assert!(n >= OWN.len(), "{n} corpus files");
}

#[test]
fn frame_pairs_match_pytransform3d() {
    let text = std::fs::read_to_string("tests/fixtures/urdf/expected_pairs.json").expect("json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("json");
    let pairs = v["pairs"].as_array().expect("pairs");
    assert!(pairs.len() >= 20);
    let (mut up_then_down, mut skipped) = (0, 0);
    for p in pairs {
        let file = p["file"].as_str().expect("file");
        let from = p["from"].as_str().expect("from");
        let to = p["to"].as_str().expect("to");
        let Some(g) = graph(file) else {
            skipped += 1;
            continue;
        };
        let chain = g
            .transform(from, to)
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        if chain.steps.iter().any(|s| s.inverted) && chain.steps.iter().any(|s| !s.inverted) {
            up_then_down += 1;
        }
        let m = chain.transform.matrix4();
        for i in 0..4 {
            for j in 0..4 {
                let w = p["T"][i][j].as_f64().expect("num");
                assert!(
                    (m[(i, j)] - w).abs() <= 1e-12,
                    "{file} {from} -> {to}: entry ({i},{j}) = {} expected {w}",
                    m[(i, j)]
                );
            }
        }
    }
    assert!(
        up_then_down >= 5 || skipped > 0,
        "only {up_then_down} pairs go up then down"
    );
}

/// Movable joints on a path default to 0 with a warning naming them.
#[test]
fn movable_joints_on_path_warn() {
    let Some(g) = graph("pr2.urdf") else { return };
    let c = g
        .transform("base_laser_link", "laser_tilt_link")
        .expect("chain");
    let names: Vec<String> = c
        .warnings
        .iter()
        .filter(|w| w.code == Code::JointAtDefault)
        .map(|w| w.message.clone())
        .collect();
    assert!(
        names.iter().any(|m| m.contains("torso_lift_joint")),
        "{names:?}"
    );
    assert!(
        names.iter().any(|m| m.contains("laser_tilt_mount_joint")),
        "{names:?}"
    );
    // Setting the prismatic torso moves the laser by exactly that much along z.
    let mut opts = LoadOptions::default();
    opts.joints.insert("torso_lift_joint".into(), 0.1);
    let pr2 = testdata::urdf("pr2.urdf").expect("read above");
    let l = load_file(&pr2, &opts).expect("load");
    let mut g2 = FrameGraph::new();
    g2.add(l).expect("graph");
    let c2 = g2
        .transform("base_laser_link", "laser_tilt_link")
        .expect("chain");
    let dz = c2.transform.translation() - c.transform.translation();
    assert!(
        (dz.z - 0.1).abs() < 1e-12 && dz.x.abs() < 1e-12 && dz.y.abs() < 1e-12,
        "{dz:?}"
    );
    assert!(!c2
        .warnings
        .iter()
        .any(|w| w.message.contains("torso_lift_joint")));
}

/// urdf-rs, where it reads a file, gives the same joint origins (an independent
/// reader; it does not read Unitree B2/Go2).
#[test]
fn urdf_rs_cross_check() {
    for f in [
        "anymal_c.urdf",
        "anymal_d.urdf",
        "pr2.urdf",
        "tiago_pro.urdf",
        "turtlebot3_waffle.urdf",
        "unitree_h1.urdf",
        "unitree_g1_29dof.urdf",
        "husky_kinematics.urdf",
    ] {
        let Some(path) = testdata::urdf(f) else {
            continue;
        };
        let robot = urdf_rs::read_file(&path).unwrap_or_else(|e| panic!("{f}: {e}"));
        let l = load_file(&path, &LoadOptions::default()).expect("load");
        assert_eq!(robot.joints.len(), l.edges.len(), "{f}");
        for j in &robot.joints {
            let e = l
                .edges
                .iter()
                .find(|e| e.child == j.child.link)
                .unwrap_or_else(|| panic!("{f}: {}", j.name));
            assert_eq!(e.parent, j.parent.link);
            let o = &j.origin;
            let t = extrinsic_audit::Transform::from_rpy(
                [o.rpy[0], o.rpy[1], o.rpy[2]],
                [o.xyz[0], o.xyz[1], o.xyz[2]],
            )
            .expect("rpy");
            // Movable joints sit at 0, so the edge is the origin.
            let diff = (t.matrix4() - e.transform.matrix4()).abs().max();
            assert!(diff < 1e-15, "{f} joint {}: {diff:e}", j.name);
        }
    }
}
