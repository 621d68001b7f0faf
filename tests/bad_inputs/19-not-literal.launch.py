from launch import LaunchDescription
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    z = LaunchConfiguration("lidar_z")
    return LaunchDescription([
        Node(
            package="tf2_ros",
            executable="static_transform_publisher",
            arguments=["0", "0", z, "0", "0", "0", "base_link", "lidar"],
        ),
    ])
