#!/usr/bin/env python3
"""The Python peer of `audit spread DIR --from base_link --to velodyne_top
--format json` on a fleet from bench/gen_fleet.py: walk, read each YAML
(PyYAML's safe_load), build the rotation (scipy, URDF rpy = extrinsic xyz),
then the chordal mean (Rotation.mean), the arithmetic translation mean, each
deviation, std (ddof 1) and the largest deviation per axis; JSON to stdout.

    PY bench/fleet_python.py DIR      (numpy, scipy, pyyaml)
"""
import json
import os
import sys

import numpy as np
import yaml
from scipy.spatial.transform import Rotation


def main():
    names, rpy, t = [], [], []
    for root, _, files in sorted(os.walk(sys.argv[1])):
        for f in sorted(files):
            with open(os.path.join(root, f)) as fh:
                e = yaml.safe_load(fh)["base_link"]["velodyne_top"]
            names.append(os.path.basename(root))
            rpy.append([e["roll"], e["pitch"], e["yaw"]])
            t.append([e["x"], e["y"], e["z"]])
    R = Rotation.from_euler("xyz", rpy)
    t = np.asarray(t)
    mean = R.mean()
    d_rot = (mean.inv() * R).as_rotvec()
    d_t = (t - t.mean(axis=0)) * 1e3
    out = {"count": len(names), "mean_quaternion_xyzw": mean.as_quat().tolist(),
           "mean_translation_m": t.mean(axis=0).tolist(),
           "rotation_std_deg": np.degrees(d_rot.std(axis=0, ddof=1)).tolist(),
           "translation_std_mm": d_t.std(axis=0, ddof=1).tolist(),
           "largest_mm": names[int(np.argmax(np.linalg.norm(d_t, axis=1)))]}
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
