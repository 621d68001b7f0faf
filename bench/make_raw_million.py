#!/usr/bin/env python3
"""A raw LiDAR scan of about a million points for the `--estimate-normals`
benchmark (issue 16): the real Velodyne scan
251370668.pcd of koide3/fast_gicp (69,088 points, x y z intensity; read in
place from the test-data folder, docs/test-data.md)
tiled 15 times, copy k shifted by 200 k m in x (so no neighbourhood spans two
copies), written as a binary PCD with the same fields: 1,036,320 points.

    python3 bench/make_raw_million.py OUT.pcd
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import testdata  # noqa: E402

SRC = testdata.need("koide3__fast_gicp/data/251370668.pcd")


def main(out):
    raw = open(SRC, "rb").read()
    at = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
    rec = np.frombuffer(raw, dtype="<f4", offset=at).reshape(-1, 4)
    tiles = []
    for k in range(15):
        t = rec.copy()
        t[:, 0] += np.float32(200.0 * k)
        tiles.append(t)
    data = np.concatenate(tiles)
    n = len(data)
    head = ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
            "FIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
            f"WIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA binary\n")
    with open(out, "wb") as f:
        f.write(head.encode())
        f.write(data.astype("<f4").tobytes())
    print(out, n)


if __name__ == "__main__":
    main(sys.argv[1])
