#!/usr/bin/env python3
"""The LAS/LAZ read benchmark's files: the las-rs airborne strip
32-1-472-150-76.laz (5,658 points; read in place from the test-data
folder, docs/test-data.md) tiled 177
times, each copy 30 m further in y: 1,001,466 points, written by laspy as
LAS 1.2 point format 1 (uncompressed) and, with lazrs, as LAZ.
Usage: make_las_million.py OUTDIR   (writes million.las and million.laz)"""
import os
import sys

import laspy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tools"))
import testdata  # noqa: E402

SRC = testdata.need("gadomski__las-rs/tests/data/32-1-472-150-76.laz")


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    src = laspy.read(SRC)
    x, y, z = (np.asarray(src.x), np.asarray(src.y), np.asarray(src.z))
    k = 177
    hdr = laspy.LasHeader(point_format=1, version="1.2")
    hdr.scales = np.array([0.01, 0.01, 0.01])
    hdr.offsets = np.array([x.min(), y.min(), 0.0])
    las = laspy.LasData(hdr)
    las.x = np.concatenate([x] * k)
    las.y = np.concatenate([y + 30.0 * i for i in range(k)])
    las.z = np.concatenate([z] * k)
    las.write(os.path.join(out, "million.las"))
    las.write(os.path.join(out, "million.laz"), laz_backend=laspy.LazBackend.Lazrs)
    print(len(las.x), "points")


if __name__ == "__main__":
    sys.exit(main())
