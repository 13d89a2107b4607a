"""What the ROS 2 CLI prints about the E-stop, parsed (pure functions of the text).

The robot runs several ROS 2 commands in one go; each one's output comes after a marker
line ``@@<action>`` and is followed by ``@@exit <status>`` (see :mod:`calls`); the sections
and the engine's stream are split by the shared engine
(:mod:`panther_ops.core.containers.exec_output`, re-exported here).
"""

from __future__ import annotations

import re

from panther_ops.core.containers.exec_output import MARK, Answers, Section, docker_stream, split

__all__ = ["MARK", "Answers", "Section", "docker_stream", "e_stop_state", "muxed", "publishers", "split",
           "trigger_response"]

_RESPONSE = re.compile(r"Trigger_Response\(success=(True|False), message=(['\"])(.*)\2\)\s*$", re.M)
_DATA = re.compile(r"^data:\s*(true|false)\s*$", re.M | re.I)


def e_stop_state(text: str) -> bool | None:
    """``ros2 topic echo --once .../hardware/e_stop`` (std_msgs/Bool): True = triggered."""
    m = _DATA.search(text)
    return None if m is None else m.group(1).lower() == "true"


def trigger_response(text: str) -> tuple[bool, str] | None:
    """``ros2 service call ... std_srvs/srv/Trigger``: (success, message), None without one."""
    found = _RESPONSE.findall(text)
    if not found:
        return None
    success, _, message = found[-1]
    return success == "True", message


def publishers(text: str) -> list[str] | None:
    """``ros2 topic info -v``: the publishing nodes (full names), None when it is not that."""
    if "Publisher count:" not in text:
        return None
    head = text.split("Subscription count:", 1)[0]
    nodes: list[str] = []
    name: str | None = None
    for raw in head.splitlines():
        line = raw.strip()
        if line.startswith("Node name:"):
            name = line.split(":", 1)[1].strip()
        elif line.startswith("Node namespace:") and name is not None:
            ns = line.split(":", 1)[1].strip().rstrip("/")
            nodes.append(f"{ns}/{name}" if ns else f"/{name}")
            name = None
    if name is not None:
        nodes.append(f"/{name}")
    return nodes


MUX = "twist_mux_controller"
"""husarion_ugv 2.3.2's chainable twist mux: it subscribes cmd_vel and the other velocity inputs
(husarion_ugv_ros@2.3.2:husarion_ugv_controller/config/WH01_controller.yaml, ROS_API.md)."""


def muxed(text: str) -> bool:
    """``ros2 topic info -v <ns>/cmd_vel``: whether the twist mux subscribes it (husarion_ugv 2.3.2)."""
    if "Subscription count:" not in text:
        return False
    tail = text.split("Subscription count:", 1)[1]
    return any(line.strip() == f"Node name: {MUX}" for line in tail.splitlines())
