#!/usr/bin/env python3
"""The rig report's numbers for one frame pair of a URDF, computed with
pytransform3d and numpy: the peer of `audit FILE --from A --to B --format json`
in the rig-report benchmark (bench/rig_bench.sh).

    python bench/rig_pytransform3d.py FILE.urdf FROM TO

Prints JSON: translation, lever arm, rotation angle, screw translation h and
pitch, adjoint singular values and the certificate band at the default
characteristic lengths (the same quantities the tool prints). Every movable
joint at 0, as the tool's default. Needs: pip install pytransform3d numpy lxml
"""
import json
import sys

import numpy as np
from pytransform3d import rotations as pr
from pytransform3d.urdf import UrdfTransformManager

ELLS = [0.25, 1.0, 2.85, 10.0]


def adjoint(R, d):
    A = np.zeros((6, 6))
    A[:3, :3] = R
    A[3:, 3:] = R
    A[3:, :3] = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]]) @ R
    return A


path, a, b = sys.argv[1:4]
tm = UrdfTransformManager()
with open(path) as f:
    tm.load_urdf(f.read())
T = tm.get_transform(b, a)  # pose of b in a
R, d = T[:3, :3], T[:3, 3]
aa = pr.axis_angle_from_matrix(R)
h = float(aa[:3] @ d)
rec = {
    "translation_m": d.tolist(),
    "lever_arm_m": float(np.linalg.norm(d)),
    "angle_rad": float(aa[3]),
    "h_m": h,
    "pitch_m_per_rad": h / aa[3] if aa[3] > 0 else None,
    "singular_values": sorted(np.linalg.svd(adjoint(R, d), compute_uv=False).tolist(), reverse=True),
    "bands": [
        [float(s.min() ** 2), float(s.max() ** 2)]
        for s in (np.linalg.svd(adjoint(R, d / l), compute_uv=False) for l in ELLS)
    ],
}
print(json.dumps(rec))
