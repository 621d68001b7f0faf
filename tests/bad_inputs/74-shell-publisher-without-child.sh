#!/bin/sh
# the child frame is missing before the &
ros2 run tf2_ros static_transform_publisher 0 0 0 0 0 0 base_link &
