"""load / frames / transform / report against pytransform3d and numpy."""

import itertools
import json
import os
import warnings

import numpy as np
import pytest
import pytransform3d.rotations as pr
import pytransform3d.transformations as pt
from pytransform3d.urdf import UrdfTransformManager

import extrinsic_audit as ea
from conftest import (ANYMAL_C_LIDAR, FIXTURES, cli_json, real, testdata, urdf_links,
                      urdf_pose)


def utm(path, joints=None):
    tm = UrdfTransformManager()
    with open(path, encoding="utf-8") as f:
        tm.load_urdf(f.read())
    for name, value in (joints or {}).items():
        tm.set_joint(name, value)
    return tm


def test_frames_are_the_urdf_links():
    robot = ea.load(ANYMAL_C_LIDAR)
    assert robot.frames() == urdf_links(ANYMAL_C_LIDAR)
    assert robot.joints() == []


def test_transform_matches_pytransform3d_on_every_pair():
    robot = ea.load([ANYMAL_C_LIDAR])
    tm = utm(ANYMAL_C_LIDAR)
    for a, b in itertools.permutations(robot.frames(), 2):
        T = robot.transform(a, b)
        assert T.shape == (4, 4) and T.dtype == np.float64
        # pytransform3d: get_transform(B, A) maps B coordinates into A,
        # the pose of B in A.
        np.testing.assert_allclose(T, tm.get_transform(b, a), rtol=0, atol=1e-15)
        R, t = robot.transform_parts(a, b)
        np.testing.assert_array_equal(R, T[:3, :3])
        np.testing.assert_array_equal(t, T[:3, 3])


def test_whole_anymal_c_with_joints_matches_pytransform3d():
    path = real("Gepetto__example-robot-data/robots/anymal_c_simple_description/urdf/anymal.urdf")
    joints = {}
    rng = np.random.default_rng(7)
    for name in ea.load(path).joints():
        joints[name] = float(rng.uniform(-0.4, 0.4))
    robot = ea.load(path, joints=joints)
    tm = utm(path, joints)
    frames = robot.frames()
    assert frames == urdf_links(path)
    for b in frames:
        np.testing.assert_allclose(robot.transform("base", b), tm.get_transform(b, "base"),
                                   rtol=0, atol=1e-12)


def test_renames_rename_the_frame():
    robot = ea.load(ANYMAL_C_LIDAR, renames={"lidar": "velodyne"})
    assert robot.frames() == ["base", "lidar_cage", "velodyne"]
    same = ea.load(ANYMAL_C_LIDAR, renames=["anymal_c_lidar.urdf:lidar=velodyne"])
    np.testing.assert_array_equal(same.transform("base", "velodyne"),
                                  ea.load(ANYMAL_C_LIDAR).transform("base", "lidar"))
    with pytest.raises(ea.AuditError):
        ea.load(ANYMAL_C_LIDAR, renames={"lidr": "velodyne"})  # a typo, not a no-op


def test_joint_values_move_the_chain_as_pytransform3d():
    path = os.path.join(FIXTURES, "urdf", "husky_kinematics.urdf")
    names = ea.load(path).joints()
    assert names
    joints = {n: 0.3 + 0.1 * i for i, n in enumerate(names)}
    robot = ea.load(path, joints=joints)
    tm = utm(path, joints)
    for a, b in itertools.permutations(robot.frames(), 2):
        np.testing.assert_allclose(robot.transform(a, b), tm.get_transform(b, a),
                                   rtol=0, atol=1e-12)


def test_xacro_args_and_package_paths_as_python_xacro():
    root = testdata.root()
    packages = [os.path.join(root, p) for p in
                ("ToyotaResearchInstitute__velodyne_simulator", "IntelRealSense__realsense-ros")]
    if not all(os.path.isdir(p) for p in packages):
        pytest.skip("test data not found: the velodyne and realsense packages (docs/test-data.md)")
    rig = os.path.join(FIXTURES, "xacro", "own", "lidar_rig", "urdf", "rig.urdf.xacro")
    args = {"prefix": "r1_", "with_camera": "false", "lidar_height_offset": "0.025"}
    names = ea.load(rig, xacro_args=args, package_paths=packages).joints()
    # Python xacro's edges are the joint origins: every movable joint at 0, said so.
    robot = ea.load(rig, xacro_args=args, package_paths=packages,
                    joints={n: 0.0 for n in names})
    with open(os.path.join(FIXTURES, "xacro", "expected", "own_lidar_rig_args.json")) as f:
        expected = json.load(f)["edges"]
    assert expected
    for e in expected:
        np.testing.assert_allclose(robot.transform(e["parent"], e["child"]),
                                   urdf_pose(e["xyz"], e["rpy"]), rtol=0, atol=1e-12)


def test_key_and_invert_as_numpy():
    with open(os.path.join(FIXTURES, "diff", "key_invert_expected.json")) as f:
        want = json.load(f)["geode_T_IMU_LiDAR"]
    path = os.path.join(FIXTURES, "formats", "geode_gamma_opencv.yaml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ea.NumericWarning)
        robot = ea.load(path, key="T_IMU_LiDAR")
        inverted = ea.load(path, key="T_IMU_LiDAR", invert=True)
    frm, to = robot.frame_pair()
    rep = robot.report(frm, to)
    assert rep.lever_arm_m == pytest.approx(want["lever_arm_m"], abs=1e-12)
    assert rep.angle_deg == pytest.approx(want["angle_deg"], abs=1e-9)
    assert rep.screw.translation_along_axis_m == pytest.approx(want["screw_translation_m"],
                                                                abs=1e-12)
    # --invert: the numbers are the other direction.
    np.testing.assert_allclose(inverted.transform(to, frm), robot.transform(frm, to), atol=1e-12)


def test_input_format_skips_detection():
    robot = ea.load(ANYMAL_C_LIDAR, input_format="urdf")
    assert robot.frames() == urdf_links(ANYMAL_C_LIDAR)
    with pytest.raises(ea.UsageError) as e:
        ea.load(ANYMAL_C_LIDAR, input_format="no-such-format")
    assert e.value.code == "usage"


def test_report_to_dict_is_the_cli_json():
    want, code = cli_json("tests/fixtures/urdf/anymal_c_lidar.urdf", "--from", "base",
                          "--to", "lidar")
    assert code == 0
    rep = ea.load("tests/fixtures/urdf/anymal_c_lidar.urdf").report("base", "lidar")
    assert rep.to_dict() == want
    # Options as the flags.
    want, _ = cli_json("tests/fixtures/urdf/anymal_c_lidar.urdf", "--from", "base", "--to",
                       "lidar", "--ell", "0.5", "--ell", "3", "--pitch-tol", "0.2",
                       "--kappa", "0.01", "--lambda", "0.004")
    rep = ea.load("tests/fixtures/urdf/anymal_c_lidar.urdf").report(
        "base", "lidar", ells=[0.5, 3], pitch_tol=0.2, kappa=0.01, lam=0.004)
    assert rep.to_dict() == want
    assert json.loads(rep.to_json()) == want


def test_report_numbers_as_numpy_and_pytransform3d():
    robot = ea.load(ANYMAL_C_LIDAR)
    rep = robot.report("base", "lidar", ells=[1.0])
    T = utm(ANYMAL_C_LIDAR).get_transform("lidar", "base")
    np.testing.assert_allclose(rep.matrix, T, atol=1e-15)
    assert rep.lever_arm_m == pytest.approx(np.linalg.norm(T[:3, 3]), abs=1e-15)
    axis_angle = pr.axis_angle_from_matrix(T[:3, :3])
    assert np.radians(rep.angle_deg) == pytest.approx(axis_angle[3], abs=1e-12)
    # The screw: h = e . t along the rotation axis, pitch h / theta.
    h = float(np.dot(axis_angle[:3], T[:3, 3]))
    assert rep.screw.translation_along_axis_m == pytest.approx(h, abs=1e-12)
    assert rep.screw.pitch_m_per_rad == pytest.approx(h / axis_angle[3], abs=1e-12)
    assert rep.screw.kind == "general"
    # Ad(T), twists [omega; v] in both: its singular values by numpy.
    sv = np.linalg.svd(pt.adjoint_from_transform(T), compute_uv=False)
    np.testing.assert_allclose(rep.adjoint_singular_values, sv, atol=1e-12)
    # The band at l = 1: [sigma_min^2, sigma_max^2] of Ad with t scaled by 1/l
    # (tests/fixtures/diff/expected.json has the same numbers).
    lo, hi = rep.bands[1.0]
    assert (lo, hi) == pytest.approx((sv[-1] ** 2, sv[0] ** 2), abs=1e-12)
    assert rep.invariant_families == ["point_displacement"]
    assert not rep.adapted_metric_exists


def test_frame_tree_is_the_cli_json():
    want, _ = cli_json("tests/fixtures/urdf/anymal_c_lidar.urdf", "--frames")
    got = ea.load("tests/fixtures/urdf/anymal_c_lidar.urdf").frame_tree().to_dict()
    assert got == want
