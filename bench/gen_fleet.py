#!/usr/bin/env python3
"""A generated fleet for `audit spread` and `audit check --fleet-tolerance`:
OUT/vNNNNN/sensors_calibration.yaml (Autoware's `PARENT: {CHILD: {x, y, z,
roll, pitch, yaw}}`), base_link -> velodyne_top scattered by 1 mm and 0.05 deg
per axis (seeded; the translation noise clamped to +-2.5 mm, so that no
vehicle it did not move is ever beyond the benchmark's 5 mm fleet tolerance:
at most 4.4 mm from the mean, which the moved ones shift by 0.12 mm), every
100th vehicle moved by 12 mm in x (beyond the tolerance whatever the noise:
bench/fleet_bench.sh checks that `check` names exactly those).

    python3 bench/gen_fleet.py OUT N
"""
import os
import random
import sys


def main():
    out, n = sys.argv[1], int(sys.argv[2])
    rng = random.Random(30)
    for i in range(1, n + 1):
        d = os.path.join(out, f"v{i:05d}")
        os.makedirs(d, exist_ok=True)
        g = lambda s: rng.gauss(0.0, s)
        # Clamped after the draw: the same draws, so the same fleet as before
        # wherever no draw was beyond 2.5 sigma.
        mm = lambda: min(max(g(0.001), -0.0025), 0.0025)
        x = 0.9 + mm() + (0.012 if i % 100 == 0 else 0.0)
        with open(os.path.join(d, "sensors_calibration.yaml"), "w") as f:
            f.write("base_link:\n  velodyne_top:\n"
                    f"    x: {x:.7f}\n    y: {mm():.7f}\n    z: {2.0 + mm():.7f}\n"
                    f"    roll: {g(0.00087):.7f}\n    pitch: {0.015 + g(0.00087):.7f}\n"
                    f"    yaw: {g(0.00087):.7f}\n")


if __name__ == "__main__":
    main()
