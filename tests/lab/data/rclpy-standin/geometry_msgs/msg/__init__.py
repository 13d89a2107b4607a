"""geometry_msgs/msg/Vector3 and Twist as rclpy's generated classes expose them (fields only)."""

from __future__ import annotations


class Vector3:
    def __init__(self, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> None:
        self.x, self.y, self.z = float(x), float(y), float(z)


class Twist:
    def __init__(self, linear: Vector3 | None = None, angular: Vector3 | None = None) -> None:
        self.linear = linear or Vector3()
        self.angular = angular or Vector3()
