"""`audit --format mcap` read back by an independent reader (Foxglove's `mcap`
package, every message validated against Foxglove's own schemas: see
foxglove_mcap.py), compared with the same command's JSON report and, for a
scan, with numpy's own generalized eigenproblem and per-point shares.

    target/py-venv/bin/python -m unittest discover -s python-tests -v

The binary is $AUDIT_BIN, else the newer of target/release/audit and
target/debug/audit.
"""
import csv
import json
import math
import os
import subprocess
import tempfile
import unittest
from pathlib import Path

import numpy as np

import foxglove_mcap as fm

ROOT = fm.ROOT
FIX = ROOT / "tests" / "fixtures"
ANYMAL = FIX / "urdf" / "anymal_c_lidar.urdf"
HUSKY = FIX / "urdf" / "husky_kinematics.urdf"
CORRIDOR = FIX / "mcap" / "corridor_utm.csv"
TUNNEL = FIX / "detector" / "tunnel_small.csv"


def audit_bin():
    if os.environ.get("AUDIT_BIN"):
        return os.environ["AUDIT_BIN"]
    built = [ROOT / "target" / k / "audit" for k in ("release", "debug")]
    built = [b for b in built if b.exists()]
    if not built:
        raise unittest.SkipTest("no audit binary: cargo build first")
    return str(max(built, key=lambda b: b.stat().st_mtime))


def run(*args, check=True):
    p = subprocess.run([audit_bin(), *map(str, args)], capture_output=True, text=False)
    if check and p.returncode != 0:
        raise AssertionError(f"audit {args}: exit {p.returncode}: {p.stderr.decode()}")
    return p


def report(*args):
    return json.loads(run(*args, "--format", "json").stdout)


def export(tmp, name, *args):
    out = Path(tmp) / name
    run(*args, "--format", "mcap", "--output", out)
    return fm.read(out)


def quat_rotate(q, v):
    x, y, z, w = q
    u = np.array([x, y, z])
    v = np.asarray(v, float)
    return v + 2 * w * np.cross(u, v) + 2 * np.cross(u, np.cross(u, v))


def quat_from_rpy(r, p, y):
    """URDF rpy (R = Rz(y) Ry(p) Rx(r)) as [x, y, z, w]."""
    cr, sr, cp, sp = math.cos(r / 2), math.sin(r / 2), math.cos(p / 2), math.sin(p / 2)
    cy, sy = math.cos(y / 2), math.sin(y / 2)
    return [sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy]


def same_rotation(a, b, tol):
    return min(np.abs(np.subtract(a, b)).max(), np.abs(np.add(a, b)).max()) < tol


def entities(f):
    (scene,) = f["topics"]["/audit/scene"]["messages"]
    return {e["id"]: e for e in scene["entities"]}


def meta(e):
    return {kv["key"]: kv["value"] for kv in e["metadata"]}


def xyz(p):
    return np.array([p["x"], p["y"], p["z"]])


def counts(f):
    return {t: len(v["messages"]) for t, v in f["topics"].items()}


class Rig(unittest.TestCase):
    """ANYmal C: base -> lidar_cage -> lidar (a general screw)."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        args = (ANYMAL, "--from", "base", "--to", "lidar")
        cls.json = report(*args)
        cls.tree = report(ANYMAL, "--frames", "--from", "base", "--to", "lidar")
        cls.f = export(cls.tmp.name, "rig.mcap", *args)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_topics_schemas_and_counts(self):
        self.assertEqual(counts(self.f), {"/tf": 1, "/audit/scene": 1})
        t = self.f["topics"]
        self.assertEqual(t["/tf"]["schema"], "foxglove.FrameTransforms")
        self.assertEqual(t["/audit/scene"]["schema"], "foxglove.SceneUpdate")
        for v in t.values():
            self.assertEqual((v["schema_encoding"], v["message_encoding"]), ("jsonschema", "json"))
            self.assertEqual(v["log_times"], [0])

    def test_every_edge_of_the_graph_is_a_transform_equal_to_the_frame_tree(self):
        (tf,) = self.f["topics"]["/tf"]["messages"]
        got = {(t["parent_frame_id"], t["child_frame_id"]): t for t in tf["transforms"]}
        self.assertEqual(len(got), len(self.tree["edges"]))
        for e in self.tree["edges"]:
            t = got[(e["parent"], e["child"])]
            self.assertEqual(list(xyz(t["translation"])), e["translation_m"])
            q = [t["rotation"][k] for k in "xyzw"]
            want = quat_from_rpy(*np.radians(e["rpy_deg"]))
            self.assertTrue(same_rotation(q, want, 1e-12), (q, want))
            self.assertEqual(t["timestamp"], {"sec": 0, "nsec": 0})

    def test_the_chain_composes_to_the_reports_transform(self):
        (tf,) = self.f["topics"]["/tf"]["messages"]
        by_child = {t["child_frame_id"]: t for t in tf["transforms"]}
        path = self.tree["chain"]["path"]
        self.assertEqual(self.f["metadata"]["extrinsic-audit"]["chain"], " -> ".join(path))
        p = np.zeros(3)  # the origin of `lidar`, walked up to `base`
        q_total = [0.0, 0.0, 0.0, 1.0]
        for child in reversed(path[1:]):
            t = by_child[child]
            q = [t["rotation"][k] for k in "xyzw"]
            p = quat_rotate(q, p) + xyz(t["translation"])
        self.assertTrue(np.allclose(p, self.json["transform"]["translation_m"], atol=1e-12, rtol=0))

    def test_screw_axis_lever_arm_and_axes_carry_the_reports_numbers(self):
        es = entities(self.f)
        self.assertEqual(set(es), {"lever_arm", "screw_axis", "axes/base", "axes/lidar",
                                   "chain/base/lidar_cage", "chain/lidar_cage/lidar"})
        sc, j = es["screw_axis"], self.json["screw"]
        m = meta(sc)
        self.assertEqual(float(m["h_m"]), j["translation_along_axis_m"])
        self.assertEqual(float(m["pitch_m_per_rad"]), j["pitch_m_per_rad"])
        self.assertEqual(json.loads(m["axis_point_m"]), j["axis_point_m"])
        self.assertEqual(json.loads(m["axis"]), self.json["rotation"]["axis"])
        (line,) = sc["lines"]
        e = np.array(self.json["rotation"]["axis"])
        for pt in line["points"]:  # on the axis
            off = xyz(pt) - np.array(j["axis_point_m"])
            self.assertLess(np.linalg.norm(np.cross(off, e)), 1e-12)
        self.assertIn("h = -0.1422 m", sc["texts"][0]["text"])
        (arrow,) = es["lever_arm"]["arrows"]
        self.assertAlmostEqual(arrow["shaft_length"] + arrow["head_length"], self.json["lever_arm_m"], delta=1e-15)
        self.assertEqual(list(xyz(arrow["pose"]["position"])), [0.0, 0.0, 0.0])
        q = [arrow["pose"]["orientation"][k] for k in "xyzw"]
        d = np.array(self.json["transform"]["translation_m"])
        self.assertTrue(np.allclose(quat_rotate(q, [1, 0, 0]), d / np.linalg.norm(d), atol=1e-12))
        self.assertEqual(float(meta(es["lever_arm"])["lever_arm_m"]), self.json["lever_arm_m"])
        self.assertEqual(json.loads(meta(es["lever_arm"])["band"]), self.json["certificate"][0]["band"])
        for f in ("base", "lidar"):
            ax = es[f"axes/{f}"]
            self.assertEqual(ax["frame_id"], f)
            colours = [(a["color"]["r"], a["color"]["g"], a["color"]["b"]) for a in ax["arrows"]]
            self.assertEqual([max(range(3), key=c.__getitem__) for c in colours], [0, 1, 2])


class Frames(unittest.TestCase):
    def test_the_frame_tree_has_every_edge_and_no_chain_entities_without_a_chain(self):
        with tempfile.TemporaryDirectory() as tmp:
            f = export(tmp, "tree.mcap", HUSKY, "--frames")
        tree = report(HUSKY, "--frames")
        self.assertEqual(counts(f), {"/tf": 1})
        (tf,) = f["topics"]["/tf"]["messages"]
        self.assertEqual([(t["parent_frame_id"], t["child_frame_id"]) for t in tf["transforms"]],
                         [(e["parent"], e["child"]) for e in tree["edges"]])
        self.assertEqual(f["metadata"]["extrinsic-audit"]["frames"], str(len(tree["frames"])))


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    p = np.array([[float(r[k]) for k in "xyz"] for r in rows])
    n = np.array([[float(r[k]) for k in ("nx", "ny", "nz")] for r in rows])
    w = np.array([float(r["w"]) if "w" in r else 1.0 for r in rows])
    return p, n, w


def numpy_weakest(p, n, w):
    """Smallest generalized eigenpair of H v = l M v about the centroid, and
    each point's share w (a . v)^2 / v^T H v (a = [p x n; n])."""
    c = (w[:, None] * p).sum(0) / w.sum()
    q = p - c
    a = np.hstack([np.cross(q, n), n])
    H = (w[:, None, None] * a[:, :, None] * a[:, None, :]).sum(0)
    J = np.zeros((len(q), 3, 6))
    for i, qi in enumerate(q):
        J[i, :, :3] = -np.array([[0, -qi[2], qi[1]], [qi[2], 0, -qi[0]], [-qi[1], qi[0], 0]])
        J[i, :, 3:] = np.eye(3)
    M = np.einsum("i,ikj,ikl->jl", w, J, J)
    L = np.linalg.cholesky(M)
    Li = np.linalg.inv(L)
    vals, y = np.linalg.eigh(Li @ H @ Li.T)
    v = Li.T @ y[:, 0]
    rows = w * (a @ v) ** 2
    return vals, rows / rows.sum(), c


class Scan(unittest.TestCase):
    """A corridor far from the origin, weighted: its weakest direction is x."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.json = report("degeneracy", CORRIDOR)
        cls.f = export(cls.tmp.name, "scan.mcap", "degeneracy", CORRIDOR)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_topics_and_counts(self):
        self.assertEqual(counts(self.f), {"/tf": 1, "/audit/scene": 1, "/audit/points": 1})
        self.assertEqual(self.f["topics"]["/audit/points"]["schema"], "foxglove.PointCloud")

    def test_eigenvalues_equal_the_report_and_numpy(self):
        pd = next(x for x in self.json["families"] if x["family"] == "point_displacement")
        md = self.f["metadata"]["extrinsic-audit"]
        self.assertEqual(json.loads(md["point_displacement_eigenvalues"]), pd["eigenvalues"])
        self.assertEqual(float(md["weakest_eigenvalue"]), pd["eigenvalues"][0])
        vals, _, _ = numpy_weakest(*read_csv(CORRIDOR))
        self.assertTrue(np.allclose(vals, pd["eigenvalues"], rtol=1e-9, atol=1e-12), (vals, pd["eigenvalues"]))

    def test_points_are_the_files_and_their_shares_numpys(self):
        p, n, w = read_csv(CORRIDOR)
        _, share, _ = numpy_weakest(p, n, w)
        (msg,) = self.f["topics"]["/audit/points"]["messages"]
        self.assertEqual(msg["frame_id"], "scan")
        self.assertEqual([f["name"] for f in msg["fields"]], ["x", "y", "z", "weakest_share"])
        pts = fm.decode_cloud(msg)
        self.assertEqual(len(pts), self.json["points"])
        origin = xyz(msg["pose"]["position"])
        got = np.array([[r["x"], r["y"], r["z"]] for r in pts]) + origin
        # float32 offsets from the centroid: sub-micrometre 500 km from the origin.
        self.assertLess(np.abs(got - p).max(), 1e-6)
        s = np.array([r["weakest_share"] for r in pts])
        self.assertLess(np.abs(s - share).max(), 1e-6 * share.max())
        self.assertAlmostEqual(s.sum(), 1.0, delta=1e-5)
        # The end-wall patch (its 9 points at x = 4) holds most of translation x.
        patch = np.isclose(p[:, 0] - 500000.0, 4.0)
        self.assertEqual(patch.sum(), 9)
        self.assertGreater(s[patch].sum(), 0.5)

    def test_the_degenerate_translation_is_drawn_along_its_direction(self):
        (sub,) = self.json["degenerate_subspace"]
        e = entities(self.f)["degenerate/0"]
        self.assertEqual(e["frame_id"], "body")
        self.assertEqual(json.loads(meta(e)["direction"]), sub["screw"]["direction"])
        self.assertEqual(float(meta(e)["eigenvalue"]), sub["eigenvalue"])
        (arrow,) = e["arrows"]
        q = [arrow["pose"]["orientation"][k] for k in "xyzw"]
        self.assertTrue(np.allclose(quat_rotate(q, [1, 0, 0]), sub["screw"]["direction"], atol=1e-12))


class Tunnel(unittest.TestCase):
    """Exactly degenerate (rotation about z and translation along z) in a
    frame shifted off the axis and turned."""

    def test_screws_in_the_body_frame_and_zero_shares(self):
        args = ("degeneracy", TUNNEL, "--shift", "1,0.5,0", "--rotate-rpy", "0,0,0.3")
        j = report(*args)
        with tempfile.TemporaryDirectory() as tmp:
            f = export(tmp, "tunnel.mcap", *args)
        (tf,) = f["topics"]["/tf"]["messages"]
        (t,) = tf["transforms"]
        self.assertEqual((t["parent_frame_id"], t["child_frame_id"]), ("scan", "body"))
        self.assertEqual(list(xyz(t["translation"])), j["frame"]["translation_m"])
        self.assertTrue(same_rotation([t["rotation"][k] for k in "xyzw"], quat_from_rpy(*j["frame"]["rpy_rad"]), 1e-12))
        es = entities(f)
        kinds = []
        for k, sub in enumerate(j["degenerate_subspace"]):
            e = es[f"degenerate/{k}"]
            kinds.append(meta(e)["kind"])
            if sub["screw"]["axis"] is not None:
                (line,) = e["lines"]
                for pt in line["points"]:
                    off = xyz(pt) - np.array(sub["screw"]["axis_point_m"])
                    self.assertLess(np.linalg.norm(np.cross(off, sub["screw"]["axis"])), 1e-9)
                self.assertEqual(float(meta(e)["pitch_m_per_rad"]), sub["screw"]["pitch_m_per_rad"])
        self.assertEqual(kinds, ["zero_pitch", "pure_translation"])
        (msg,) = f["topics"]["/audit/points"]["messages"]
        self.assertEqual({r["weakest_share"] for r in fm.decode_cloud(msg)}, {0.0})
        self.assertIn("no point constrains", f["metadata"]["extrinsic-audit"]["weakest_share"])


class Pair(unittest.TestCase):
    def test_a_pair_has_its_target_frame_and_both_clouds(self):
        args = ("degeneracy", CORRIDOR, "--target", CORRIDOR, "--initial-guess", "0.05,0.02,0,0,0,0")
        j = report(*args)
        with tempfile.TemporaryDirectory() as tmp:
            f = export(tmp, "pair.mcap", *args)
        self.assertEqual(counts(f), {"/tf": 1, "/audit/scene": 1, "/audit/points": 1, "/audit/target_points": 1})
        (tf,) = f["topics"]["/tf"]["messages"]
        names = [(t["parent_frame_id"], t["child_frame_id"]) for t in tf["transforms"]]
        self.assertEqual(names, [("target", "scan"), ("scan", "body")])
        guess = tf["transforms"][0]
        self.assertEqual(list(xyz(guess["translation"])), j["pair"]["initial_guess"]["translation_m"])
        (src,) = f["topics"]["/audit/points"]["messages"]
        (tgt,) = f["topics"]["/audit/target_points"]["messages"]
        self.assertEqual(len(fm.decode_cloud(src)), j["pair"]["correspondences"])
        self.assertEqual(len(fm.decode_cloud(tgt)), j["pair"]["target_points"])
        self.assertEqual(tgt["frame_id"], "target")
        shares = sum(r["weakest_share"] for r in fm.decode_cloud(src))
        self.assertAlmostEqual(shares, 1.0, delta=1e-5)


class Refusals(unittest.TestCase):
    def test_a_report_without_a_scene_and_an_input_as_output_are_refused(self):
        with tempfile.TemporaryDirectory() as tmp:
            p = run("survey", ROOT / "calibrations", "--format", "mcap", "--output",
                    Path(tmp) / "s.mcap", check=False)
            self.assertEqual(p.returncode, 2)
            self.assertIn(b"--format mcap writes a 3D scene", p.stderr)
            copy = Path(tmp) / "robot.urdf"
            copy.write_bytes(ANYMAL.read_bytes())
            p = run(copy, "--from", "base", "--to", "lidar", "--format", "mcap", "--output", copy, check=False)
            self.assertEqual(p.returncode, 2)
            self.assertIn(b"refusing to write over an input", p.stderr)
            self.assertEqual(copy.read_bytes(), ANYMAL.read_bytes())


class Terminal(unittest.TestCase):
    def test_mcap_is_refused_on_a_terminal_and_written_to_a_pipe(self):
        import pty

        args = [audit_bin(), ANYMAL, "--from", "base", "--to", "lidar", "--format", "mcap"]
        master, slave = pty.openpty()
        try:
            p = subprocess.run(args, stdout=slave, stderr=subprocess.PIPE, timeout=60)
        finally:
            os.close(slave)
            os.close(master)
        self.assertEqual(p.returncode, 2)
        self.assertIn(b"--format mcap is binary: refusing to write it to a terminal", p.stderr)
        p = subprocess.run(args, capture_output=True, timeout=60)
        self.assertEqual(p.returncode, 0, p.stderr)
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / "piped.mcap"
            out.write_bytes(p.stdout)
            self.assertEqual(counts(fm.read(out)), {"/tf": 1, "/audit/scene": 1})


class Validator(unittest.TestCase):
    """The reader rejects what Foxglove would: it is not a rubber stamp."""

    def test_a_missing_field_a_null_and_a_foreign_schema_are_rejected(self):
        from mcap.writer import Writer

        schema = (fm.SCHEMAS / "SceneUpdate.json").read_bytes()
        good = {"timestamp": {"sec": 0, "nsec": 0}, "frame_id": "f", "id": "e",
                "lifetime": {"sec": 0, "nsec": 0}, "frame_locked": True, "metadata": [],
                "arrows": [], "cubes": [], "spheres": [], "cylinders": [], "lines": [],
                "triangles": [], "texts": [], "models": []}
        no_models = {k: v for k, v in good.items() if k != "models"}
        nan_text = dict(good, texts=[{"pose": {"position": {"x": None, "y": 0, "z": 0},
                                               "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}},
                                      "billboard": True, "font_size": 1, "scale_invariant": True,
                                      "color": {"r": 1, "g": 1, "b": 1, "a": 1}, "text": "t"}])
        cases = [(schema, no_models, "'models' is a required property"),
                 (schema, nan_text, "None is not of type 'number'"),
                 (schema.replace(b'"Text"', b'"Txt"'), good, "not the committed foxglove.SceneUpdate")]
        with tempfile.TemporaryDirectory() as tmp:
            for i, (data, entity, why) in enumerate(cases):
                path = Path(tmp) / f"bad{i}.mcap"
                with open(path, "wb") as f:
                    w = Writer(f)
                    w.start()
                    sid = w.register_schema(name="foxglove.SceneUpdate", encoding="jsonschema", data=data)
                    ch = w.register_channel(topic="/audit/scene", message_encoding="json", schema_id=sid)
                    msg = {"deletions": [], "entities": [entity]}
                    w.add_message(ch, log_time=0, publish_time=0, data=json.dumps(msg).encode())
                    w.finish()
                with self.assertRaises(fm.Invalid) as e:
                    fm.read(path)
                self.assertIn(why, str(e.exception))


if __name__ == "__main__":
    unittest.main()
