#!/usr/bin/env python3
"""The survey's per-rig numbers computed by a plain Python loop (tomllib +
numpy): the peer of `audit survey DIR --format json` in the survey benchmark
(bench/rig_bench.sh).

    python bench/survey_python.py DIR

For every stand-alone rig file (`*.toml` without `[[include]]`, found
recursively) it composes the transforms from `rig.from` to `rig.to`
(inverting edges walked backwards, `invert = true` honoured, `unit = "mm"`
scaled), and computes lever arm, rotation angle, screw translation h, the
adjoint singular values and the certificate band at the default lengths, as
the tool does. Prints one JSON line per rig. Needs: pip install numpy
"""
import json
import math
import pathlib
import sys
import tomllib

import numpy as np

ELLS = [0.25, 1.0, 2.85, 10.0]


def rot(t):
    if "rotation_matrix" in t:
        return np.array(t["rotation_matrix"], float)
    if "rpy" in t or "ypr" in t:
        r, p, y = t["rpy"] if "rpy" in t else t["ypr"][::-1]
        cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
        return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                         [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                         [-sp, cp * sr, cp * cr]])
    if "quaternion_xyzw" in t or "quaternion_wxyz" in t:
        if "quaternion_xyzw" in t:
            x, y, z, w = t["quaternion_xyzw"]
        else:
            w, x, y, z = t["quaternion_wxyz"]
        n = math.sqrt(x * x + y * y + z * z + w * w)
        x, y, z, w = x / n, y / n, z / n, w / n
        return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    if "axis_angle" in t:
        a = np.array(t["axis_angle"]["axis"], float)
        a /= np.linalg.norm(a)
        th = t["axis_angle"]["angle"]
        K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        return np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K
    raise ValueError("rotation form")


def edge(t):
    T = np.eye(4)
    if "matrix4" in t:
        T = np.array(t["matrix4"], float)
    elif "matrix3x4" in t:
        T[:3, :] = np.array(t["matrix3x4"], float)
    else:
        T[:3, :3] = rot(t)
        T[:3, 3] = t["translation"]
    if t.get("unit", "m") == "mm":
        T[:3, 3] /= 1000.0
    # Project onto SO(3) as the tool does for rounded matrices.
    u, _, vt = np.linalg.svd(T[:3, :3])
    T[:3, :3] = u @ vt
    return np.linalg.inv(T) if t.get("invert", False) else T


def chain(edges, a, b):
    """Pose of b in a through the tree (breadth-first over both directions)."""
    adj = {}
    for p, c, T in edges:
        adj.setdefault(p, []).append((c, T))
        adj.setdefault(c, []).append((p, np.linalg.inv(T)))
    seen, todo = {a: np.eye(4)}, [a]
    while todo:
        f = todo.pop()
        for g, T in adj.get(f, []):
            if g not in seen:
                seen[g] = seen[f] @ T
                todo.append(g)
    return seen[b]


def adjoint(R, d):
    A = np.zeros((6, 6))
    A[:3, :3] = R
    A[3:, 3:] = R
    A[3:, :3] = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]]) @ R
    return A


for path in sorted(pathlib.Path(sys.argv[1]).rglob("*.toml")):
    doc = tomllib.loads(path.read_text())
    if "include" in doc or "rig" not in doc or doc["rig"].get("placeholder", False):
        continue
    rig = doc["rig"]
    T = chain([(t["parent"], t["child"], edge(t)) for t in doc["transform"]], rig["from"], rig["to"])
    R, d = T[:3, :3], T[:3, 3]
    angle = math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2)))
    # Rotation axis: the eigenvector of eigenvalue 1 (valid at a half-turn too),
    # signed like the skew part when there is one; h is then the screw translation.
    vals, vecs = np.linalg.eig(R)
    axis = np.real(vecs[:, np.argmin(abs(vals - 1))])
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if w @ axis < 0:
        axis = -axis
    h = float(axis @ d) if angle > 1e-12 else 0.0
    print(json.dumps({
        "id": rig["id"],
        "lever_arm_m": float(np.linalg.norm(d)),
        "angle_rad": angle,
        "h_m": h,
        "singular_values": np.linalg.svd(adjoint(R, d), compute_uv=False).tolist(),
        "bands": [[float(s.min() ** 2), float(s.max() ** 2)]
                  for s in (np.linalg.svd(adjoint(R, d / l), compute_uv=False) for l in ELLS)],
    }))
