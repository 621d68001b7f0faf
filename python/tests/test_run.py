"""The run reader (`ea.run`): one result per scan whose to_dict() is the
CLI's JSON line (`audit run --jsonl`), the summary the CLI's `--format
json`, on the run fixtures; the eigenvalues against a floor's closed form;
the GIL released while a scan is read; usage errors as exceptions. And the
load options that mirror the CLI's flags (sigma, URDF version, file-size
cap, the external xacro program, bag topics), each against the CLI or an
independent computation."""

import json
import os
import stat
import subprocess

import numpy as np
import pytest
import pytransform3d.rotations as pr

import extrinsic_audit as ea
from conftest import ANYMAL_C_LIDAR, FIXTURES, ROOT, audit_command, cli_json
from test_gil import counted

RUN = os.path.join("tests", "fixtures", "run")
KITTI = os.path.join(RUN, "kitti_seq")


def cli_run(tmp_path, *args):
    """`audit run ARGS --jsonl FILE --format json`: (the lines, the summary)."""
    lines = tmp_path / "scans.jsonl"
    p = subprocess.run([audit_command(), "run", *args, "--jsonl", str(lines), "--format", "json"],
                       cwd=ROOT, capture_output=True, text=True, check=False)
    assert p.returncode == 0, p.stderr
    return [json.loads(s) for s in lines.read_text().splitlines()], json.loads(p.stdout)


CASES = [
    ([os.path.join(RUN, "run.mcap")], [], {}),
    ([os.path.join(RUN, "pcd_seq")], ["--every", "2", "--lidar-frame", "lidar"],
     {"every": 2, "lidar_frame": "lidar"}),
    ([KITTI], ["--pairs", "--poses", os.path.join(KITTI, "poses.txt"), "--poses-format", "kitti",
               "--calib", os.path.join(KITTI, "calib.txt"), "--start", "1", "--voxel", "0.2"],
     {"pairs": True, "poses": os.path.join(KITTI, "poses.txt"), "poses_format": "kitti",
      "calib": os.path.join(KITTI, "calib.txt"), "start": 1, "voxel": 0.2}),
]


@pytest.mark.parametrize("paths, flags, kw", CASES, ids=["mcap", "pcd-every", "kitti-pairs"])
def test_every_result_is_the_cli_json_line_and_the_summary_its_json(tmp_path, paths, flags, kw):
    lines, summary = cli_run(tmp_path, *paths, *flags)
    reader = ea.run(paths, **kw)
    assert reader.pairs == bool(kw.get("pairs"))
    got = list(reader)
    assert [r.to_dict() for r in got] == lines
    assert len(got) > 1
    assert reader.frames == [f["name"] for f in summary["frames"]]
    report = reader.finish()
    assert report.to_dict() == summary
    assert report.read == summary["read"] and report.analysed == summary["analysed"]


def floor_sequence(root, scans=6, n=81, step=0.05):
    """A KITTI sequence whose every scan is the floor z = -1, a square of
    n x n points: little-endian float32 x, y, z, intensity."""
    velodyne = root / "velodyne"
    velodyne.mkdir()
    g = -2.0 + step * np.arange(n, dtype=np.float32)
    x, y = np.meshgrid(g, g)
    rows = np.column_stack([x.ravel(), y.ravel(), -np.ones(n * n), np.zeros(n * n)])
    for k in range(scans):
        rows.astype("<f4").tofile(velodyne / f"{k:06d}.bin")
    return root


def test_a_floor_gives_the_closed_form_in_every_scan(tmp_path):
    # About the centroid a plane moves its points along its normal only under
    # z, roll and pitch, and then wholly so (eigenvalue 1 of H against the
    # point-displacement metric M); x, y and yaw move none along it (0).
    seq = floor_sequence(tmp_path)
    reader = ea.run([seq], radius=0.2)
    assert reader.frames == ["scan"]
    results = list(reader)
    assert [r.index for r in results] == list(range(6))
    for r in results:
        assert r.skipped is None
        np.testing.assert_allclose(r.eigenvalues("scan"), [0, 0, 0, 1, 1, 1], atol=1e-9)
        assert r.family("scan", "point_displacement")["footprint"] == \
            [False, False, True, True, True, False]
    assert reader.finish().analysed == 6


def test_a_partial_read_then_finish_reads_the_rest_and_a_window(tmp_path):
    seq = floor_sequence(tmp_path)
    reader = ea.run([seq], radius=0.2, start=2, end=5)
    first = next(reader)
    assert first.index == 2
    report = reader.finish()
    assert (report.read, report.analysed) == (3, 3)
    with pytest.raises(ea.UsageError):
        reader.finish()
    # A reader dropped half-way stops its work (no hang, nothing left over).
    reader = ea.run([seq], radius=0.2)
    next(reader)
    del reader


def test_reading_scans_releases_the_gil(tmp_path):
    # Raw scans of 150,000 points each, normals estimated without a grid:
    # the work the counter thread must be able to run through.
    rng = np.random.default_rng(1)
    velodyne = tmp_path / "velodyne"
    velodyne.mkdir()
    for k in range(3):
        xy = rng.uniform(-20, 20, (150_000, 2))
        rows = np.column_stack([xy, 0.01 * rng.standard_normal(150_000), np.zeros(150_000)])
        rows.astype("<f4").tofile(velodyne / f"{k:06d}.bin")
    inside, results = counted(lambda: list(ea.run([tmp_path], voxel=0, radius=0.6)))
    assert len(results) == 3 and all(r.skipped is None for r in results)
    assert inside > 10_000, inside
    held, _ = counted(lambda: sum(range(40_000_000)))
    assert held < inside / 10, (held, inside)


def test_run_usage_errors():
    with pytest.raises(ea.UsageError, match="topic"):
        ea.run([os.path.join(RUN, "pcd_seq")], topic="/points")
    with pytest.raises(ea.UsageError, match="every"):
        ea.run([os.path.join(RUN, "pcd_seq")], every=0)
    with pytest.raises(ea.UsageError, match="tau"):
        ea.run([os.path.join(RUN, "pcd_seq")], tau=-1)
    with pytest.raises(ea.UsageError, match="poses_format"):
        ea.run([KITTI], pairs=True, poses=os.path.join(KITTI, "poses.txt"), poses_format="x")
    with pytest.raises(ea.UsageError, match="start"):
        ea.run([KITTI], start=1.5)
    with pytest.raises(ea.UsageError):
        ea.run([])


# --- load(): the rest of the CLI's reading flags -----------------------------

def test_sigma_is_the_cli_report_with_sigma():
    want, _ = cli_json(ANYMAL_C_LIDAR, "--from", "base", "--to", "lidar", "--sigma-t", "0.002",
                       "--sigma-r", "0.1")
    plain, _ = cli_json(ANYMAL_C_LIDAR, "--from", "base", "--to", "lidar")
    assert want != plain
    rep = ea.load(ANYMAL_C_LIDAR, sigma_t=0.002, sigma_r=0.1).report("base", "lidar")
    assert rep.to_dict() == want
    with pytest.raises(ea.UsageError, match="sigma_r"):
        ea.load(ANYMAL_C_LIDAR, sigma_r=11).report("base", "lidar")


QUAT_URDF = """<robot name="q"{version}>
  <link name="base"/><link name="lidar"/>
  <joint name="j" type="fixed"><parent link="base"/><child link="lidar"/>
    <origin xyz="1 0 0" quat_xyzw="0 0 0.3826834323650898 0.9238795325112867"/></joint>
</robot>
"""


def test_urdf_version_1_1_applies_quat_xyzw(tmp_path):
    f = tmp_path / "q.urdf"
    f.write_text(QUAT_URDF.format(version=""))
    # A 1.0 file: ROS ignores quat_xyzw (a named warning), so no rotation.
    with pytest.warns(ea.AuditWarning):
        r10 = ea.load(f).transform("base", "lidar")
    np.testing.assert_allclose(r10[:3, :3], np.eye(3), atol=1e-15)
    r11 = ea.load(f, urdf_version="1.1").transform("base", "lidar")
    want = pr.matrix_from_quaternion([0.9238795325112867, 0, 0, 0.3826834323650898])
    np.testing.assert_allclose(r11[:3, :3], want, atol=1e-12)
    np.testing.assert_allclose(r11[:3, 3], [1, 0, 0], atol=0)
    with pytest.raises(ea.UsageError, match="urdf_version"):
        ea.load(f, urdf_version="2.0")


def test_max_file_size_refuses_a_larger_file():
    size = os.path.getsize(ANYMAL_C_LIDAR)
    with pytest.raises(ea.InputError) as e:
        ea.load(ANYMAL_C_LIDAR, max_file_size=size - 1)
    assert e.value.code == "limit"
    assert ea.load(ANYMAL_C_LIDAR, max_file_size=size).frames()


def test_the_external_xacro_program_is_run_from_xacro_path(tmp_path):
    # A stand-in `xacro` on a folder of its own: it prints a fixed URDF.
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    prog = bin_dir / "xacro"
    prog.write_text("#!/bin/sh\ncat <<'EOF'\n<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/>"
                    "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/>"
                    "<origin xyz=\"0 0 3\"/></joint></robot>\nEOF\n")
    prog.chmod(prog.stat().st_mode | stat.S_IXUSR)
    src = tmp_path / "r.urdf.xacro"
    src.write_text('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"/>\n')
    robot = ea.load(src, xacro="external", xacro_path=[bin_dir])
    assert robot.frames() == ["a", "b"]
    np.testing.assert_array_equal(robot.transform("a", "b")[:3, 3], [0, 0, 3])
    with pytest.raises(ea.AuditError):
        ea.load(src, xacro="external", xacro_path=[tmp_path / "empty"])
    with pytest.raises(ea.UsageError, match="xacro"):
        ea.load(src, xacro="python")


def test_bag_topics_choose_what_is_read():
    bag = os.path.join(FIXTURES, "bags", "unrelated.mcap")
    assert "camera" not in ea.load(bag).frames()
    assert "camera" in ea.load(bag, tf_topics="/tf").frames()
    with pytest.raises(ea.AuditError, match="/no_such_topic"):
        ea.load(bag, tf_static_topics=["/no_such_topic"], description_topics="/none")
