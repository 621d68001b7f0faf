#!/usr/bin/env python3
"""The numpy/scipy peer of `audit degeneracy FILE.ply` as a whole process.

Reads a binary little-endian PLY whose vertices are exactly the double
properties x y z nx ny nz (what `examples/write_cloud.rs` writes), assembles
H = sum a a^T with a = [p x n; n] and M from the moments (N, sum p, sum p p^T),
solves scipy.linalg.eigh(H, M) and prints the generalized eigenvalues. It does
less than `audit degeneracy` (one metric family instead of six, no subspace, no
checks on the normals), so the ratio favours it slightly.

    python bench/degeneracy_numpy.py FILE.ply
"""
import sys
import numpy as np
import scipy.linalg


def read_ply(path):
    with open(path, "rb") as f:
        n, props = None, []
        while True:
            line = f.readline()
            if not line:
                sys.exit("no end_header")
            t = line.split()
            if t[:2] == [b"element", b"vertex"]:
                n = int(t[2])
            elif t[:1] == [b"property"]:
                props.append((t[1], t[2]))
            elif t[:1] == [b"format"] and t[1] != b"binary_little_endian":
                sys.exit("expected binary_little_endian")
            elif t[:1] == [b"end_header"]:
                break
        want = [(b"double", k) for k in (b"x", b"y", b"z", b"nx", b"ny", b"nz")]
        if props != want:
            sys.exit("expected double x y z nx ny nz")
        return np.fromfile(f, dtype="<f8", count=6 * n).reshape(n, 6)


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def main():
    X = read_ply(sys.argv[1])
    P, N = X[:, :3], X[:, 3:]
    A = np.hstack([np.cross(P, N), N])
    H = A.T @ A
    s = P.sum(axis=0)
    S = P.T @ P
    M = np.zeros((6, 6))
    M[:3, :3] = np.trace(S) * np.eye(3) - S
    M[:3, 3:] = skew(s)
    M[3:, :3] = -skew(s)
    M[3:, 3:] = len(P) * np.eye(3)
    print(scipy.linalg.eigh(H, M, eigvals_only=True))


if __name__ == "__main__":
    main()
