"""geometry_msgs/msg/Vector3, Twist and TwistStamped (with std_msgs/Header's stamp) as rclpy's generated
classes expose them (fields only)."""

from __future__ import annotations


class Vector3:
    def __init__(self, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> None:
        self.x, self.y, self.z = float(x), float(y), float(z)


class Twist:
    def __init__(self, linear: Vector3 | None = None, angular: Vector3 | None = None) -> None:
        self.linear = linear or Vector3()
        self.angular = angular or Vector3()


class Time:
    def __init__(self, sec: int = 0, nanosec: int = 0) -> None:
        self.sec, self.nanosec = int(sec), int(nanosec)


class Header:
    def __init__(self, stamp: Time | None = None, frame_id: str = "") -> None:
        self.stamp = stamp or Time()
        self.frame_id = frame_id


class TwistStamped:
    def __init__(self, header: Header | None = None, twist: Twist | None = None) -> None:
        self.header = header or Header()
        self.twist = twist or Twist()
