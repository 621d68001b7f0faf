"""Transform calls per second: extrinsic_audit against pytransform3d, paired
in one process on ANYmal C (BENCHMARKS.md, "Python package").

Both load the same URDF; each round times CALLS calls of
`robot.transform("base", "lidar")` and of pytransform3d's
`UrdfTransformManager.get_transform("lidar", "base")` (the same pose: lidar
in base), one after the other, after checking the two agree to 1e-12. The
robot is the whole ANYmal C of the test-data folder when it is there
(docs/test-data.md), else the authored base -> LiDAR chain
(tests/fixtures/urdf/anymal_c_lidar.urdf).

    python python/bench/transform.py [--rounds 15] [--calls 20000]

from the checkout, in a venv with the wheel, numpy and pytransform3d
(python-tests/run.sh makes one: target/py-venv).
"""

import argparse
import os
import platform
import statistics
import sys
import time

import numpy as np
from pytransform3d.urdf import UrdfTransformManager

import extrinsic_audit as ea

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import testdata  # noqa: E402


def robot_file():
    real = testdata.find("tests/fixtures/urdf/anymal_c.urdf")
    if real:
        return real, "ANYmal C (whole URDF, test-data folder)"
    return os.path.join(ROOT, "tests/fixtures/urdf/anymal_c_lidar.urdf"), "ANYmal C base -> LiDAR chain (authored fixture)"


def rate(fn, calls):
    t0 = time.perf_counter()
    for _ in range(calls):
        fn()
    return calls / (time.perf_counter() - t0)


def summary(v):
    return f"min {min(v):>10,.0f}  median {statistics.median(v):>10,.0f}  max {max(v):>10,.0f}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--calls", type=int, default=20000)
    a = ap.parse_args()
    path, what = robot_file()
    robot = ea.load(path)
    tm = UrdfTransformManager()
    with open(path, encoding="utf-8") as f:
        tm.load_urdf(f.read())
    ours = lambda: robot.transform("base", "lidar")  # noqa: E731
    peer = lambda: tm.get_transform("lidar", "base")  # noqa: E731
    assert np.allclose(ours(), peer(), rtol=0, atol=1e-12)
    rate(ours, a.calls // 10), rate(peer, a.calls // 10)  # warm-up
    r_ours, r_peer, ratio = [], [], []
    for _ in range(a.rounds):
        x, y = rate(ours, a.calls), rate(peer, a.calls)
        r_ours.append(x)
        r_peer.append(y)
        ratio.append(x / y)
    load = os.getloadavg()
    print(f"robot: {what}; {a.rounds} rounds of {a.calls} calls each")
    print(f"machine: {platform.machine()} {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    print(f"extrinsic_audit {ea.__version__} transform   calls/s: {summary(r_ours)}")
    print(f"pytransform3d get_transform      calls/s: {summary(r_peer)}")
    print(f"ratio (same round)                       : min {min(ratio):.1f}  median "
          f"{statistics.median(ratio):.1f}  max {max(ratio):.1f}")


if __name__ == "__main__":
    main()
