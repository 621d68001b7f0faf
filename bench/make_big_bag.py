#!/usr/bin/env python3
"""Write a large MCAP bag for the bag-reading benchmark (bench/run_bag_bench.sh).

/robot_description is absent; /tf_static (two transforms, CDR by rosbags) is the
first message, so it sits in the first chunk; then SIZE_MB of /points messages
(random bytes, 1 MiB each, declared sensor_msgs/msg/PointCloud2 but never
decoded by the reader) in uncompressed 4 MiB chunks, and a /tf message every
50 /points messages so that /tf spans the whole file.

    python make_big_bag.py OUT.mcap SIZE_MB
"""

import math
import os
import sys

from mcap.writer import CompressionType, Writer
from rosbags.typesys import Stores, get_typestore

TS = get_typestore(Stores.ROS2_HUMBLE)
T = TS.types


def tf(transforms, sec):
    items = [
        T['geometry_msgs/msg/TransformStamped'](
            header=T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=sec, nanosec=0), frame_id=p),
            child_frame_id=c,
            transform=T['geometry_msgs/msg/Transform'](
                translation=T['geometry_msgs/msg/Vector3'](x=d[0], y=d[1], z=d[2]),
                rotation=T['geometry_msgs/msg/Quaternion'](x=q[0], y=q[1], z=q[2], w=q[3])))
        for p, c, d, q in transforms
    ]
    return TS.serialize_cdr(T['tf2_msgs/msg/TFMessage'](transforms=items), 'tf2_msgs/msg/TFMessage')


def main():
    out, size_mb = sys.argv[1], int(sys.argv[2])
    s = math.sin(0.05 / 2)
    static = tf([('base_link', 'imu_link', [0.1, -0.02, 0.3], [0, 0, 0, 1]),
                 ('base_link', 'lidar', [0.52, 0.01, 1.19], [0, 0, s, math.cos(0.05 / 2)])], 0)
    with open(out, 'wb') as f:
        w = Writer(f, chunk_size=4 << 20, compression=CompressionType.NONE)
        w.start(profile='ros2', library='make_big_bag.py')
        ch = {}
        for topic, typ in [('/tf_static', 'tf2_msgs/msg/TFMessage'), ('/tf', 'tf2_msgs/msg/TFMessage'),
                           ('/points', 'sensor_msgs/msg/PointCloud2')]:
            sid = w.register_schema(name=typ, encoding='ros2msg', data=b'')
            ch[topic] = w.register_channel(topic=topic, message_encoding='cdr', schema_id=sid)
        w.add_message(ch['/tf_static'], log_time=10**9, publish_time=10**9, data=static)
        blob = os.urandom(1 << 20)
        for i in range(size_mb):
            t = 10**9 + (i + 1) * 10**8
            w.add_message(ch['/points'], log_time=t, publish_time=t, data=blob)
            if i % 50 == 0:
                moving = tf([('odom', 'base_link', [i * 0.01, 0, 0], [0, 0, 0, 1])], i)
                w.add_message(ch['/tf'], log_time=t, publish_time=t, data=moving)
        w.finish()


if __name__ == '__main__':
    main()
