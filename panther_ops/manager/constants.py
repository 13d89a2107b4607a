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
