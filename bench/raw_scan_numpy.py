#!/usr/bin/env python3
"""numpy/scipy peer of `audit degeneracy RAW.pcd --estimate-normals --voxel 0.1`
(issue 16 benchmark): read the binary PCD (x y z intensity float32), voxel grid
0.1 m, PCA normals within 0.3 m from at least 8 points (cKDTree, vectorised
covariance of the offsets from each query point), oriented toward the origin,
H and M, scipy.linalg.eigh(H, M). Less work than `audit`, which also solves the
other metric families and the subspace.

    python3 bench/raw_scan_numpy.py RAW.pcd
"""
import sys

import numpy as np
from scipy.linalg import eigh
from scipy.spatial import cKDTree


def main(path):
    raw = open(path, "rb").read()
    at = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
    xyz = np.frombuffer(raw, dtype="<f4", offset=at).reshape(-1, 4)[:, :3].astype(np.float64)
    xyz = xyz[np.all(np.isfinite(xyz), axis=1)]
    keys = np.floor(xyz / 0.1).astype(np.int64)
    _, inv, cnt = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    inv = inv.reshape(-1)
    pts = np.stack([np.bincount(inv, weights=xyz[:, k]) / cnt for k in range(3)], axis=1)
    tree = cKDTree(pts)
    nbs = tree.query_ball_point(pts, 0.3, workers=-1)
    sizes = np.fromiter((len(b) for b in nbs), dtype=np.int64, count=len(nbs))
    flat = np.fromiter((i for b in nbs for i in b), dtype=np.int64, count=int(sizes.sum()))
    owner = np.repeat(np.arange(len(pts)), sizes)
    d = pts[flat] - pts[owner]
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    s1 = np.add.reduceat(d, starts, axis=0)
    s2 = np.add.reduceat(d[:, :, None] * d[:, None, :], starts, axis=0)
    nf = sizes[:, None]
    m = s1 / nf
    cov = s2 / nf[:, :, None] - m[:, :, None] * m[:, None, :]
    ok = sizes >= 8
    w, v = np.linalg.eigh(cov[ok])
    n = v[:, :, 0]
    p = pts[ok]
    flip = np.einsum("ij,ij->i", n, -p) < 0
    n[flip] = -n[flip]
    a = np.hstack([np.cross(p, n), n])
    h = a.T @ a
    c = p.sum(axis=0)
    s = p.T @ p
    mm = np.zeros((6, 6))
    mm[:3, :3] = np.trace(s) * np.eye(3) - s
    cx = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
    mm[:3, 3:] = cx
    mm[3:, :3] = -cx
    mm[3:, 3:] = len(p) * np.eye(3)
    print(len(p), eigh(h, mm, eigvals_only=True))


if __name__ == "__main__":
    main(sys.argv[1])
