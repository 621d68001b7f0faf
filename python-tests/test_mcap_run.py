"""`audit run ... --format mcap --output F.mcap` read back by Foxglove's
`mcap` package (every message validated: foxglove_mcap.py), against the
same run's JSON lines (`--jsonl`) and summary (`--format json`), and the
transforms against the fixture generator's own (tests/fixtures/run/scenes.py).

    target/py-venv/bin/python -m unittest discover -s python-tests -p 'test_mcap_run.py' -v
"""
import json
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

import foxglove_mcap as fm
from test_mcap import audit_bin, counts, run

RUN = fm.ROOT / "tests" / "fixtures" / "run"
sys.path.insert(0, str(RUN))
import scenes  # noqa: E402  (the fixture generator's transforms)


def no_nulls(v):
    """A JSON line as the MCAP message carries it: null members left out."""
    if isinstance(v, dict):
        return {k: no_nulls(x) for k, x in v.items() if x is not None}
    if isinstance(v, list):
        return [no_nulls(x) for x in v]
    return v


def export_run(tmp, *args):
    """The MCAP file, the JSON lines and the JSON summary of one run."""
    out, lines = Path(tmp) / "run.mcap", Path(tmp) / "scans.jsonl"
    run("run", *args, "--jsonl", lines, "--format", "mcap", "--output", out)
    summary = json.loads(run("run", *args, "--format", "json").stdout)
    return fm.read(out), [json.loads(x) for x in lines.read_text().splitlines()], summary


def quat_matrix(q):
    x, y, z, w = q["x"], q["y"], q["z"], q["w"]
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


class RunTimeline(unittest.TestCase):
    """tests/fixtures/run/run.mcap: 8 scans at 10 Hz in frame `lidar`,
    /tf_static base_link -> lidar, imu_link, rear_axle, trailer_axle."""

    def test_one_message_per_scan_equal_to_its_json_line_at_its_stamp(self):
        with tempfile.TemporaryDirectory() as tmp:
            f, lines, summary = export_run(tmp, RUN / "run.mcap", "--all-frames")
        self.assertEqual(counts(f), {"/tf": 1, "/audit/run": 8})
        t = f["topics"]["/audit/run"]
        self.assertEqual((t["schema"], t["schema_encoding"], t["message_encoding"]),
                         ("extrinsic_audit.RunScan", "jsonschema", "json"))
        self.assertEqual(len(lines), 8)
        for msg, line, log_time in zip(t["messages"], lines, t["log_times"]):
            stamp = msg.pop("timestamp")
            # Every number is the JSON line's, to the last digit.
            self.assertEqual(msg, no_nulls(line))
            self.assertEqual(log_time, line["stamp_ns"])
            self.assertEqual(stamp, {"sec": line["stamp_ns"] // 10**9,
                                     "nsec": line["stamp_ns"] % 10**9})
        self.assertEqual(t["log_times"], sorted(t["log_times"]))
        self.assertEqual(t["log_times"][0], 1_700_000_000 * 10**9)
        frames = [fr["frame"] for fr in t["messages"][0]["frames"]]
        self.assertEqual(frames, [fr["name"] for fr in summary["frames"]])
        self.assertEqual(frames, ["scan", "base_link", "imu_link", "rear_axle", "trailer_axle"])
        # The tunnel: point displacement finds one degenerate direction in
        # the last three scans, the same count in every frame.
        pd = [[next(x for x in fr["families"] if x["family"] == "point_displacement")
               ["degenerate_count"] for fr in m["frames"]] for m in t["messages"]]
        self.assertEqual(pd, [[0] * 5] * 5 + [[1] * 5] * 3)
        meta = f["metadata"]["extrinsic-audit"]
        self.assertEqual((meta["report"], meta["unit"], meta["timeline_topic"], meta["log_time"]),
                         ("run", "scans", "/audit/run", "header.stamp"))
        self.assertEqual(json.loads(meta["summary"]), summary)

    def test_the_transforms_are_the_fixture_generators_at_the_first_scan(self):
        with tempfile.TemporaryDirectory() as tmp:
            f, _, _ = export_run(tmp, RUN / "run.mcap", "--all-frames")
        (tf,) = f["topics"]["/tf"]["messages"]
        self.assertEqual(f["topics"]["/tf"]["log_times"], [1_700_000_000 * 10**9])
        want = {"lidar": scenes.T_BASE_LIDAR, "imu_link": scenes.T_BASE_IMU,
                "rear_axle": scenes.T_BASE_REAR_AXLE, "trailer_axle": scenes.T_BASE_TRAILER_AXLE}
        got = {t["child_frame_id"]: t for t in tf["transforms"]}
        self.assertEqual(sorted(got), sorted(want))
        for child, T in want.items():
            t = got[child]
            self.assertEqual(t["parent_frame_id"], "base_link")
            self.assertEqual(t["timestamp"], {"sec": 1_700_000_000, "nsec": 0})
            d = t["translation"]
            # The bag holds float64 (the generator's numbers): 1e-12 m, 1e-12.
            np.testing.assert_allclose([d["x"], d["y"], d["z"]], T[:3, 3], atol=1e-12)
            np.testing.assert_allclose(quat_matrix(t["rotation"]), T[:3, :3], atol=1e-12)

    def test_pairs_carry_their_matching_as_the_json_lines_do(self):
        args = [RUN / "kitti_seq", "--pairs", "--poses", RUN / "kitti_seq" / "poses_lidar.txt",
                "--poses-format", "kitti-lidar"]
        with tempfile.TemporaryDirectory() as tmp:
            f, lines, _ = export_run(tmp, *args)
        t = f["topics"]["/audit/run"]
        self.assertGreater(len(lines), 0)
        self.assertEqual(len(t["messages"]), len(lines))
        for msg, line in zip(t["messages"], lines):
            msg.pop("timestamp")
            self.assertEqual(msg, no_nulls(line))
            self.assertEqual(msg["unit"], "pairs")
            self.assertIn("pair", msg)
        # KITTI has times.txt and no stamps: log time is time_s.
        self.assertEqual(t["log_times"], [round(x["time_s"] * 1e9) for x in lines])
        self.assertEqual(f["metadata"]["extrinsic-audit"]["log_time"], "time_s")
        # No transforms in a KITTI sequence: no /tf.
        self.assertNotIn("/tf", f["topics"])

    def test_a_folder_without_times_is_at_one_scan_a_second(self):
        with tempfile.TemporaryDirectory() as tmp:
            f, lines, _ = export_run(tmp, RUN / "pcd_seq")
        t = f["topics"]["/audit/run"]
        self.assertEqual(len(t["messages"]), len(lines))
        self.assertEqual(t["log_times"], [x["index"] * 10**9 for x in lines])
        self.assertEqual(f["metadata"]["extrinsic-audit"]["log_time"], "index")

    def test_without_output_it_is_refused_by_name(self):
        p = run("run", RUN / "run.mcap", "--format", "mcap", check=False)
        self.assertEqual(p.returncode, 2)
        self.assertIn(b"--format mcap: audit run streams the MCAP file; give --output FILE.mcap",
                      p.stderr)
        self.assertEqual(p.stdout, b"")


class ViewerReadable(unittest.TestCase):
    """What Foxglove's and Lichtblick's JSON-schema reader refuses (seen in
    Lichtblick: "Unsupported type undefined for schema_version") is refused
    here too, and the committed schema passes."""

    def test_the_run_schema_is_readable_and_nullable_types_are_not(self):
        schema = json.loads((fm.OWN_SCHEMAS / "RunScan.json").read_text())
        fm.viewer_readable(schema)
        for bad, why in [({"type": ["number", "null"]}, "found ['number', 'null']"),
                         ({"const": 1}, "found None"),
                         ({"anyOf": [{"type": "number"}, {"type": "null"}]}, "found None"),
                         ({"type": "array", "items": {"type": ["boolean", "null"]}},
                          "one non-array item type")]:
            with self.assertRaises(fm.Invalid) as e:
                fm.viewer_readable({"type": "object", "properties": {"x": bad}})
            self.assertIn(why, str(e.exception))


if __name__ == "__main__":
    unittest.main()
