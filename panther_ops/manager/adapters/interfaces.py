"""The ROS 2 interfaces of each Panther stack: message package, topics and service names.

One table for everything that talks to a robot's ROS graph: the manager's ROS 2 adapter
(`adapters/ros2.py`), and, on the operator side, `panther-ops lights test` and `manager deploy`
(which passes the robot's version to the deployed manager with ``--stack``). Pure data, no ROS.

* panther_ros 2.0.x: ``panther_msgs``; battery ``battery``; motor drivers
  ``driver/motor_controllers_state`` (DriverState: front, rear); lights service
  ``lights/controller/set/animation``.
* panther_ros 2.1.x: ``panther_msgs``; ``battery/battery_status``;
  ``hardware/motor_controllers_state`` (DriverState); ``lights/set_animation``.
* husarion_ugv 2.2.x: ``husarion_ugv_msgs``; ``battery/battery_status``;
  ``hardware/robot_driver_state`` (RobotDriverState: driver_states[]); ``lights/set_animation``;
  its lights manager also reads ``joy`` (``drive_state``) and gives its Lights tree the
  husarion_ugv_msgs animation numbers and ``current_battery_anim_id``,
  ``current_error_anim_id`` (husarion_ugv_ros@2.2.2:husarion_ugv_manager/src/lights_manager_node.cpp).
  2.3.0 and 2.3.1 are the same (husarion_ugv_ros@2.3.1:husarion_ugv_manager/src/lights_manager_node.cpp).
* husarion_ugv 2.3.2: as 2.2, but the lights manager no longer reads ``joy`` (no ``drive_state``):
  the Lights tree checks ``twist_mux_controller/source`` itself (CheckStringMsg), and its
  blackboard adds GOAL_FAILED_ANIM_ID 16 and FLOOD_LIGHT_ANIM_ID 17
  (husarion_ugv_ros@2.3.2:husarion_ugv_manager/src/lights_manager_node.cpp).

Sources: panther_ros 2.0.x ``panther_manager/src/safety_manager_node.cpp`` and
``panther_lights`` controller node (2.1.0 renamed the ROS API, "Enhance ROS API names");
panther_ros@2.1.1 ROS_API.md; husarion_ugv_ros ``husarion_ugv_manager/src/safety_manager_node.cpp``
and ROS_API.md (humble). The trees name services as 2.1+ does (``lights/set_animation``,
``hardware/...``); `RosInterfaces.service` maps them to the robot's names.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

from panther_ops.manager import keys
from panther_ops.manager.constants import (
    ANIMATION_ID_CONSTANTS,
    ANIMATION_ID_CONSTANTS_22,
    ANIMATION_ID_CONSTANTS_232,
    MUX_SOURCE_TOPIC,
)
from panther_ops.manager.versions import Version, by_release


@dataclass(frozen=True)
class RosInterfaces:
    """Names of one stack's ROS 2 interfaces (relative: the robot's namespace applies)."""

    stack: str
    msg_package: str
    battery: str = "battery/battery_status"
    e_stop: str = "hardware/e_stop"
    io_state: str = "hardware/io_state"
    system_status: str = "system_status"
    driver_state: str = "hardware/motor_controllers_state"
    driver_state_type: str = "DriverState"
    """``DriverState`` (``front``/``rear``) or ``RobotDriverState`` (``driver_states[]``)"""
    renamed_services: dict[str, str] = field(default_factory=dict)
    """tree name (2.1+ spelling) -> this stack's name"""
    animation_ids: dict[str, int] = field(default_factory=lambda: dict(ANIMATION_ID_CONSTANTS))
    """The Lights tree's ``<NAME>_ANIM_ID`` entries: this stack's LEDAnimation numbers."""
    lights_state: dict[str, Any] = field(
        default_factory=lambda: {keys.CHARGING_ANIM_PERCENT: "", keys.CURRENT_ANIM_ID: -1})
    """The Lights tree's initial state entries, as this stack's lights manager sets them."""
    joy: str | None = None
    """The topic whose dead man button sets ``drive_state`` (2.2), or None."""
    string_topics: tuple[str, ...] = ()
    """std_msgs/String topics the stock trees check (CheckStringMsg, 2.3.2)."""

    def service(self, name: str) -> str:
        """The robot's name of a service the trees call by its 2.1+ name."""
        return self.renamed_services.get(name.lstrip("/"), name.lstrip("/"))

    @property
    def set_led_animation_type(self) -> str:
        """``<msgs>/srv/SetLEDAnimation`` as ``ros2 service call`` takes it."""
        return f"{self.msg_package}/srv/SetLEDAnimation"

    def service_path(self, name: str, namespace: str) -> str:
        """Absolute service name under the robot's namespace (``/panther/lights/set_animation``)."""
        ns = namespace.strip("/")
        return f"/{ns}/{self.service(name)}" if ns else f"/{self.service(name)}"


PANTHER_2_0 = RosInterfaces(
    "panther_ros 2.0", "panther_msgs", battery="battery", driver_state="driver/motor_controllers_state",
    renamed_services={"lights/set_animation": "lights/controller/set/animation"})
PANTHER_2_1 = RosInterfaces("panther_ros 2.1", "panther_msgs")
HUSARION_UGV_2_2 = RosInterfaces(
    "husarion_ugv 2.2", "husarion_ugv_msgs", driver_state="hardware/robot_driver_state",
    driver_state_type="RobotDriverState", animation_ids=dict(ANIMATION_ID_CONSTANTS_22),
    lights_state={keys.CHARGING_ANIM_PERCENT: "", keys.CURRENT_ANIM_ID: -1, keys.CURRENT_BATTERY_ANIM_ID: -1,
                  keys.CURRENT_ERROR_ANIM_ID: -1, keys.DRIVE_STATE: False},
    joy="joy")
HUSARION_UGV_2_3_2 = RosInterfaces(
    "husarion_ugv 2.3.2", "husarion_ugv_msgs", driver_state="hardware/robot_driver_state",
    driver_state_type="RobotDriverState", animation_ids=dict(ANIMATION_ID_CONSTANTS_232),
    lights_state={keys.CHARGING_ANIM_PERCENT: "", keys.CURRENT_ANIM_ID: -1, keys.CURRENT_BATTERY_ANIM_ID: -1,
                  keys.CURRENT_ERROR_ANIM_ID: -1},
    string_topics=(MUX_SOURCE_TOPIC,))


def interfaces_for(version: Version) -> RosInterfaces:
    """The interfaces of a stack version (2.0.0 - 2.3.x)."""
    return by_release(version, (((2, 3, 2), HUSARION_UGV_2_3_2), ((2, 2, 0), HUSARION_UGV_2_2),
                                ((2, 1, 0), PANTHER_2_1)), PANTHER_2_0)


def parse_stack(text: str) -> Version:
    """``2.1.1`` -> (2, 1, 1); ValueError naming the value otherwise."""
    m = re.fullmatch(r"(\d+)\.(\d+)\.(\d+)", text.strip())
    if not m:
        raise ValueError(f"--stack {text!r}: expected the robot's stack version X.Y.Z, e.g. 2.1.1")
    return (int(m[1]), int(m[2]), int(m[3]))


def detect_interfaces() -> RosInterfaces:
    """Without ``--stack``: the message package importable here decides (husarion_ugv_msgs: 2.2)."""
    import importlib.util

    if importlib.util.find_spec("husarion_ugv_msgs") is not None:
        return HUSARION_UGV_2_2
    return PANTHER_2_1
