"""The detector on numpy arrays: float64 and float32, read in place, against
the generalized eigenproblem solved by numpy/scipy from the same points."""

import os

import numpy as np
import pytest
from scipy.linalg import eigh

import extrinsic_audit as ea
from extrinsic_audit import _rows
from conftest import FIXTURES


def tunnel(rings=60, per_ring=36, radius=2.85):
    """The paper's circular tunnel about z, exact radial normals."""
    a = np.repeat(np.arange(per_ring) * 2 * np.pi / per_ring, 1)[None, :].repeat(rings, 0)
    z = (-3.0 + 0.1 * np.arange(rings))[:, None].repeat(per_ring, 1)
    xyz = np.stack([radius * np.cos(a), radius * np.sin(a), z], -1).reshape(-1, 3)
    n = np.stack([-np.cos(a), -np.sin(a), np.zeros_like(a)], -1).reshape(-1, 3)
    return xyz, n


def room(n=3000, seed=3):
    """Points on five planes of different orientations: nothing degenerate."""
    rng = np.random.default_rng(seed)
    normals = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [0, 1, 1]], float)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    pts, nrm = [], []
    for k, nk in enumerate(normals):
        u = np.cross(nk, [0.3, 0.5, 0.8])
        u /= np.linalg.norm(u)
        v = np.cross(nk, u)
        s = rng.uniform(-4, 4, (n // 5, 2))
        pts.append(3.0 * nk + (k - 2) * 0.4 + s[:, :1] * u + s[:, 1:] * v)
        nrm.append(np.repeat(nk[None], n // 5, 0))
    return np.vstack(pts), np.vstack(nrm)


def h_and_m(p, n):
    """H = sum a a^T with a = [p x n; n]; M = sum J^T J with J = [-[p]x, I]."""
    a = np.hstack([np.cross(p, n), n])
    h = a.T @ a
    m = np.zeros((6, 6))
    for q in p:
        px = np.array([[0, -q[2], q[1]], [q[2], 0, -q[0]], [-q[1], q[0], 0]])
        j = np.hstack([-px, np.eye(3)])
        m += j.T @ j
    return h, m


def test_point_displacement_eigenvalues_as_scipy():
    p, n = room()
    rep = ea.degeneracy(p, n)
    assert rep.points == len(p)
    h, m = h_and_m(p, n)
    pd = rep.family("point_displacement")
    np.testing.assert_allclose(pd.eigenvalues, eigh(h, m, eigvals_only=True), rtol=1e-9,
                               atol=1e-12)
    assert pd.degenerate_count == 0
    assert not rep.footprint.any()


def test_tunnel_closed_form():
    xyz, n = tunnel()
    rep = ea.degeneracy(xyz, n)
    # On the axis, the rotation about z and the translation along it.
    assert rep.family("point_displacement").degenerate_count == 2
    assert rep.footprint.tolist() == [False, False, True, False, False, True]
    assert rep.to_dict()["footprint"] == rep.footprint.tolist()


def test_float32_f64_views_and_copies_agree():
    p, n = room()
    want = ea.degeneracy(p, n).to_dict()
    # float32: read in place as float32, the numbers those of the rounded points.
    p32, n32 = p.astype(np.float32), n.astype(np.float32)
    assert _rows(p32, "points") is p32
    got32 = ea.degeneracy(p32, n32)
    h, m = h_and_m(p32.astype(np.float64), n32.astype(np.float64))
    np.testing.assert_allclose(got32.family("point_displacement").eigenvalues,
                               eigh(h, m, eigvals_only=True), rtol=1e-6)
    # A contiguous view of rows: no copy.
    big, bign = np.vstack([p, p]), np.vstack([n, n])
    view, nview = big[: len(p)], bign[: len(p)]
    assert view.base is big and view.flags.c_contiguous
    assert _rows(view, "points") is view
    assert ea.degeneracy(view, nview).to_dict() == want
    # Not contiguous (every other row; three columns of six): copied once,
    # same answer.
    strided = np.repeat(p, 2, axis=0)[::2]
    assert not strided.flags.c_contiguous
    assert not np.shares_memory(_rows(strided, "points"), strided)
    six = np.hstack([p, n])
    assert not six[:, :3].flags.c_contiguous
    assert ea.degeneracy(strided, six[:, 3:]).to_dict() == want
    # A Fortran-ordered array and a list of lists too.
    assert ea.degeneracy(np.asfortranarray(p), n.tolist()).to_dict() == want


def test_the_native_side_refuses_rather_than_copies():
    p, n = room(500)
    with pytest.raises(ea.UsageError, match="C-contiguous"):
        ea._native.degeneracy(p[::2], None, None, ea._detector_args(*([None] * 3), False,
                                                                     *([None] * 6)))


def test_frame_change_moves_unnormalized_not_point_displacement():
    p, n = room()
    T = np.eye(4)
    T[:3, 3] = [0.5, -1.0, 2.0]  # the body frame 2.3 m away
    a, b = ea.degeneracy(p, n), ea.degeneracy(p, n, frame=T)
    np.testing.assert_allclose(a.family("point_displacement").eigenvalues,
                               b.family("point_displacement").eigenvalues, rtol=1e-9)
    ua, ub = a.family("unnormalized").eigenvalues, b.family("unnormalized").eigenvalues
    assert np.max(np.abs(ua - ub) / ua) > 0.01
    # Points re-expressed by numpy: p' = R^T (p - d).
    c = ea.degeneracy(p - T[:3, 3], n)
    np.testing.assert_allclose(c.family("unnormalized").eigenvalues, ub, rtol=1e-9)


def test_weights_scale_h_and_m():
    p, n = room(1000)
    w = np.full(len(p), 2.0)
    a, b = ea.degeneracy(p, n), ea.degeneracy(p, n, w)
    np.testing.assert_allclose(a.family("point_displacement").eigenvalues,
                               b.family("point_displacement").eigenvalues, rtol=1e-12)


def test_bad_arrays_are_usage_errors():
    p, n = room(500)
    with pytest.raises(ea.UsageError) as e:
        ea.degeneracy(p, n[1:])
    assert e.value.code == "usage" and "per point" in e.value.message
    with pytest.raises(ea.UsageError, match=r"\(N, 3\)"):
        ea.degeneracy(p[:, :2])
    with pytest.raises(ea.UsageError, match="frame"):
        ea.degeneracy(p, n, frame=np.eye(3))
    with pytest.raises(ea.UsageError, match="tau"):
        ea.degeneracy(p, n, tau=-1.0)


def test_raw_points_get_normals_and_a_scan_file():
    path = os.path.join(FIXTURES, "detector", "tunnel_small.csv")
    rep = ea.degeneracy_scan(path)
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=0 if _numeric(path) else 1)
    assert rep.points == len(data)
    got = ea.degeneracy(np.ascontiguousarray(data[:, :3]), np.ascontiguousarray(data[:, 3:6]))
    np.testing.assert_array_equal(got.family("point_displacement").eigenvalues,
                                  rep.family("point_displacement").eigenvalues)
    # Without normals: estimated (PCA within the radius), then the same analysis.
    xyz, _ = tunnel(rings=40, per_ring=72)
    raw = ea.degeneracy(xyz, radius=0.5)
    assert raw["normals"]["kept"] > 0
    assert raw.family("point_displacement").degenerate_count == 2


def _numeric(path):
    with open(path) as f:
        first = f.readline()
    return first[:1].lstrip("-").isdigit()
