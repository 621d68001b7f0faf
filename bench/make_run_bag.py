#!/usr/bin/env python3
"""A generated recorded run of any length, for the streaming-memory test and
the benchmark of issue 26 (not a committed fixture: it is made at run time).

A spinning LiDAR (BEAMS x COLUMNS rays, vertical field of view +-22.5 deg,
Ouster-like PointCloud2 layout: x y z float32, 4 pad, intensity float32,
t uint32 ns, reflectivity uint16, ring uint16, ambient uint16, 2 pad,
range uint32, point_step 48; organised, height = BEAMS, no-return cells NaN)
is ray-cast in a rectangular corridor 4 m wide and 3 m high with a back wall
and a far end wall, 1 cm Gaussian range noise, the robot advancing 0.5 m per
scan (so every scan differs and the corridor's degenerate translation comes
and goes with the walls' range). /tf_static (base_link -> lidar) and /tf
(odom -> base_link per scan) are written too.

  32k-point scans: --beams 32 --columns 1024 (1.5 MiB per scan)
  128k-point scans: --beams 128 --columns 1024 (6 MiB per scan)
  several GB: e.g. --beams 128 --scans 800 (4.8 GiB) or --beams 32 --scans 3000

Containers: --format mcap (one file, the mcap package's writer, chunks of
--chunk-mib, optional zstd), rosbag2-mcap or rosbag2-sqlite3 (rosbags'
writer, a folder with metadata.yaml), ros1 (rosbags' ROS 1 writer).

  /tmp/venv26/bin/python make_big_bag.py /tmp/big128.mcap --beams 128 --scans 800
Defaults are small (20 scans of 32k points, ~30 MiB).
"""

import argparse
import math
import shutil
import sys
import time
from pathlib import Path

import numpy as np
from rosbags.typesys import Stores, get_typestore

# scenes.py is shared with the run fixtures (tests/fixtures/run/).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "fixtures" / "run"))
import scenes as sc  # noqa: E402

PC2, TF = "sensor_msgs/msg/PointCloud2", "tf2_msgs/msg/TFMessage"
FIELDS = [("x", 7, 0), ("y", 7, 4), ("z", 7, 8), ("intensity", 7, 16), ("t", 6, 20), ("reflectivity", 4, 24),
          ("ring", 4, 26), ("ambient", 4, 28), ("range", 6, 32)]
DTYPE = np.dtype({"names": [f[0] for f in FIELDS],
                  "formats": ["<f4", "<f4", "<f4", "<f4", "<u4", "<u2", "<u2", "<u2", "<u4"],
                  "offsets": [f[2] for f in FIELDS], "itemsize": 48})
BOX = np.array([[-30.0, 400.0], [-2.0, 2.0], [-0.9, 2.1]])  # corridor about the LiDAR's height (m)
T0 = 1_700_000_000_000_000_000


def rays(beams, columns):
    el = np.deg2rad(np.linspace(-22.5, 22.5, beams))
    az = np.linspace(0, 2 * math.pi, columns, endpoint=False)
    e, a = np.meshgrid(el, az, indexing="ij")
    return np.stack([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)], axis=-1).reshape(-1, 3)


def cast(origin, dirs, rng, max_range=100.0):
    """Distances from `origin` (inside BOX) along unit `dirs` to the box walls."""
    with np.errstate(divide="ignore"):
        hi = (BOX[:, 1] - origin) / dirs
        lo = (BOX[:, 0] - origin) / dirs
    t = np.where(dirs > 0, hi, lo)
    t = np.where(dirs == 0, np.inf, t).min(axis=1)
    t = t + rng.normal(0, 0.01, len(t))
    t[t > max_range] = np.nan
    return t


def cloud(k, dirs, beams, columns, rng):
    origin = np.array([0.5 * k - 25.0, 0.3 * math.sin(0.1 * k), 0.0])
    t = cast(origin, dirs, rng)
    p = dirs * t[:, None]
    rec = np.zeros(len(p), dtype=DTYPE)
    rec["x"], rec["y"], rec["z"] = p[:, 0], p[:, 1], p[:, 2]
    rec["intensity"] = rng.uniform(0, 255, len(p))
    rec["t"] = np.tile(np.arange(columns, dtype=np.uint32) * (100_000_000 // columns), beams)
    rec["ring"] = np.repeat(np.arange(beams, dtype=np.uint16), columns)
    rec["range"] = np.nan_to_num(t * 1000).astype(np.uint32)
    return rec.tobytes(), origin


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--scans", type=int, default=20)
    ap.add_argument("--beams", type=int, default=32)
    ap.add_argument("--columns", type=int, default=1024)
    ap.add_argument("--format", choices=["mcap", "rosbag2-mcap", "rosbag2-sqlite3", "ros1"], default="mcap")
    ap.add_argument("--compression", choices=["none", "zstd"], default="none")
    ap.add_argument("--chunk-mib", type=float, default=4.0)
    ap.add_argument("--topic", default="/points")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    ros1 = a.format == "ros1"
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    if ros1 and TF not in store.types:
        from rosbags.typesys import get_types_from_msg
        store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", TF))
    t = store.types
    ser = store.serialize_ros1 if ros1 else store.serialize_cdr

    def hdr(ns, frame):
        st = t["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)
        return t["std_msgs/msg/Header"](seq=0, stamp=st, frame_id=frame) if ros1 else \
            t["std_msgs/msg/Header"](stamp=st, frame_id=frame)

    def tf(ns, parent, child, m):
        q, d = sc.quat_xyzw(m[:3, :3]), m[:3, 3]
        ts = t["geometry_msgs/msg/TransformStamped"](
            header=hdr(ns, parent), child_frame_id=child, transform=t["geometry_msgs/msg/Transform"](
                translation=t["geometry_msgs/msg/Vector3"](x=d[0], y=d[1], z=d[2]),
                rotation=t["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3])))
        return ser(t[TF](transforms=[ts]), TF)

    fields = [t["sensor_msgs/msg/PointField"](name=n, offset=o, datatype=d, count=1) for n, d, o in FIELDS]
    dirs = rays(a.beams, a.columns)
    rng = np.random.default_rng(a.seed)
    out = Path(a.out)
    writer, add, close = open_writer(out, a, ros1, store)
    add(T0, "/tf_static", TF, tf(T0, "base_link", "lidar", sc.T_BASE_LIDAR))
    t_start, total = time.perf_counter(), 0
    for k in range(a.scans):
        ns = T0 + k * 100_000_000
        data, origin = cloud(k, dirs, a.beams, a.columns, rng)
        msg = t[PC2](header=hdr(ns, "lidar"), height=a.beams, width=a.columns, fields=fields, is_bigendian=False,
                     point_step=48, row_step=48 * a.columns, data=np.frombuffer(data, np.uint8), is_dense=False)
        add(ns, "/tf", TF, tf(ns, "odom", "base_link", sc.base_pose(origin[0], origin[1])))
        raw = ser(msg, PC2)
        add(ns + 20_000_000, a.topic, PC2, raw)
        total += len(raw)
        if k % 50 == 0 or k == a.scans - 1:
            print(f"\r{k + 1}/{a.scans} scans, {total / 2**20:.0f} MiB, {time.perf_counter() - t_start:.0f} s",
                  end="", file=sys.stderr, flush=True)
    close()
    print(file=sys.stderr)


def open_writer(out, a, ros1, store):
    """(writer, add(log_ns, topic, type, bytes), close()) for the chosen container."""
    if a.format == "mcap":
        from mcap.writer import CompressionType, Writer
        f = open(out, "wb")
        w = Writer(f, chunk_size=int(a.chunk_mib * 2**20),
                   compression=CompressionType.ZSTD if a.compression == "zstd" else CompressionType.NONE)
        w.start(profile="ros2", library="make_big_bag.py")
        chans = {}

        def add(ns, topic, typ, data):
            if topic not in chans:
                sid = w.register_schema(name=typ, encoding="ros2msg",
                                        data=store.generate_msgdef(typ, ros_version=2)[0].encode())
                chans[topic] = w.register_channel(topic=topic, message_encoding="cdr", schema_id=sid)
            w.add_message(chans[topic], log_time=ns, publish_time=ns, data=data)

        def close():
            w.finish()
            f.close()
        return w, add, close
    if ros1:
        from rosbags.rosbag1 import Writer
        out.unlink(missing_ok=True)
        w = Writer(out)
        if a.compression == "zstd":
            sys.exit("ROS 1 bags have bz2 and lz4 chunks, not zstd")
    else:
        from rosbags.rosbag2 import StoragePlugin, Writer
        from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
        shutil.rmtree(out, ignore_errors=True)
        w = Writer(out, version=9, storage_plugin=StoragePlugin.MCAP if a.format == "rosbag2-mcap"
                   else StoragePlugin.SQLITE3)
        if a.compression == "zstd":
            w.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
    w.open()
    conns = {}

    def add(ns, topic, typ, data):
        if topic not in conns:
            conns[topic] = w.add_connection(topic, typ, typestore=store)
        w.write(conns[topic], ns, data)
    return w, add, w.close


if __name__ == "__main__":
    main()
