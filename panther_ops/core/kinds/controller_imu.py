"""The IMU broadcaster of a controller file: does it read the sensor the robot's URDF declares?

Facts (upstream, at each supported tag):

- The URDF names the IMU sensor ``${ns}imu`` with ``ns = namespace + "/"`` (or ``""``):
  panther_ros@2.0.4 and @2.1.1:panther_description/urdf/panther_macro.urdf.xacro,
  husarion_ugv_ros@2.2.0 and @2.2.2:husarion_ugv_description/urdf/panther/panther_macro.urdf.xacro
  (and lynx/lynx_macro.urdf.xacro). bringup spawns ``imu_broadcaster`` on every robot
  (``*_controller/launch/controller.launch.py``).
- panther_ros 2.0.x-2.1.x and husarion_ugv 2.2.0 build Husarion's fork of ros2_controllers
  (``panther/panther_hardware.repos``, ``husarion_ugv/hardware_deps.repos`` at 2.2.0:
  husarion/ros2_controllers@9da42a07). Its broadcaster
  (imu_sensor_broadcaster/src/imu_sensor_broadcaster.cpp) reads
  ``<node namespace without '/'>/`` + ``sensor_name`` when ``use_namespace_as_sensor_name_prefix``
  is true, else ``sensor_name`` as written; it always prefixes ``frame_id`` with the
  namespace. The stock files say ``use_namespace_as_sensor_name_prefix: true``,
  ``sensor_name: imu``, ``frame_id: imu_link``.
- husarion_ugv 2.2.1+ drops the fork (husarion_ugv_ros@2.2.2:husarion_ugv/hardware_deps.repos):
  ``sensor_name`` and ``frame_id`` are used as written, after controller.launch.py replaced
  ``<namespace>/`` by ``<ns>/`` or ``""`` in the whole file (ReplaceString,
  husarion_ugv_ros@2.2.2:husarion_ugv_controller/launch/controller.launch.py). The stock files
  say ``sensor_name: <namespace>/imu``, ``frame_id: <namespace>/imu_link``.

- husarion_ugv 2.3.2 writes ``static_covariance_orientation: <static_covariance_orientation>``
  in the stock files, and controller.launch.py replaces that placeholder with a list picked by
  ``use_madgwick_filter`` (husarion_ugv_ros@2.3.2:husarion_ugv_controller/launch/
  controller.launch.py, ReplaceString); no earlier release replaces it, so there the text is a
  string where the broadcaster wants a list of doubles (`covariance_findings`).

A broadcaster that reads another name than the URDF's finds no such state interfaces and
does not start: no ``imu/data``, and the EKF runs without the IMU. `imu_findings` says so
(an error: the file breaks the IMU on this robot), or warns when the file works only as
long as the robot has no namespace, or when the IMU messages would name a frame that TF
does not have.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.stack import Stack

FLAG = "use_namespace_as_sensor_name_prefix"
PLACEHOLDER = "<namespace>/"
COVARIANCE = "static_covariance_orientation"
COVARIANCE_PLACEHOLDER = "<static_covariance_orientation>"
COVARIANCE_PLACEHOLDER_SINCE = (2, 3, 2)
"""The first release whose controller.launch.py fills `COVARIANCE_PLACEHOLDER`."""
FORK_UNTIL = (2, 2, 0)
"""The last version that builds husarion/ros2_controllers (the prefix flag)."""


@dataclass
class ImuFindings:
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    hint: str | None = None


def _params(plain: dict[str, Any]) -> tuple[str, dict[str, Any]] | None:
    for top, body in plain.items():
        if isinstance(body, dict) and isinstance(body.get("imu_broadcaster"), dict):
            params = body["imu_broadcaster"].get("ros__parameters")
            if isinstance(params, dict):
                return f"{top}.imu_broadcaster.ros__parameters", params
    return None


def stock_form(stack: Stack) -> str:
    """What the stock file of ``stack`` writes, as a hint."""
    if stack.version <= FORK_UNTIL:
        return f"{FLAG}: true with sensor_name: imu, as the stock file of {stack.label()}"
    return f"sensor_name: {PLACEHOLDER}imu and frame_id: {PLACEHOLDER}imu_link, as the stock file of {stack.label()}"


def _read(stack: Stack, params: dict[str, Any], ns: str) -> tuple[str, str | None]:
    """The sensor name and frame id the broadcaster uses on ``stack`` under namespace ``ns``."""
    sensor, frame = str(params.get("sensor_name", "")), params.get("frame_id")
    prefix = f"{ns}/" if ns else ""
    if stack.version <= FORK_UNTIL:
        read = (prefix if params.get(FLAG) is True else "") + sensor
        return read, (prefix + frame) if isinstance(frame, str) else None
    read = sensor.replace(PLACEHOLDER, prefix)
    return read, frame.replace(PLACEHOLDER, prefix) if isinstance(frame, str) else None


def imu_findings(plain: dict[str, Any], stack: Stack, namespace: str | None) -> ImuFindings:
    """What the file's IMU broadcaster does on ``stack`` with the driver's ``namespace``
    (``""``: none; None: not known, then only what breaks under any namespace is an error)."""
    out = ImuFindings()
    found = _params(plain)
    if found is None:
        return out
    where, params = found
    sensor = params.get("sensor_name")
    if not isinstance(sensor, str) or not sensor:
        out.errors.append(f"{where}.sensor_name={sensor!r}: the IMU broadcaster needs the IMU's sensor name "
                          f"(the broadcaster refuses an empty one)")
        out.hint = stock_form(stack)
        return out
    covariance_findings(where, params, stack, out)
    ns = (namespace or "").strip("/")
    read, frame = _read(stack, params, ns)
    fork = stack.version <= FORK_UNTIL
    works_bare = _read(stack, params, "")[0] == "imu"
    works_named = _read(stack, params, "ns")[0] == "ns/imu"
    if fork and "<namespace>" in sensor:
        out.errors.append(f"{where}.sensor_name={sensor!r}: {stack.label()} does not replace '<namespace>' "
                          f"(husarion_ugv 2.2.1+ does): the IMU broadcaster would look for a sensor "
                          f"named {read!r} and not start")
    elif namespace is not None and read != (expected := f"{ns}/imu" if ns else "imu"):
        out.errors.append(
            f"{where}: the IMU broadcaster would read sensor {read!r}, but on this robot (namespace "
            f"{ns or 'none'}) the URDF names the IMU {expected!r} (${{ns}}imu): the IMU would not start")
    elif namespace is None and not works_bare and not works_named:
        out.errors.append(f"{where}: the IMU broadcaster would read sensor {read!r}, but the URDF names the IMU "
                          f"'imu' (or '<ns>/imu' under a namespace): the IMU would not start")
    elif not ns and works_bare and not works_named:
        named = _read(stack, params, "ns")[0].replace("ns/", "<ns>/", 1)
        out.warnings.append(f"{where}: works only while the robot has no namespace: with one, the IMU broadcaster "
                            f"reads {named!r} but the URDF names the IMU '<ns>/imu'")
    if out.errors:
        out.hint = stock_form(stack)
        return out
    if frame is not None and ns and not fork and not frame.startswith(f"{ns}/"):
        out.warnings.append(
            f"{where}.frame_id={params.get('frame_id')!r}: the IMU messages would name frame {frame!r}, "
            f"but TF has the robot's frames under {ns}/ (robot_state_publisher frame_prefix): write "
            f"{PLACEHOLDER}{params.get('frame_id')}")
    if fork and isinstance(params.get("frame_id"), str) and "<namespace>" in params["frame_id"]:
        out.warnings.append(f"{where}.frame_id={params['frame_id']!r}: {stack.label()} prefixes the frame with "
                            f"the namespace itself and does not replace '<namespace>'")
    return out


def covariance_findings(where: str, params: dict[str, Any], stack: Stack, out: ImuFindings) -> None:
    """An error when the orientation covariance is text the release does not replace by a list."""
    value = params.get(COVARIANCE)
    if not isinstance(value, str):
        return
    if value == COVARIANCE_PLACEHOLDER and stack.version >= COVARIANCE_PLACEHOLDER_SINCE:
        return
    filled = ".".join(map(str, COVARIANCE_PLACEHOLDER_SINCE))
    out.errors.append(f"{where}.{COVARIANCE}={value!r}: the IMU broadcaster wants a list of 9 numbers; "
                      + (f"only {COVARIANCE_PLACEHOLDER} is replaced by one at launch on {stack.label()}"
                         if stack.version >= COVARIANCE_PLACEHOLDER_SINCE else
                         f"{stack.label()} replaces no placeholder here (husarion_ugv {filled}+ fills "
                         f"{COVARIANCE_PLACEHOLDER})"))
    out.hint = "e.g. [1.8e-3, 0.0, 0.0, 0.0, 1.8e-3, 0.0, 0.0, 0.0, 1.8e-3]"
