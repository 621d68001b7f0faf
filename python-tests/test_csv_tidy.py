"""`--format csv` of every command that offers it, read by pandas with no
options, as a user would (issue 33, item 5): one table, the number columns
read as numbers (no "[x, y, z]" strings, no "1.2 mm" cells), and the values
equal to the same run's `--format json`, exactly (both print shortest
round-trip f64s). The JSON path of each column checked is written out here,
by hand, from docs/schemas: not derived from the column names.

    target/py-venv/bin/python -m unittest python-tests/test_csv_tidy.py -v
"""
import io
import json
import subprocess
import unittest

import pandas as pd

from test_mcap import ROOT, audit_bin

FIX = ROOT / "tests" / "fixtures"
URDF = str(FIX / "urdf" / "anymal_c_lidar.urdf")
PLY = str(FIX / "detector" / "tunnel_small_le.ply")


def audit(*args):
    p = subprocess.run([audit_bin(), *args], cwd=ROOT, capture_output=True)
    if p.returncode not in (0, 1):
        raise AssertionError(f"audit {args}: exit {p.returncode}: {p.stderr.decode()}")
    return p.stdout.decode()


def both(*args):
    """(DataFrame of `--format csv`, JSON of `--format json`, the CSV text)."""
    text = audit(*args, "--format", "csv")
    return pd.read_csv(io.StringIO(text)), json.loads(audit(*args, "--format", "json")), text


def at(v, path):
    """The value at `path`; None below a null (an edge in one file has no delta)."""
    for k in path:
        if v is None:
            return None
        v = v[k]
    return v


# Per command: its arguments, where its rows are in the JSON, and columns
# with the JSON path (within a row) of their value.
CASES = {
    "rig report": (
        [URDF, "--from", "base", "--to", "lidar", "--ell", "1,0.5"],
        lambda v: [v],
        {
            "translation_x_m": ["transform", "translation_m", 0],
            "translation_z_m": ["transform", "translation_m", 2],
            "quaternion_w": ["transform", "quaternion_xyzw", 3],
            "rpy_yaw_rad": ["transform", "rpy_rad", 2],
            "lever_arm_m": ["lever_arm_m"],
            "angle_deg": ["rotation", "angle_deg"],
            "translation_along_axis_m": ["screw", "translation_along_axis_m"],
            "pitch_m_per_rad": ["screw", "pitch_m_per_rad"],
            "axis_point_y_m": ["screw", "axis_point_m", 1],
            "sigma_max": ["adjoint", "singular_values", 0],
            "band_l1_low": ["certificate", 0, "band", 0],
            "band_l1_high": ["certificate", 0, "band", 1],
            "band_l0.5_low": ["certificate", 1, "band", 0],
            "screw_kind": ["screw", "kind"],
        },
    ),
    "survey": (
        ["survey", str(ROOT / "calibrations")],
        lambda v: v["rigs"],
        {
            "id": ["id"],
            "lever_arm_m": ["lever_arm_m"],
            "angle_deg": ["angle_deg"],
            "screw_translation_m": ["screw_translation_m"],
            "sigma_max": ["sigma_max"],
            "band_l1_low": ["band_l1", 0],
            "band_l1_high": ["band_l1", 1],
            "pitch_verdict": ["pitch_verdict"],
        },
    ),
    "check": (
        ["check", str(ROOT / "calibrations"), "--max-lever-arm", "0.1"],
        lambda v: v["findings"],
        {"code": ["code"], "severity": ["severity"], "line": ["line"], "message": ["message"]},
    ),
    "diff": (
        ["diff", str(FIX / "diff" / "whole_old.urdf"), str(FIX / "diff" / "whole_new.urdf")],
        lambda v: v["edges"],
        {
            "parent": ["parent"],
            "child": ["child"],
            "status": ["status"],
            "translation_delta_x_m": ["translation_delta_m", 0],
            "translation_change_mm": ["translation_change_mm"],
            "rotation_change_deg": ["rotation_change_deg"],
        },
    ),
    "spread": (
        ["spread", str(FIX / "spread" / "kitti-repeat")],
        lambda v: v["calibrations"],
        {
            "name": ["name"],
            "translation_y_m": ["translation_m", 1],
            "quaternion_x": ["quaternion_xyzw", 0],
            "rotation_to_z_deg": ["deviation", "rotation_to_deg", 2],
            "translation_from_x_mm": ["deviation", "translation_from_mm", 0],
            "distance_mm": ["deviation", "distance_mm"],
            "h_m": ["h_m"],
        },
    ),
    "degeneracy": (
        ["degeneracy", PLY, "--shift", "1,0,0"],
        lambda v: v["families"],
        {
            "family": ["family"],
            "eigenvalues_1": ["eigenvalues", 0],
            "eigenvalues_6": ["eigenvalues", 5],
            "threshold": ["threshold"],
            "degenerate_count": ["degenerate_count"],
        },
    ),
    "degeneracy of a pair": (
        ["degeneracy", PLY, "--target", PLY, "--gate", "0.5"],
        lambda v: v["families"],
        {"eigenvalues_3": ["eigenvalues", 2], "degenerate_count": ["degenerate_count"]},
    ),
    "simulate": (
        ["simulate", "--shift", "0.3,0,0.2", "--rotate-rpy", "0,0,1.57", "--scene", "tunnel"],
        lambda v: v["families"],
        {
            "eigenvalues_from_1": ["eigenvalues", "from", 0],
            "eigenvalues_to_6": ["eigenvalues", "to", 5],
            "degenerate_count_to": ["degenerate_count", "to"],
            "max_eigenvalue_rel_change": ["max_eigenvalue_rel_change"],
        },
    ),
    "sweep": (
        ["sweep", PLY, "--rig", URDF, "--from", "base", "--to", "lidar"],
        lambda v: v["families"],
        {
            "decision_change_rate": ["decision_change_rate"],
            "decision_change_wilson95_high": ["decision_change_wilson95", 1],
            "max_eigenvalue_rel_change": ["max_eigenvalue_rel_change"],
            "rig_degenerate_count": ["rig", "degenerate_count"],
        },
    ),
    "tunnel": (
        ["tunnel", "--shift", "0,2,0"],
        lambda v: [v["on_axis"], v["shifted"]],
        {"origin_y_m": ["origin_m", 1], "eigenvalues_2": ["eigenvalues", 1], "nullity": ["nullity"]},
    ),
    "calibrate-threshold": (
        ["calibrate-threshold", "--seeds", "1", "--noise", "0", "--voxel", "0.1"],
        lambda v: [c for f in v["families"] for c in f["configurations"]],
        {"noise_m": ["noise_m"], "interval_hi": ["interval", "hi"], "corridor_lo": ["per_scene", "corridor", "lo"]},
    ),
}

# Columns of text (or of flags) in any table; every other column is numbers.
TEXT = {
    "id", "sensor", "platform", "dataset", "from", "to", "pitch_verdict", "uncertainty_source",
    "duplicate_of", "severity", "code", "file", "message", "help", "parent", "child", "status",
    "old_place", "new_place", "name", "family", "error", "frame", "screw_kind",
}


class TidyCsv(unittest.TestCase):
    def test_every_command_reads_as_one_table_of_numbers_equal_to_its_json(self):
        for name, (args, get_rows, columns) in CASES.items():
            with self.subTest(name):
                df, v, text = both(*args)
                self.assertNotIn("\n\n", text, "one table, no blank line")
                self.assertNotIn("[", text)
                want = get_rows(v)
                self.assertEqual(len(df), len(want))
                self.assertGreater(len(df), 0)
                for c in df.columns:
                    if c in TEXT:
                        continue
                    col = df[c]
                    if col.isna().all():
                        continue  # no value in this run (e.g. no screw axis)
                    # Numbers as numbers, flags as booleans: never text.
                    self.assertTrue(
                        pd.api.types.is_numeric_dtype(col) or pd.api.types.is_bool_dtype(col),
                        f"{name}: {c} read as {col.dtype}: {col.tolist()[:3]}",
                    )
                for c, path in columns.items():
                    self.assertIn(c, df.columns, name)
                    for i, row in enumerate(want):
                        x, got = at(row, path), df[c].iloc[i]
                        if x is None:
                            self.assertTrue(pd.isna(got), f"{name}: {c}[{i}] = {got!r}, JSON null")
                        elif isinstance(x, str):
                            self.assertEqual(got, x, f"{name}: {c}[{i}]")
                        else:
                            self.assertEqual(float(got), float(x), f"{name}: {c}[{i}]")


if __name__ == "__main__":
    unittest.main()
