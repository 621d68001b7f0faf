//! Which format each fixture is detected as: one table, every format of the
//! registry at least once, detected as `formats::load_file` detects it (no
//! `--input-format`). A format that an extension selects and that content
//! also identifies (magic bytes, a sniffer) is detected both ways: the file as
//! named, and the same bytes under a name without an extension.
//!
//! Fixtures are the project's own where it has one; a format whose only
//! fixtures are third-party files reads them in place from the test-data
//! folder (`common::testdata`), and its row is skipped, saying so, where the
//! folder does not have them.

use extrinsic_audit::internals::formats::{all_formats, detect_file, FORMATS};
use extrinsic_audit::LoadOptions;
use std::path::{Path, PathBuf};

/// Where a fixture lives.
#[derive(Clone, Copy)]
enum At {
    /// In this repository (relative to its root).
    Own(&'static str),
    /// In the test-data folder (`<owner>__<repo>/<path in the repo>`).
    Shared(&'static str),
}

/// How a row is detected.
#[derive(Clone, Copy, PartialEq)]
enum By {
    /// As the file is named.
    Name,
    /// The same bytes under a name without an extension: by content alone.
    Content,
}

use At::{Own, Shared};
use By::{Content, Name};

const TABLE: &[(At, &str, By)] = &[
    (Own("tests/fixtures/bags/robot.urdf"), "urdf", Name),
    (Own("tests/fixtures/bags/robot.urdf"), "urdf", Content),
    (Own("tests/fixtures/xacro/own/lidar_rig/urdf/semantics.urdf.xacro"), "xacro", Name),
    (Own("tests/fixtures/formats/ros1_static_tf.launch"), "launch-xml", Name),
    (Own("tests/fixtures/formats/ros1_static_tf.launch"), "launch-xml", Content),
    (Own("tests/fixtures/formats/ros2_static_tf.launch.xml"), "launch-xml", Name),
    (Shared("Livox-SDK__LIO-Livox/launch/mid360.launch"), "lio-livox-launch", Name),
    (Shared("Livox-SDK__LIO-Livox/launch/mid360.launch"), "lio-livox-launch", Content),
    (Own("tests/fixtures/formats/calib/lio-livox-launch/horizon.launch"), "lio-livox-launch", Name),
    (Own("tests/fixtures/formats/calib/roslaunch-eval/eval_static_tf.launch"), "launch-xml", Name),
    (Own("tests/fixtures/formats/ros2_static_tf.launch.py"), "launch-py", Name),
    (Own("tests/fixtures/formats/ros2_static_tf.launch.py"), "launch-py", Content),
    (Own("tests/fixtures/extrinsics/static_tf_script.sh"), "static-tf-commands", Name),
    (Own("tests/fixtures/extrinsics/static_tf_script.sh"), "static-tf-commands", Content),
    (Own("tests/fixtures/formats/ros2_static_tf_commands.txt"), "static-tf-commands", Name),
    (Own("tests/fixtures/formats/ros1_tf_static_echo.yaml"), "tf-static-echo", Name),
    (Own("tests/fixtures/formats/ros2_tf_static_echo.yaml"), "tf-static-echo", Content),
    (Own("tests/fixtures/formats/ros2_static_tf.launch.yaml"), "launch-yaml", Name),
    (Own("tests/fixtures/formats/ros2_static_tf.launch.yaml"), "launch-yaml", Content),
    (Own("tests/fixtures/formats/fastlio_avia.yaml"), "fast-lio", Name),
    (Own("tests/fixtures/formats/calib/fast-livo/fast_livo_avia.yaml"), "fast-livo", Name),
    (Own("tests/fixtures/formats/calib/fast-livo/fast_livo2_avia.yaml"), "fast-livo", Content),
    (Own("tests/fixtures/formats/calib/orb-slam3/euroc_stereo_inertial_v1.yaml"), "orb-slam3", Name),
    (Own("tests/fixtures/formats/calib/orb-slam3/tumvi_stereo_inertial_v04.yaml"), "orb-slam3", Content),
    (Own("tests/fixtures/formats/calib/autoware-calibration/sensor_kit_calibration.yaml"), "autoware-calibration", Name),
    (Own("tests/fixtures/formats/calib/autoware-calibration/sensors_calibration.yaml"), "autoware-calibration", Content),
    (Own("tests/fixtures/formats/calib/euroc-sensor/euroc_cam0_sensor.yaml"), "euroc-sensor", Name),
    (Own("tests/fixtures/formats/calib/euroc-sensor/kimera_right_camera_params.yaml"), "euroc-sensor", Content),
    (Own("tests/fixtures/formats/calib/okvis/okvis_euroc_config.yaml"), "okvis", Name),
    (Own("tests/fixtures/formats/calib/okvis/okvis_euroc_config.yaml"), "okvis", Content),
    (Own("tests/fixtures/formats/calib/r3live/r3live_config.yaml"), "r3live", Name),
    (Own("tests/fixtures/formats/calib/r3live/r3live_config_commented_t.yaml"), "r3live", Content),
    (Own("tests/fixtures/formats/calib/apollo-extrinsics/velodyne64_novatel_extrinsics.yaml"), "apollo-extrinsics", Name),
    (Own("tests/fixtures/formats/calib/apollo-extrinsics/front_camera_extrinsics.yaml"), "apollo-extrinsics", Content),
    (Own("tests/fixtures/formats/calib/basalt-calib/euroc_ds_calib.json"), "basalt-calib", Name),
    (Own("tests/fixtures/formats/calib/basalt-calib/euroc_ds_calib.json"), "basalt-calib", Content),
    (Own("tests/fixtures/formats/calib/glim-sensors/config_sensors.json"), "glim-sensors", Name),
    (Own("tests/fixtures/formats/calib/glim-sensors/config_sensors_newer_college.json"), "glim-sensors", Content),
    (Own("tests/fixtures/formats/calib/opencalib/top_center_lidar-to-center_camera-extrinsic.json"), "opencalib", Name),
    (Own("tests/fixtures/formats/calib/opencalib/gnss-to-top_center_lidar-extrinsic.json"), "opencalib", Content),
    (Own("tests/fixtures/formats/calib/livox-driver2/synthetic_two_lidars.json"), "livox-driver2", Name),
    (Own("tests/fixtures/formats/calib/livox-driver2/mid360_config.json"), "livox-driver2", Content),
    (Own("tests/fixtures/formats/calib/matrix4-text/euroc_cam0_in_body.txt"), "matrix4-text", Name),
    (Own("tests/fixtures/formats/calib/matrix4-text/horizon_commas.txt"), "matrix4-text", Content),
    (Shared("TixiaoShan__LIO-SAM/config/params.yaml"), "lio-sam", Name),
    (Own("tests/fixtures/extrinsics/iglio_ncd.yaml"), "ig-lio", Name),
    (Shared("vectr-ucla__direct_lidar_inertial_odometry/cfg/dlio.yaml"), "dlio", Name),
    (Own("tests/fixtures/extrinsics/vins_mono_euroc.yaml"), "vins-mono", Name),
    (Own("tests/fixtures/formats/slict_mcdviral_hhs.yaml"), "slict", Name),
    (Own("tests/fixtures/formats/cocolic_viral_lidar.yaml"), "coco-lic", Name),
    (Own("tests/fixtures/formats/fusionportable_ouster00.yaml"), "quaternion-yaml", Name),
    (
        Shared("leggedrobotics__grand_tour_box/box_calibration/box_calibration/calibration/tf/calibration_latest.yaml"),
        "tf-tree-yaml",
        Name,
    ),
    (Own("tests/fixtures/extrinsics/kalibr_openvins_euroc_imucam_chain.yaml"), "matrix-yaml", Name),
    (Own("tests/fixtures/extrinsics/geode_style_ambiguous.yaml"), "matrix-yaml", Content),
    (Own("tests/fixtures/extrinsics/nuscenes/calibrated_sensor.json"), "nuscenes-json", Name),
    (Own("tests/fixtures/extrinsics/ouster_extrinsics_example.json"), "ouster-extrinsics", Name),
    (Own("tests/fixtures/extrinsics/av2/av2_test_log_egovehicle_SE3_sensor.json"), "av2-json", Name),
    (Shared("ouster-lidar__ouster-sdk/tests/pcaps/OS-0-128-U1_v2.3.0_1024x10.json"), "ouster-json", Name),
    (Own("tests/fixtures/bags/description.mcap"), "bag", Name),
    (Own("tests/fixtures/bags/description.mcap"), "bag", Content),
    (Own("tests/fixtures/bags/description.bag"), "bag", Name),
    (Own("tests/fixtures/bags/description.bag"), "bag", Content),
    (Own("tests/fixtures/bags/description_db3/description_db3.db3"), "bag", Name),
    (Own("tests/fixtures/bags/description_db3/description_db3.db3"), "bag", Content),
    // rosbag2 folders (sqlite3 and MCAP storage): by their metadata.yaml.
    (Own("tests/fixtures/bags/description_db3"), "bag", Name),
    (Own("tests/fixtures/bags/updates_mcapdir"), "bag", Name),
    (Own("tests/fixtures/extrinsics/av2/av2_test_log_egovehicle_SE3_sensor.uncompressed.feather"), "av2-feather", Name),
    (Own("tests/fixtures/extrinsics/av2/av2_test_log_egovehicle_SE3_sensor.uncompressed.feather"), "av2-feather", Content),
    (Shared("gadomski__las-rs/tests/data/autzen.las"), "point-cloud", Name),
    (Shared("gadomski__las-rs/tests/data/autzen.laz"), "point-cloud", Content),
    (Own("tests/fixtures/detector/tunnel_small_ascii.ply"), "point-cloud", Name),
    (Own("tests/fixtures/detector/tunnel_small_le.ply"), "point-cloud", Content),
    (Own("tests/fixtures/detector/tunnel_small_ascii.pcd"), "point-cloud", Name),
    (Own("tests/fixtures/detector/tunnel_small_ascii.pcd"), "point-cloud", Content),
    (Own("tests/fixtures/detector/tunnel_small_bin.pcd"), "point-cloud", Content),
    (Own("tests/fixtures/detector/tunnel_small.csv"), "point-cloud", Name),
    (Own("tests/fixtures/formats/calib_imu_to_velo.txt"), "kitti-calib", Name),
    (Own("tests/fixtures/extrinsics/kitti_object_000000.txt"), "kitti-object", Name),
    (Shared("SJTU-ViSYS__M2DGR/calibration_results.txt"), "m2dgr-txt", Name),
    (Own("calibrations/fastlio-avia.toml"), "rig-toml", Name),
];

/// Formats only an extension selects: no content names them (a `.xacro`
/// without its name reads as the URDF it looks like; a TOML is no other
/// format's text).
const NAME_ONLY: &[&str] = &["xacro", "rig-toml"];

fn path_of(at: At) -> Option<PathBuf> {
    match at {
        Own(p) => Some(Path::new(env!("CARGO_MANIFEST_DIR")).join(p)),
        Shared(p) => crate::common::testdata::file(p),
    }
}

fn name_of(at: At) -> &'static str {
    match at {
        Own(p) | Shared(p) => p,
    }
}

#[test]
fn every_fixture_is_detected_as_its_format() {
    let dir = tempfile::tempdir().unwrap();
    let mut skipped = 0;
    for (i, &(at, id, by)) in TABLE.iter().enumerate() {
        let Some(file) = path_of(at) else {
            skipped += 1;
            continue;
        };
        let read = match by {
            Name => file,
            Content => {
                assert!(
                    file.is_file(),
                    "{}: a folder is read by its name",
                    name_of(at)
                );
                let copy = dir.path().join(format!("input{i}"));
                std::fs::copy(&file, &copy).unwrap();
                copy
            }
        };
        let found = detect_file(&read, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{} ({:?}): {e}", name_of(at), by == Content));
        let how = if by == Content {
            "by content"
        } else {
            "by name"
        };
        assert_eq!(found.name(), id, "{} {how}", name_of(at));
    }
    if skipped > 0 {
        eprintln!("{skipped} rows skipped: their third-party fixtures are absent");
    }
}

#[test]
fn the_table_covers_every_format_both_ways() {
    for (f, _) in all_formats() {
        let rows: Vec<_> = TABLE.iter().filter(|(_, id, _)| *id == f.name()).collect();
        assert!(!rows.is_empty(), "{}: no fixture in the table", f.name());
        let named = rows.iter().any(|(at, _, by)| {
            let ext = name_of(*at).rsplit('/').next().unwrap_or("");
            *by == Name
                && FORMATS
                    .iter()
                    .filter(|s| s.id == f.name())
                    .flat_map(|s| s.extensions.iter())
                    .any(|e| ext.ends_with(&format!(".{e}")))
        });
        if named && !NAME_ONLY.contains(&f.name()) {
            assert!(
                rows.iter().any(|(_, _, by)| *by == Content),
                "{}: detected by its extension in the table, not by its content",
                f.name()
            );
        }
    }
}

/// `--input-format NAME` reads each fixture with the format it names, bags
/// and Arrow files included; a LAS/LAZ scan is refused with the command that
/// reads it. A bag stays a bag under a text format's name (a text reader
/// cannot read it, and a bag is never read whole).
#[test]
fn input_format_names_every_format() {
    use extrinsic_audit::internals::formats::load_file;
    use extrinsic_audit::Format;
    for &(at, id, by) in TABLE {
        let Some(file) = path_of(at).filter(|_| by == Name) else {
            continue;
        };
        let mut opts = LoadOptions::default();
        opts.format = Some(Format::from_name(id).unwrap());
        match load_file(&file, &opts) {
            Ok(l) => assert!(!l.edges.is_empty(), "{id}: {}", name_of(at)),
            // No direction can be traced: refused without --assume, naming it.
            Err(e) if id == "matrix4-text" => assert!(e.message.contains("--assume"), "{e}"),
            Err(e) if id == "point-cloud" => {
                assert!(e.message.contains("point cloud"), "{e}");
                assert!(
                    e.message
                        .contains("audit degeneracy FILE --estimate-normals"),
                    "{e}"
                );
            }
            Err(e) => panic!("--input-format {id} {}: {e}", name_of(at)),
        }
    }
    let bag = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/bags/description.mcap");
    let mut opts = LoadOptions::default();
    opts.format = Some(Format::from_name("fast-lio").unwrap());
    let l = load_file(&bag, &opts).expect("a bag under a text format's name");
    assert!(l.edges.iter().any(|e| e.provenance.format == "bag"));
}
