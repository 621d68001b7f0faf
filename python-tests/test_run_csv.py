"""`audit run`'s per-scan CSV read by pandas with no options, as a user
would: one row per scan (or pair), one number per column, the dtypes a
table of numbers should have (no column of numbers read as text), and every
value equal to the same run's JSON lines (the CSV prints shortest
round-trip f64s, so equality is exact).

    target/py-venv/bin/python -m unittest discover -s python-tests -v
"""
import json
import subprocess
import tempfile
import unittest
from pathlib import Path

import numpy as np
import pandas as pd

from test_mcap import ROOT, audit_bin

RUN = ROOT / "tests" / "fixtures" / "run"
FIXED = ["index", "time_s", "stamp_ns", "frame_id", "place", "status", "reason",
         "cells", "nonfinite", "points", "normals"]
PAIR = ["target_index", "target_time_s", "source_points", "target_points", "mean_distance_m",
        "guess_x_m", "guess_y_m", "guess_z_m", "guess_roll_rad", "guess_pitch_rad", "guess_yaw_rad"]
TEXT = {"frame_id", "place", "status", "reason", "normals"}
AXES = ["rx", "ry", "rz", "tx", "ty", "tz"]


def run_both(*args):
    """`audit run ARGS --csv --jsonl` in the fixtures' folder: (DataFrame, records, summary)."""
    with tempfile.TemporaryDirectory() as d:
        csv, jl = Path(d) / "r.csv", Path(d) / "r.jsonl"
        p = subprocess.run([audit_bin(), "run", *args, "--csv", csv, "--jsonl", jl, "--format", "json"],
                           cwd=RUN, capture_output=True)
        if p.returncode != 0:
            raise AssertionError(f"audit run {args}: exit {p.returncode}: {p.stderr.decode()}")
        recs = [json.loads(line) for line in jl.read_text().splitlines()]
        return pd.read_csv(csv), recs, json.loads(p.stdout)


class RunCsv(unittest.TestCase):
    def check(self, df, recs, summary, pairs=False):
        # One row per record, in run order.
        self.assertEqual(len(df), len(recs))
        self.assertEqual(df["index"].tolist(), [r["index"] for r in recs])
        # The columns: fixed, pair, then per frame and family.
        frames = [f["name"] for f in summary["frames"]]
        fams = [f["key"] for f in summary["families"]]
        want = FIXED + (PAIR if pairs else [])
        for fr in frames:
            for k in fams:
                want += [f"{k}@{fr}.lambda{i}" for i in range(1, 7)]
                want += [f"{k}@{fr}.threshold", f"{k}@{fr}.count"]
            want += [f"point_displacement@{fr}.footprint_{a}" for a in AXES]
        self.assertEqual(list(df.columns), want)
        # Dtypes: every column but the text ones is numeric as read.
        for c in df.columns:
            if c in TEXT:
                self.assertFalse(pd.api.types.is_numeric_dtype(df[c]) and df[c].notna().any(), c)
            else:
                self.assertTrue(pd.api.types.is_numeric_dtype(df[c]), f"{c}: {df[c].dtype}")
        ok = df["status"] == "ok"
        for c in ["index", "stamp_ns"]:
            self.assertEqual(df[c].dtype, np.int64, c)
        if ok.all():
            for c in [c for c in df.columns if c.endswith(".count") or ".footprint_" in c]:
                self.assertEqual(df[c].dtype, np.int64, c)
        # Values: the JSON lines', exactly.
        for (_, row), r in zip(df.iterrows(), recs):
            self.assertEqual(row["status"], r["status"])
            self.assertEqual(row["stamp_ns"], r["stamp_ns"])
            if r["status"] != "ok":
                self.assertEqual(row["reason"], r["reason"])
                self.assertTrue(np.isnan(row[f"point_displacement@{frames[0]}.lambda1"]))
                continue
            self.assertTrue(pd.isna(row["reason"]))
            self.assertEqual(row["points"], r["points"])
            self.assertEqual(row["normals"], r["normals"])
            if pairs:
                p = r["pair"]
                self.assertEqual(row["target_index"], p["target_index"])
                self.assertEqual(row["mean_distance_m"], p["mean_distance_m"])
                self.assertEqual([row[f"guess_{a}_m"] for a in "xyz"], p["initial_guess"]["translation_m"])
            for f in r["frames"]:
                for fam in f["families"] or []:
                    pre = f"{fam['family']}@{f['frame']}"
                    got = [row[f"{pre}.lambda{i}"] for i in range(1, 7)]
                    self.assertEqual(got, fam["eigenvalues"], pre)
                    self.assertEqual(row[f"{pre}.threshold"], fam["threshold"], pre)
                    self.assertEqual(row[f"{pre}.count"], fam["degenerate_count"], pre)
                    if fam["family"] == "point_displacement":
                        fp = [bool(row[f"{pre}.footprint_{a}"]) for a in AXES]
                        self.assertEqual(fp, fam["footprint"], pre)

    def test_scans_in_every_frame(self):
        df, recs, s = run_both("run.mcap", "--all-frames")
        self.assertEqual(len(df), 8)
        self.check(df, recs, s)

    def test_pairs(self):
        df, recs, s = run_both("run.bag", "--pairs", "--all-frames")
        self.assertEqual(len(df), 7)
        self.check(df, recs, s, pairs=True)

    def test_skipped_scans_are_rows_with_empty_numbers(self):
        df, recs, s = run_both("hostile.mcap")
        self.assertIn("skipped", df["status"].tolist())
        self.check(df, recs, s)
        # The empty cells of skipped rows are missing values, not text.
        skipped = df[df["status"] == "skipped"]
        self.assertTrue(skipped["point_displacement@scan.count"].isna().all())
        self.assertEqual(df["point_displacement@scan.count"].dtype, np.float64)


if __name__ == "__main__":
    unittest.main()
