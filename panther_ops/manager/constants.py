"""Fixed constants of the Panther stack: message enums and animation IDs.

Values are those of sensor_msgs/BatteryState and panther_msgs/LEDAnimation, as listed in the
manual's BehaviorTree section. The configurable ones (thresholds, periods) live in `config.py`.
"""

from __future__ import annotations

from enum import IntEnum


class PowerSupplyStatus(IntEnum):
    """sensor_msgs/BatteryState power_supply_status."""

    UNKNOWN = 0
    CHARGING = 1
    DISCHARGING = 2
    NOT_CHARGING = 3
    FULL = 4


class PowerSupplyHealth(IntEnum):
    """sensor_msgs/BatteryState power_supply_health."""

    UNKNOWN = 0
    GOOD = 1
    OVERHEAT = 2
    DEAD = 3
    OVERVOLTAGE = 4
    UNSPEC_FAILURE = 5
    COLD = 6
    WATCHDOG_TIMER_EXPIRE = 7
    SAFETY_TIMER_EXPIRE = 8


class AnimationId(IntEnum):
    """panther_msgs/LEDAnimation IDs of the default animations."""

    E_STOP = 0
    READY = 1
    ERROR = 2
    MANUAL_ACTION = 3
    AUTONOMOUS_ACTION = 4
    GOAL_ACHIEVED = 5
    LOW_BATTERY = 6
    CRITICAL_BATTERY = 7
    BATTERY_STATE = 8
    CHARGING_BATTERY = 9


ANIMATION_ID_CONSTANTS: dict[str, int] = {f"{a.name}_ANIM_ID": int(a) for a in AnimationId}
"""E_STOP_ANIM_ID ... CHARGING_BATTERY_ANIM_ID, as the Lights tree's constant entries."""


class AnimationId22(IntEnum):
    """husarion_ugv_msgs/LEDAnimation IDs (husarion_ugv 2.2): other numbers than panther_msgs'.

    Source: husarion/husarion_ugv_ros@2.2.2:husarion_ugv_lights/config/panther_animations.yaml
    (each default animation's ``id`` and ``name``) and
    husarion_ugv_manager/src/lights_manager_node.cpp (``CreateLightsInitialBlackboard``: the
    ``<NAME>_ANIM_ID`` entries, ``LEDAnimationMsg::<NAME>``); the same at 2.2.0.
    """

    E_STOP = 0
    READY = 1
    ERROR = 2
    NO_ERROR = 3
    MANUAL_ACTION = 4
    LOW_BATTERY = 5
    CRITICAL_BATTERY = 6
    CHARGING_BATTERY = 7
    BATTERY_CHARGED = 8
    CHARGER_INSERTED = 9
    BATTERY_NOMINAL = 10
    AUTONOMOUS_READY = 11
    AUTONOMOUS_ACTION = 12
    GOAL_ACHIEVED = 13
    BLINKER_LEFT = 14
    BLINKER_RIGHT = 15


ANIMATION_ID_CONSTANTS_22: dict[str, int] = {f"{a.name}_ANIM_ID": int(a) for a in AnimationId22}
"""The 2.2 Lights tree's animation constants (husarion_ugv_msgs numbers)."""
ANIMATION_ID_CONSTANTS_232: dict[str, int] = {**ANIMATION_ID_CONSTANTS_22, "GOAL_FAILED_ANIM_ID": 16,
                                              "FLOOD_LIGHT_ANIM_ID": 17}
"""husarion_ugv 2.3.2's: 2.2's and GOAL_FAILED 16, FLOOD_LIGHT 17 (husarion_ugv_ros@2.3.2:
husarion_ugv_manager/src/lights_manager_node.cpp ``CreateLightsInitialBlackboard``; the numbers are the
``id`` of those animations in husarion_ugv_ros@2.3.2:husarion_ugv_lights/config/panther_animations.yaml)."""
MUX_SOURCE_TOPIC = "twist_mux_controller/source"
"""husarion_ugv 2.3.2: the twist mux's active input (std_msgs/String), checked by the Lights tree."""
MUX_SOURCES = ("manual", "autonomous", "unknown", "not_published")
"""What `MUX_SOURCE_TOPIC` says (husarion_ugv_ros@2.3.2:ROS_API.md)."""

DEAD_MAN_BUTTON_INDEX = 4
"""2.2's lights manager: ``drive_state`` = ``joy.buttons[4]`` (the gamepad's dead man switch);
husarion/husarion_ugv_ros@2.2.2:husarion_ugv_manager/include/husarion_ugv_manager/lights_manager_node.hpp
``kDeadManButtonIndex``."""

STATUS_CONSTANTS: dict[str, int] = {f"POWER_SUPPLY_STATUS_{s.name}": int(s) for s in PowerSupplyStatus}
HEALTH_CONSTANTS: dict[str, int] = {f"POWER_SUPPLY_HEALTH_{h.name}": int(h) for h in PowerSupplyHealth}

# Services the default trees call (panther-stack.md §1.10, §1.12).
SET_ANIMATION_SERVICE = "lights/set_animation"
E_STOP_TRIGGER_SERVICE = "hardware/e_stop_trigger"
AUX_POWER_ENABLE_SERVICE = "hardware/aux_power_enable"
FAN_ENABLE_SERVICE = "hardware/fan_enable"

LIGHTS_TREE = "Lights"
SAFETY_TREE = "Safety"
SHUTDOWN_TREE = "Shutdown"
