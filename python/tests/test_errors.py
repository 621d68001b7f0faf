"""Errors are AuditError subclasses carrying code, file, line and message;
warnings go through the warnings module, one category per code family."""

import os
import warnings

import pytest

import extrinsic_audit as ea
from conftest import ANYMAL_C_LIDAR, FIXTURES, cli_json


def test_a_parse_error_names_file_and_line(tmp_path):
    bad = tmp_path / "bad.urdf"
    bad.write_text('<robot name="r">\n  <link name="a"/>\n  <joint name="j" type="fixed">\n'
                   '    <parent link="a"/>\n    <child link="b"/>\n'
                   '    <origin xyz="0 0 nope"/>\n  </joint>\n  <link name="b"/>\n</robot>\n')
    with pytest.raises(ea.InputError) as e:
        ea.load(str(bad))
    err = e.value
    assert isinstance(err, ea.AuditError)
    assert err.code in ("parse", "invalid")
    assert err.file == str(bad) and err.line == 6
    assert "nope" in err.message
    assert str(err).startswith(f"error[{err.code}]: {bad}:6")


def test_a_missing_file_is_io():
    with pytest.raises(ea.InputError) as e:
        ea.load("no/such/file.urdf")
    assert e.value.code == "io" and e.value.file == "no/such/file.urdf"


def test_an_unknown_frame_is_a_frame_error_and_a_lookup_error():
    robot = ea.load(ANYMAL_C_LIDAR)
    with pytest.raises(LookupError) as e:
        robot.transform("base", "lidr")
    assert isinstance(e.value, ea.FrameError) and e.value.code == "frames"
    assert "lidr" in e.value.message and "'lidar'" in e.value.message


def test_usage_errors_are_value_errors():
    with pytest.raises(ValueError):
        ea.load(ANYMAL_C_LIDAR, renames=["no-equals-sign"])
    with pytest.raises(ea.UsageError):
        ea.load(ANYMAL_C_LIDAR).report("base", "lidar", kappa=0.1)
    with pytest.raises(ea.UsageError) as e:
        ea.check("calibrations/", allow=["no-such-code"])
    assert "no-such-code" in e.value.message


def test_warnings_carry_code_file_and_line():
    path = "calibrations/geode-alpha-vlp16.toml"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = ea.load(path)
    [w] = caught
    assert w.category is ea.NumericWarning and issubclass(w.category, UserWarning)
    m = w.message
    assert (m.code, m.file, m.line, m.column) == ("non-orthonormal-rotation", path, 23, 1)
    # The same warning the CLI puts in its JSON.
    want, _ = cli_json(path, "--from", "IMU", "--to", "LiDAR")
    assert want["warnings"] == [str(m)]
    assert robot.report("IMU", "LiDAR").warnings == want["warnings"]


def test_a_joint_at_default_warns_on_the_chain_and_filters_make_it_an_error():
    path = os.path.join(FIXTURES, "urdf", "husky_kinematics.urdf")
    robot = ea.load(path)
    joint = robot.joints()[0]
    child = next(f for f in robot.frames() if "wheel" in f)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot.transform("base_link", child)
    assert [w.category for w in caught] == [ea.JointWarning]
    assert caught[0].message.code == "joint-at-default"
    assert caught[0].filename == __file__  # attributed to the caller's line
    with warnings.catch_warnings():
        warnings.simplefilter("error", ea.JointWarning)
        with pytest.raises(ea.JointWarning):
            robot.transform("base_link", child)
    # Set, it is silent.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ea.load(path, joints={j: 0.0 for j in robot.joints()}).transform("base_link", child)
    assert joint


def test_millimetres_in_a_metre_field_is_a_convention_warning(tmp_path):
    f = tmp_path / "fast_lio.yaml"
    f.write_text("mapping:\n  extrinsic_T: [41.65, 23.26, -28.4]\n"
                 "  extrinsic_R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n")
    with pytest.warns(ea.ConventionWarning) as rec:
        ea.load(str(f))
    assert rec[0].message.code == "millimetres-in-metre-field"
    assert rec[0].message.file == str(f)
