"""`rclpy` stand-in of the panther-ops test lab's Python image (tests/lab/pyimage.py). NOT ROS 2.

The real images (husarion/panther, husarion/husarion-ugv: `FROM husarnet/ros:humble-ros-core`,
husarion/husarion_ugv_ros@2.2.2:docker/Dockerfile.hardware, husarion/panther-docker@2.1.2:
Dockerfile.hardware) have rclpy and geometry_msgs (REP 2001 ros_core). This stand-in has only
the part of rclpy's API a publisher needs, and shares its state with the image's `ros2`
stand-in (tests/lab/data/ros2-standin.sh) so `ros2 topic info` and the E-stop reset see it:

  rclpy.init(), rclpy.ok(), rclpy.shutdown(), rclpy.create_node(name, namespace=None)
  Node.create_publisher(msg_type, topic, qos_depth) -> Publisher, Node.destroy_node(),
  Node.get_name(); Publisher.publish(msg)

A publisher on the driver's ``<ns>/cmd_vel`` (the launch's ``namespace:=`` of PID 1, else
$ROBOT_NAMESPACE) is registered in ``$STATE/cmd_vel/<node>`` (its pid) until the node is
destroyed, rclpy shut down or the process ends; each message published there is appended to
``$STATE/cmd_vel.log`` as ``<uptime> <linear.x> <angular.z>``. The twist mux inputs of
husarion_ugv 2.3.2, ``<ns>/manual/cmd_vel`` and ``<ns>/autonomous/cmd_vel``, are registered and
logged the same way in ``manual_cmd_vel/``, ``manual_cmd_vel.log`` (and ``autonomous_...``); a
TwistStamped's twist is logged. Each publish also leaves ``$STATE/velocity/<node>``:
``<1 when the velocity is not zero, else 0> 0 <uptime>`` (rate 0: one message, at that time; the ros2
stand-in's E-stop reset rules read it: the newest message, within the controller's timeout). $STATE is
/var/lib/ros2-standin (``ROS2_STANDIN_STATE`` overrides it, for tests without a container).
Anything else of rclpy is missing here (AttributeError), not imitated.
"""

from __future__ import annotations

import atexit
import contextlib
import os
from typing import Any

_STATE = os.environ.get("ROS2_STANDIN_STATE", "/var/lib/ros2-standin")
_context = {"ok": False}
_nodes: list[Node] = []


def _driver_topic(name: str) -> str:
    ns = ""
    try:
        with open("/proc/1/cmdline", "rb") as f:
            for word in f.read().split(b"\0"):
                if word.startswith(b"namespace:="):
                    ns = word[len(b"namespace:="):].decode()
                    break
    except OSError:
        pass
    ns = (ns or os.environ.get("ROBOT_NAMESPACE", "")).strip("/")
    return f"/{ns}/{name}" if ns else f"/{name}"


def _uptime() -> str:
    try:
        with open("/proc/uptime") as f:
            return f.read().split()[0]
    except OSError:
        import time

        return f"{time.monotonic():.2f}"


def init(args: Any = None) -> None:
    if _context["ok"]:
        raise RuntimeError("Context.init() must only be called once")
    _context["ok"] = True


def ok() -> bool:
    return _context["ok"]


def shutdown() -> None:
    for node in list(_nodes):
        node.destroy_node()
    _context["ok"] = False


class Publisher:
    def __init__(self, node: Node, topic: str) -> None:
        self.node = node
        self.topic = topic if topic.startswith("/") else f"{node.namespace.rstrip('/')}/{topic}"
        self.registered = ""
        self.registry = ""
        for name in ("cmd_vel", "manual/cmd_vel", "autonomous/cmd_vel"):
            if self.topic == _driver_topic(name):
                self.registry = name.replace("/", "_")
                os.makedirs(os.path.join(_STATE, self.registry), exist_ok=True)
                self.registered = os.path.join(_STATE, self.registry, node.get_name())
                with open(self.registered, "w") as f:
                    f.write(f"{os.getpid()}\n")

    def publish(self, msg: Any) -> None:
        if not _context["ok"]:
            raise RuntimeError("publish after rclpy.shutdown()")
        if self.registered:
            twist = getattr(msg, "twist", msg)
            with open(os.path.join(_STATE, f"{self.registry}.log"), "a") as f:
                f.write(f"{_uptime()} {float(twist.linear.x)!r} {float(twist.angular.z)!r}\n")
            moving = any(float(v) != 0.0 for v in (twist.linear.x, twist.linear.y, twist.angular.z))
            os.makedirs(os.path.join(_STATE, "velocity"), exist_ok=True)
            with open(os.path.join(_STATE, "velocity", self.node.get_name()), "w") as f:
                f.write(f"{int(moving)} 0 {_uptime()}\n")

    def destroy(self) -> None:
        if self.registered:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self.registered)
            with contextlib.suppress(FileNotFoundError):
                os.unlink(os.path.join(_STATE, "velocity", self.node.get_name()))
            self.registered = ""


class Node:
    def __init__(self, name: str, namespace: str | None = None) -> None:
        if not _context["ok"]:
            raise RuntimeError("rclpy.init() has not been called")
        self._name = name
        self.namespace = "/" + (namespace or "").strip("/")
        self.publishers: list[Publisher] = []
        _nodes.append(self)

    def get_name(self) -> str:
        return self._name

    def create_publisher(self, msg_type: Any, topic: str, qos_profile: Any) -> Publisher:
        pub = Publisher(self, topic)
        self.publishers.append(pub)
        return pub

    def destroy_node(self) -> None:
        for pub in self.publishers:
            pub.destroy()
        self.publishers = []
        if self in _nodes:
            _nodes.remove(self)


def create_node(node_name: str, *, namespace: str | None = None) -> Node:
    return Node(node_name, namespace)


atexit.register(lambda: [p.destroy() for n in list(_nodes) for p in n.publishers])
