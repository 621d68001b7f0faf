"""check / diff / survey: the CLI's JSON, and numbers from numpy and
pytransform3d on the shipped calibrations and fixtures."""

import glob
import json
import os
import shutil
import tomllib
import warnings

import numpy as np
import pytest
import pytransform3d.rotations as pr

import extrinsic_audit as ea
from conftest import CALIBRATIONS, FIXTURES, ROOT, cli_json

D = "calibrations/anymal-d.urdf"
KALIBR = "tests/fixtures/diff/anymal_d_kalibr.yaml"
FASTLIO = "tests/fixtures/diff/anymal_d_fastlio.yaml"


def expected():
    with open(os.path.join(FIXTURES, "diff", "expected.json")) as f:
        return json.load(f)


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ea.AuditWarning)
        return fn(*args, **kwargs)


def test_check_against_the_baseline_is_the_cli_json():
    want, code = cli_json("check", "calibrations/", "--baseline", "calibrations/baseline.json")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rep = ea.check("calibrations/", baseline="calibrations/baseline.json")
    assert rep.to_dict() == want
    assert rep.exit_code == code == 0 and rep.ok
    assert rep.files_checked == len(glob.glob(os.path.join(CALIBRATIONS, "*.toml"))) + 1
    # The four rigs printed with 4 decimals warn: a rotation off orthonormal.
    numeric = [w.message for w in caught if issubclass(w.category, ea.NumericWarning)]
    assert sorted(os.path.basename(w.file) for w in numeric) == [
        "geode-alpha-vlp16.toml", "geode-beta-os1-64.toml", "geode-gamma-avia.toml",
        "m3dgr-avia-d435i-imu.toml"]
    assert all(w.code == "non-orthonormal-rotation" and w.line == 23 for w in numeric)


def test_check_finds_drift_measured_as_numpy(tmp_path):
    rig = tmp_path / "rig.toml"
    shutil.copy(os.path.join(CALIBRATIONS, "fastlio-avia.toml"), rig)
    base = tmp_path / "baseline.json"
    first = quiet(ea.check, [str(rig)], write_baseline=str(base))
    assert first.ok and base.exists()
    with open(rig, "rb") as f:
        t = tomllib.load(f)["transform"]
    assert len(t) == 1 and "translation" in t[0], "the fixture gives one translation"
    old = np.array(t[0]["translation"], dtype=float)
    new = old + np.array([0.003, -0.004, 0.0])  # 5 mm
    text = rig.read_text()
    line = next(ln for ln in text.splitlines() if ln.startswith("translation = ["))
    assert text.count(line) == 1
    rig.write_text(text.replace(line, "translation = [%r, %r, %r]" % tuple(float(v) for v in new)))
    rep = quiet(ea.check, [str(rig)], baseline=str(base), max_translation_drift=0.001)
    assert not rep.ok and rep.exit_code == 1
    drift = [f for f in rep.findings if f["code"] == "drift"]
    # The finding points at the line where the moved numbers are written
    # (issue 33), not at the [[transform]] header.
    at = text.splitlines().index(line) + 1
    assert drift and all(f["severity"] == "error" and f["line"] == at for f in drift)
    moved = "moved %.3f mm" % (1e3 * np.linalg.norm(new - old))
    assert moved == "moved 5.000 mm" and all(moved in f["message"] for f in drift)
    # Within a looser tolerance the same change passes.
    assert quiet(ea.check, [str(rig)], baseline=str(base), max_translation_drift=0.01).ok


def test_diff_is_the_cli_json_and_numpy():
    x = expected()["urdf_vs_kalibr"]
    args = ["diff", D, KALIBR, "--from", "imu_link", "--to", "lidar",
            "--rename", "anymal_d_kalibr.yaml:imu=imu_link"]
    want, code = cli_json(*args)
    rep = ea.diff(D, KALIBR, "imu_link", "lidar", renames=["anymal_d_kalibr.yaml:imu=imu_link"])
    assert rep.to_dict() == want
    assert code == 0 and not rep.exceeded
    c = rep["chain"]
    assert c["translation_change_mm"] == pytest.approx(x["chain"]["translation_change_mm"],
                                                       abs=1e-9)
    assert c["rotation_change_deg"] == pytest.approx(x["chain"]["rotation_change_deg"], abs=1e-9)


def test_diff_of_whole_files_is_the_cli_json_and_pytransform3d():
    # tests/fixtures/diff/gen_whole.py: the edges' changes by pytransform3d.
    fx = os.path.join(ROOT, "tests", "fixtures", "diff")
    with open(os.path.join(fx, "whole_expected.json")) as f:
        x = json.load(f)["old_vs_new"]
    old, new = os.path.join(fx, "whole_old.urdf"), os.path.join(fx, "whole_new.urdf")
    want, code = cli_json("diff", old, new)
    rep = ea.diff(old, new)
    assert rep.to_dict() == want
    assert code == 1 and rep.exceeded
    assert rep.frm is None and rep.to is None and rep["chain"] is None
    assert "None" not in repr(rep) and "whole files" in repr(rep)
    got = {f"{e['parent']} -> {e['child']}": e for e in rep["edges"]}
    for edge, v in x.items():
        assert got[edge]["translation_change_mm"] == pytest.approx(v["translation_change_mm"],
                                                                   abs=1e-9)
        assert got[edge]["rotation_change_deg"] == pytest.approx(v["rotation_change_deg"],
                                                                 abs=1e-9)


def test_diff_beyond_the_tolerance():
    x = expected()["urdf_vs_fastlio"]
    rep = ea.diff(D, FASTLIO, "imu_link", "lidar", renames=[(FASTLIO.split("/")[-1], "imu",
                                                             "imu_link")])
    assert rep.exceeded  # 2.2 mm and 0.2 deg exceed 1 mm, 0.05 deg
    assert rep["chain"]["translation_change_mm"] == pytest.approx(
        x["chain"]["translation_change_mm"], abs=1e-9)
    loose = ea.diff(D, FASTLIO, "imu_link", "lidar", renames={"imu": "imu_link"},
                    tolerance=(5.0, 1.0))
    assert not loose.exceeded


def toml_pose(path):
    """The rig's from -> to pose, composed with numpy from its [[transform]]
    tables (translation + rpy, or matrix4), when it is one edge."""
    with open(path, "rb") as f:
        d = tomllib.load(f)
    rig = d["rig"]
    edges = d.get("transform", [])
    if len(edges) != 1 or (edges[0]["parent"], edges[0]["child"]) != (rig["from"], rig["to"]):
        return None
    e = edges[0]
    if e.get("unit", "m") != "m":
        return None
    m = np.eye(4)
    if "matrix4" in e:
        m = np.array(e["matrix4"], dtype=float)
        u, _, vt = np.linalg.svd(m[:3, :3])  # projected as the reader does
        m[:3, :3] = u @ vt
    elif "rotation_matrix" in e and "translation" in e:
        u, _, vt = np.linalg.svd(np.array(e["rotation_matrix"], dtype=float))
        m[:3, :3] = u @ vt
        m[:3, 3] = e["translation"]
    elif "rpy" in e and "translation" in e:
        m[:3, :3] = pr.matrix_from_euler(e["rpy"], 0, 1, 2, extrinsic=True)
        m[:3, 3] = e["translation"]
    else:
        return None
    return rig["id"], m


def test_survey_is_the_cli_json_and_numpy():
    want, _ = cli_json("survey", "calibrations/")
    rep = quiet(ea.survey, "calibrations/")
    assert rep.to_dict() == want
    rows = {r["id"]: r for r in rep.rigs}
    checked = 0
    for path in sorted(glob.glob(os.path.join(ROOT, "calibrations", "*.toml"))):
        got = toml_pose(path)
        if got is None or got[0] not in rows:
            continue
        rid, m = got
        assert rows[rid]["lever_arm_m"] == pytest.approx(np.linalg.norm(m[:3, 3]), abs=1e-12)
        angle = np.degrees(pr.axis_angle_from_matrix(m[:3, :3])[3])
        assert rows[rid]["angle_deg"] == pytest.approx(angle, abs=1e-6)
        checked += 1
    assert checked >= 15, checked  # the one-edge rigs in m


def test_survey_sort_and_all():
    everything = quiet(ea.survey, "calibrations/", all=True, sort="lever-arm")
    want, _ = cli_json("survey", "calibrations/", "--all", "--sort", "lever-arm")
    assert everything.to_dict() == want
    assert len(everything.rigs) > len(quiet(ea.survey, "calibrations/").rigs)
    with pytest.raises(ea.UsageError):
        ea.survey("calibrations/", sort="no-such-column")
