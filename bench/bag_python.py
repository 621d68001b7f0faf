#!/usr/bin/env python3
"""The Python peer of `audit BAG --frames` in bench/run_bag_bench.sh.

Reads /tf_static from a bare MCAP file with the `mcap` library's seeking reader
(it uses the summary's chunk index, so it skips chunks without /tf_static, as
`audit` does), decodes each TFMessage with rosbags' CDR deserializer and prints
one line per transform (parent, child, translation, quaternion x y z w).

    python bag_python.py BAG.mcap
"""

import sys

from mcap.reader import make_reader
from rosbags.typesys import Stores, get_typestore

TS = get_typestore(Stores.ROS2_HUMBLE)


def main():
    with open(sys.argv[1], 'rb') as f:
        reader = make_reader(f)
        for _schema, _channel, message in reader.iter_messages(topics=['/tf_static']):
            tf = TS.deserialize_cdr(message.data, 'tf2_msgs/msg/TFMessage')
            for t in tf.transforms:
                d, q = t.transform.translation, t.transform.rotation
                print(t.header.frame_id, t.child_frame_id, d.x, d.y, d.z, q.x, q.y, q.z, q.w)


if __name__ == '__main__':
    main()
