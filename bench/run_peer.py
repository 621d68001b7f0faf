#!/usr/bin/env python3
"""Python peer of `audit degeneracy` over a recorded run (issue 26 benchmark).

For every sensor_msgs/msg/PointCloud2 message of one topic of a bag, the same
per-scan work as the tool: decode x, y, z (offsets, datatypes, byte order,
row_step honoured; non-finite points dropped), voxel grid anchored at the
origin (one centroid per voxel, key floor(p / v): src/degeneracy/scene.rs),
normals by Open3D (`estimate_normals` with a radius search, or hybrid
radius + k nearest, oriented toward the sensor origin) with points that have
fewer than --min-neighbours within the radius dropped (scipy cKDTree counts,
as src/degeneracy/normals.rs drops them), H = sum a a^T and
M = sum J^T J (numpy), and the generalized eigenvalues of every detector
family (scipy.linalg.eigh): unnormalized, characteristic length l = 0.25, 1,
2.85, 10 m, block scaling, Jacobi, point displacement (solved about the
centroid). One line per scan on stdout; the totals (scans/s, points/s, peak
RSS) on stderr and, with --json, as one JSON object.

Readers: rosbags' AnyReader (ROS 1 .bag, rosbag2 folders, ROS 2 .mcap), or
with --reader mcap the `mcap` package's streaming reader (MCAP files only,
messages in file order, CDR decoded by rosbags). Both stream: one message is
held at a time.

Defaults as the tool's (src/tolerances.rs): radius 0.30 m
(RAW_NORMAL_RADIUS_M), 8 neighbours (RAW_MIN_NEIGHBOURS), no k limit, voxel
0.10 m (the paper's; the tool has no voxel unless --voxel is given: pass the
same value to both), thresholds of src/analysis/family.rs.

  /tmp/venv26/bin/python peer.py big.mcap --topic /points --voxel 0.1 --json peer.json
  /usr/bin/time -v /tmp/venv26/bin/python peer.py big.mcap ...   (peak memory as the benchmark reports it)
"""

import argparse
import json
import resource
import sys
import time

import numpy as np
from scipy.linalg import eigh
from scipy.spatial import cKDTree

ELLS = [0.25, 1.0, 2.85, 10.0]
THRESHOLDS = {"unnormalized": (0.04582, True), "l=0.25": (0.02157, True), "l=1": (0.04582, True),
              "l=2.85": (0.01462, True), "l=10": (0.001202, True), "block_scaling": (0.01221, True),
              "jacobi": (0.8619, False), "point_displacement": (1e-2, False)}
NP_TYPE = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}
PC2 = "sensor_msgs/msg/PointCloud2"


def decode_xyz(msg, with_normals=False):
    """x y z (float64, finite rows only) and normals when asked and present."""
    fields = {f.name: (f.offset, NP_TYPE[f.datatype]) for f in msg.fields}
    names = ["x", "y", "z"]
    if with_normals and all(f"normal_{c}" in fields for c in "xyz"):
        names += [f"normal_{c}" for c in "xyz"]
    bo = ">" if msg.is_bigendian else "<"
    dt = np.dtype({"names": names, "formats": [bo + fields[k][1] for k in names],
                   "offsets": [fields[k][0] for k in names], "itemsize": msg.point_step})
    data = memoryview(msg.data)
    h, w, rs = msg.height, msg.width, msg.row_step
    if h * w == 0:
        return np.zeros((0, 3)), None
    if rs == w * msg.point_step:
        rec = np.frombuffer(data, dtype=dt, count=h * w)
    else:
        rec = np.concatenate([np.frombuffer(data, dtype=dt, count=w, offset=r * rs) for r in range(h)])
    p = np.empty((len(rec), 3))
    for i, c in enumerate("xyz"):
        p[:, i] = rec[c]
    n = None
    if len(names) == 6:
        n = np.stack([rec[f"normal_{c}"].astype(np.float64) for c in "xyz"], axis=1)
    ok = np.isfinite(p).all(axis=1)
    if n is not None:
        ok &= np.isfinite(n).all(axis=1)
        n = n[ok]
    return p[ok], n


def voxel(p, v):
    """One centroid per voxel of the grid anchored at the origin."""
    if len(p) == 0:
        return p
    k = np.floor(p / v).astype(np.int64)
    k -= k.min(axis=0)
    span = k.max(axis=0) + 1
    key = (k[:, 0] * span[1] + k[:, 1]) * span[2] + k[:, 2]
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    out = np.empty((len(cnt), 3))
    for i in range(3):
        out[:, i] = np.bincount(inv, weights=p[:, i]) / cnt
    return out


def normals_open3d(p, radius, knn, min_nb, o3d):
    pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(p))
    param = (o3d.geometry.KDTreeSearchParamHybrid(radius=radius, max_nn=knn) if knn
             else o3d.geometry.KDTreeSearchParamRadius(radius=radius))
    pc.estimate_normals(search_param=param, fast_normal_computation=False)
    pc.orient_normals_towards_camera_location(np.zeros(3))
    n = np.asarray(pc.normals)
    cnt = cKDTree(p).query_ball_point(p, radius, return_length=True, workers=-1)
    keep = cnt >= min_nb  # with --knn the neighbourhood is min(count, k) >= min_nb iff count >= min_nb
    return p[keep], n[keep]


def normals_scipy(p, radius, knn, min_nb):
    """Fallback without Open3D: cKDTree neighbourhoods, batched numpy PCA."""
    tree = cKDTree(p)
    if knn:
        d, idx = tree.query(p, k=knn, distance_upper_bound=radius, workers=-1)
        valid = np.isfinite(d)
    else:
        lists = tree.query_ball_point(p, radius, workers=-1)
        m = max(len(x) for x in lists)
        idx = np.full((len(p), m), len(p))
        for i, x in enumerate(lists):
            idx[i, :len(x)] = x
        valid = idx < len(p)
    cnt = valid.sum(axis=1)
    keep = cnt >= min_nb
    pp = np.vstack([p, np.zeros(3)])
    off = pp[np.minimum(idx, len(p))] - p[:, None, :]
    off[~valid] = 0
    c = cnt[:, None]
    mean = off.sum(axis=1) / np.maximum(c, 1)
    cov = np.einsum("nki,nkj->nij", off, off) / np.maximum(c, 1)[:, :, None] - mean[:, :, None] * mean[:, None, :]
    w, v = np.linalg.eigh(cov[keep])
    n = v[:, :, 0]
    flip = np.einsum("ni,ni->n", n, -p[keep]) < 0
    n[flip] *= -1
    return p[keep], n


def families(p, n):
    a = np.hstack([np.cross(p, n), n])
    h = a.T @ a
    N = len(p)
    c = p.mean(axis=0)
    q = p - c
    ac = np.hstack([np.cross(q, n), n])
    hc = ac.T @ ac
    S = q.T @ q
    mc = np.zeros((6, 6))
    mc[:3, :3] = np.trace(S) * np.eye(3) - S
    mc[3:, 3:] = N * np.eye(3)
    out = {"unnormalized": np.linalg.eigvalsh(h)}
    for l in ELLS:
        out["l=%g" % l] = eigh(h, np.diag([l * l] * 3 + [1.0] * 3), eigvals_only=True)
    l2 = np.trace(h[:3, :3]) / np.trace(h[3:, 3:])
    out["block_scaling"] = eigh(h, np.diag([l2] * 3 + [1.0] * 3), eigvals_only=True)
    d = np.diag(h)
    out["jacobi"] = eigh(h, np.diag(np.maximum(d, 1e-12 * d.max())), eigvals_only=True)
    out["point_displacement"] = eigh(hc, mc, eigvals_only=True)
    counts = {k: int(np.sum(v / (N if THRESHOLDS[k][1] else 1.0) < THRESHOLDS[k][0])) for k, v in out.items()}
    return out, counts


def messages(path, topic, reader):
    """(log ns, msg) of `topic`, streamed."""
    if reader == "mcap":
        from mcap.reader import make_reader
        from rosbags.typesys import Stores, get_typestore
        store = get_typestore(Stores.ROS2_HUMBLE)
        with open(path, "rb") as f:
            for _, ch, m in make_reader(f).iter_messages(topics=[topic] if topic else None, log_time_order=False):
                if topic or ch.topic == first_pc2_topic_mcap(path):
                    yield m.log_time, store.deserialize_cdr(m.data, PC2)
        return
    from pathlib import Path
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore
    with AnyReader([Path(path)], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as r:
        conns = [c for c in r.connections if c.msgtype == PC2 and (topic is None or c.topic == topic)]
        topics = sorted({c.topic for c in conns})
        if not topic and len(topics) != 1:
            sys.exit(f"expected one PointCloud2 topic, found {topics}: give --topic")
        for c, t, raw in r.messages(connections=conns):
            yield t, r.deserialize(raw, c.msgtype)


def first_pc2_topic_mcap(path, _cache={}):
    if path not in _cache:
        from mcap.reader import make_reader
        with open(path, "rb") as f:
            s = make_reader(f).get_summary()
        t = sorted(ch.topic for ch in s.channels.values() if s.schemas[ch.schema_id].name == PC2)
        if len(t) != 1:
            sys.exit(f"expected one PointCloud2 topic, found {t}: give --topic")
        _cache[path] = t[0]
    return _cache[path]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bag")
    ap.add_argument("--topic")
    ap.add_argument("--reader", choices=["rosbags", "mcap"], default="rosbags")
    ap.add_argument("--voxel", type=float, default=0.1, help="voxel edge (m); 0: none")
    ap.add_argument("--radius", type=float, default=0.3)
    ap.add_argument("--knn", type=int, default=None)
    ap.add_argument("--min-neighbours", type=int, default=8)
    ap.add_argument("--normals", choices=["open3d", "scipy", "fields"], default="open3d",
                    help="fields: use the message's normal_x/y/z (no estimation)")
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument("--max-scans", type=int, default=None)
    ap.add_argument("--json", help="write the totals here")
    ap.add_argument("--quiet", action="store_true", help="no per-scan lines")
    a = ap.parse_args()
    o3d = None
    if a.normals == "open3d":
        import open3d as o3d  # noqa: F811
    t0 = time.perf_counter()
    scans = points = 0
    for k, (t, msg) in enumerate(messages(a.bag, a.topic, a.reader)):
        if k % a.every:
            continue
        if a.max_scans is not None and scans >= a.max_scans:
            break
        p, nf = decode_xyz(msg, with_normals=a.normals == "fields")
        points += len(p)
        scans += 1
        if a.normals == "fields":
            q, n = p, nf
        else:
            q = voxel(p, a.voxel) if a.voxel > 0 else p
            if a.normals == "open3d":
                q, n = normals_open3d(q, a.radius, a.knn, a.min_neighbours, o3d)
            else:
                q, n = normals_scipy(q, a.radius, a.knn, a.min_neighbours)
        if len(q) < 3:
            print(f"scan {k} t={t} points={len(p)} kept={len(q)}: too few points", flush=True)
            continue
        ev, counts = families(q, n)
        if not a.quiet:
            pd = " ".join("%.6e" % x for x in ev["point_displacement"])
            print(f"scan {k} t={t} points={len(p)} kept={len(q)} pd=[{pd}] counts=" +
                  ",".join(f"{key}:{c}" for key, c in counts.items()), flush=True)
    dt = time.perf_counter() - t0
    rss_mib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    tot = {"scans": scans, "points": points, "seconds": dt, "scans_per_s": scans / dt if dt else 0.0,
           "points_per_s": points / dt if dt else 0.0, "peak_rss_mib": rss_mib, "normals": a.normals,
           "voxel_m": a.voxel, "radius_m": a.radius, "knn": a.knn, "min_neighbours": a.min_neighbours,
           "reader": a.reader}
    print("peer: %d scans, %d points in %.3f s: %.2f scans/s, %.3g points/s, peak RSS %.0f MiB"
          % (scans, points, dt, tot["scans_per_s"], tot["points_per_s"], rss_mib), file=sys.stderr)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(tot, f, indent=1)


if __name__ == "__main__":
    main()
