"""The robot's own fix topic: what `gps status` asks once the NMEA driver holds the port.

The NMEA driver (ros-drivers/nmea_navsat_driver) publishes a ``sensor_msgs/NavSatFix`` for
every GGA sentence it receives; that topic, not the port, tells whether the robot has a fix
(asked by :mod:`fix_echo`). Here: the topic's name, from compose.yaml, and the message as
``ros2 topic echo`` prints it, parsed (pure).

The topic, by how compose.yaml runs the driver (each from its source):

- ``launch_nmea_gps:=True`` on the driver (panther_ros 2.1.1, husarion_ugv 2.2): the node
  runs in the driver's namespace (bringup's ``namespace``, passed down by
  ``*_localization/launch/localization.launch.py``) with ``fix`` remapped to
  ``<device_namespace>/fix``: ``<ns>/gps/fix``. 2.1.1 declares ``device_namespace``
  (default ``gps``: husarion_ugv_ros@2.1.1:panther_localization/launch/nmea_navsat.launch.py);
  2.2 fixes it to ``gps`` (husarion_ugv_ros@2.2.2:husarion_ugv_localization/launch/nmea_navsat.launch.py,
  the same at 2.2.0). Relative here: resolved in the driver container against the
  inventory's namespace, else the driver's own (as the E-stop's commands are).
- the ``nmea-gps`` service, ``ros2 launch /husarion_utils/nmea_navsat.launch.py
  robot_namespace:=NS``: the node is named ``<device_namespace>`` (default ``gps``) in
  ``NS`` (default ``ROBOT_NAMESPACE``, else none) with ``fix`` remapped to ``~/fix``:
  ``/NS/gps/fix`` (husarion/nmea-gps-docker@1accbc32:husarion_utils/nmea_navsat.launch.py).
- the ``nmea-gps`` service, ``ros2 run nmea_navsat_driver nmea_socket_driver ... -r
  __ns:=/NS`` (another port): the node's own relative ``fix``, so ``/NS/fix``
  (ros-drivers/nmea_navsat_driver@2.0.1:src/libnmea_navsat_driver/driver.py, branch ros2,
  which the image builds).

The message as ``ros2 topic echo`` prints it (YAML, ``rosidl_runtime_py.message_to_yaml``,
then ``---``), parsed here. ``status.status`` (NavSatStatus): -1 no fix, 0 fix, 1 SBAS fix,
2 GBAS fix; nmea_navsat_driver sets it from GGA's fix quality (0 -> -1, 1 -> 0, 2 -> 1,
4/5/9 -> 2, any other -> -1) and the altitude from GGA's altitude plus geoid separation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import yaml

from panther_ops.core.parse.ros_names import RosNameError, namespace, topic_name
from panther_ops.core.robot.launchcmd import shell_tokens
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.stack import Family
from panther_ops.core.yaml.render import Block

MSG_TYPE = "sensor_msgs/msg/NavSatFix"
DEVICE_NAMESPACE = "gps"
"""The NMEA launch files' ``device_namespace`` default (the node's sub-namespace of ``fix``)."""
STATUS = {-1: "no fix", 0: "fix", 1: "SBAS fix", 2: "GBAS fix"}
"""sensor_msgs/NavSatStatus ``status`` values."""

class TopicError(ValueError):
    """compose.yaml runs the NMEA driver under a name that is not a ROS name."""


def _words(command: Any) -> list[str]:
    if isinstance(command, Block):
        command = command.text
    if isinstance(command, list):
        return [str(w) for w in command]
    if isinstance(command, str):
        return [t.value for t in shell_tokens(command)]
    return []


def _assigned(words: list[str], key: str) -> str | None:
    """The last ``key:=value`` among ``words`` (as ROS 2 reads its arguments)."""
    found = None
    for w in words:
        if w.startswith(f"{key}:="):
            found = w[len(key) + 2:]
    return found


def _join(ns: str, *parts: str) -> str:
    ns = ns.strip("/")
    return "/" + "/".join(x for x in (ns, *parts) if x)


def service_topic(service: dict[str, Any]) -> str:
    """The fix topic of the ``nmea-gps`` service (its compose settings, ``command`` read)."""
    words = _words(service.get("command"))
    if "run" in words[:2]:  # the socket driver node itself: its relative `fix`
        return topic_name(_join(namespace(_assigned(words, "__ns") or ""), "fix"))
    env = service.get("environment")
    default = ""
    if isinstance(env, dict):
        default = str(env.get("ROBOT_NAMESPACE") or "")
    elif isinstance(env, list):
        default = next((str(e).split("=", 1)[1] for e in env if str(e).startswith("ROBOT_NAMESPACE=")), "")
    asked = _assigned(words, "robot_namespace")
    device = _assigned(words, "device_namespace") or DEVICE_NAMESPACE
    return topic_name(_join(namespace(default if asked is None else asked), namespace(device), "fix"))


def fix_topic(cfg: RobotConfig, mode: str, service: str) -> str:
    """The fix topic for driver ``mode`` (``service``: absolute; ``argument``: relative to the
    driver's namespace). TopicError when compose.yaml names something that is not ROS's."""
    try:
        if mode == "service":
            return service_topic(cfg.compose.service(service))
        device = DEVICE_NAMESPACE
        if cfg.stack.family is Family.PANTHER_ROS:  # 2.1.1 declares it; 2.2 fixes it to gps
            device = str(cfg.compose.args.get("device_namespace") or DEVICE_NAMESPACE)
        return topic_name(f"{namespace(device)}/fix")
    except RosNameError as exc:
        raise TopicError(f"compose.yaml's NMEA driver ({service}): {exc}") from None


@dataclass(frozen=True)
class NavSatFix:
    """One sensor_msgs/NavSatFix, as `ros2 topic echo` printed it."""

    lat: float
    lon: float
    altitude_m: float
    status: int
    service: int | None
    frame_id: str | None
    stamp: float | None

    @property
    def has_fix(self) -> bool:
        return self.status >= 0 and math.isfinite(self.lat) and math.isfinite(self.lon)

    def to_json(self) -> dict[str, Any]:
        def num(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {"lat": num(self.lat), "lon": num(self.lon), "altitude_m": num(self.altitude_m),
                "status": self.status, "fix": STATUS.get(self.status, "unknown"), "service": self.service,
                "frame_id": self.frame_id, "stamp": self.stamp}


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def parse_fix(text: str) -> NavSatFix | None:
    """The first NavSatFix in ``ros2 topic echo``'s output (other lines, e.g. its warnings,
    skipped); None when there is none."""
    lines = text.splitlines()
    try:
        start = lines.index("header:")
    except ValueError:
        return None
    end = next((i for i in range(start, len(lines)) if lines[i].strip() == "---"), len(lines))
    try:
        doc = yaml.safe_load("\n".join(lines[start:end]))
    except yaml.YAMLError:
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("status"), dict):
        return None
    status = doc["status"].get("status")
    lat, lon, alt = (_number(doc.get(k)) for k in ("latitude", "longitude", "altitude"))
    if isinstance(status, bool) or not isinstance(status, int) or lat is None or lon is None or alt is None:
        return None
    service = doc["status"].get("service")
    header = doc.get("header")
    header = header if isinstance(header, dict) else {}
    stamp = header.get("stamp")
    stamp = stamp if isinstance(stamp, dict) else {}
    sec, nsec = stamp.get("sec"), stamp.get("nanosec")
    when = sec + nsec / 1e9 if isinstance(sec, int) and isinstance(nsec, int) else None
    frame = header.get("frame_id")
    return NavSatFix(lat, lon, alt, status, service if isinstance(service, int) else None,
                     None if frame is None else str(frame), when)
