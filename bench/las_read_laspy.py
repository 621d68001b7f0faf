#!/usr/bin/env python3
"""The laspy peer of `read_xyz FILE` (bench/las_read.sh): read a LAS or LAZ
(lazrs backend), form x, y, z in f64 (X * scale + offset), print the count and
the coordinate sums."""
import sys

import laspy
import numpy as np

las = laspy.read(sys.argv[1])
x, y, z = (np.asarray(las.x), np.asarray(las.y), np.asarray(las.z))
print(len(x), x.sum(), y.sum(), z.sum())
