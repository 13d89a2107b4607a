"""From robot messages to blackboard entries, with the moving averages of the C++ nodes.

Lights gets battery_status / battery_health, the moving average of the battery percentage
(``battery_percent``, starting at 1.0) and its rounded string (``battery_percent_round``),
and e_stop_state; on husarion_ugv 2.2 also ``drive_state`` (the joy message's dead man
button, as 2.2's lights manager). Safety gets battery_status / battery_health, ``bat_temp``, ``cpu_temp``,
``driver_temp`` (the hotter of the two drivers), e_stop_state, aux_state and fan_state.
On husarion_ugv 2.3.2 the string topics the Lights tree checks (``twist_mux_controller/source``)
go to the trees' `TopicLatch` (CheckStringMsg). Battery values are not averaged while the status
or health is UNKNOWN (as upstream).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from panther_ops.manager import keys
from panther_ops.manager.blackboard import TreeBlackboard
from panther_ops.manager.config import ManagerConfig
from panther_ops.manager.constants import DEAD_MAN_BUTTON_INDEX, PowerSupplyHealth, PowerSupplyStatus
from panther_ops.manager.moving_average import MovingAverage
from panther_ops.manager.robot_io import (
    BatteryMsg,
    DriverStateMsg,
    EStopMsg,
    IOStateMsg,
    JoyMsg,
    RobotMsg,
    StringMsg,
    SystemStatusMsg,
    TopicLatch,
)


def round_percent(percent: float, step: float) -> str:
    """``battery_percent_round``: rounded to `step`, as std::to_string prints it."""
    rounded = math.floor(percent / step + 0.5) * step
    return f"{rounded:.6f}"


class InputFeeder:
    """Keeps the moving averages and writes what the trees read."""

    def __init__(self, config: ManagerConfig, lights: TreeBlackboard | None,
                 safety: TreeBlackboard | None, topics: TopicLatch | None = None) -> None:
        self.lights = lights
        self.topics = topics or TopicLatch()
        self.safety = safety
        self.step = config.lights.update_charging_anim_step
        self.percent = MovingAverage(config.lights.battery_percent_window_len, 1.0)
        self.bat_temp = MovingAverage(config.safety.battery_temp_window_len)
        self.cpu_temp = MovingAverage(config.safety.cpu_temp_window_len)
        self.front_temp = MovingAverage(config.safety.driver_temp_window_len)
        self.rear_temp = MovingAverage(config.safety.driver_temp_window_len)

    def apply(self, msg: RobotMsg) -> str | None:
        """Write one message's entries; return a shutdown reason (power button) or None."""
        if isinstance(msg, BatteryMsg):
            self._battery(msg)
        elif isinstance(msg, EStopMsg):
            for bb in (self.lights, self.safety):
                if bb is not None:
                    bb.set(keys.E_STOP_STATE, bool(msg.triggered))
        elif isinstance(msg, IOStateMsg):
            if self.safety is not None:
                self.safety.set(keys.AUX_STATE, bool(msg.aux_power))
                self.safety.set(keys.FAN_STATE, bool(msg.fan))
            if msg.power_button:
                return "Power button pressed"
        elif isinstance(msg, SystemStatusMsg):
            if self.safety is not None:
                self.safety.set(keys.CPU_TEMP, self.cpu_temp.roll(msg.cpu_temp))
        elif isinstance(msg, StringMsg):
            self.topics.put(msg)
        elif isinstance(msg, JoyMsg):
            if self.lights is not None and len(msg.buttons) > DEAD_MAN_BUTTON_INDEX:
                self.lights.set(keys.DRIVE_STATE, bool(msg.buttons[DEAD_MAN_BUTTON_INDEX]))
        elif isinstance(msg, DriverStateMsg) and self.safety is not None:
            front = self.front_temp.roll(msg.front_temp)
            rear = self.rear_temp.roll(msg.rear_temp)
            self.safety.set(keys.DRIVER_TEMP, max(front, rear))
        return None

    def apply_all(self, msgs: Iterable[RobotMsg]) -> str | None:
        """Apply messages in order; the first shutdown reason met, if any."""
        reason: str | None = None
        for msg in msgs:
            reason = self.apply(msg) or reason
        return reason

    def _battery(self, msg: BatteryMsg) -> None:
        known = (msg.status != PowerSupplyStatus.UNKNOWN
                 and msg.health != PowerSupplyHealth.UNKNOWN)
        if known and not math.isnan(msg.percentage):
            self.percent.roll(msg.percentage)
        if known and not math.isnan(msg.temperature):
            self.bat_temp.roll(msg.temperature)
        if self.lights is not None:
            self.lights.set(keys.BATTERY_STATUS, int(msg.status))
            self.lights.set(keys.BATTERY_HEALTH, int(msg.health))
            self.lights.set(keys.BATTERY_PERCENT, self.percent.average)
            self.lights.set(keys.BATTERY_PERCENT_ROUND, round_percent(self.percent.average, self.step))
        if self.safety is not None:
            self.safety.set(keys.BATTERY_STATUS, int(msg.status))
            self.safety.set(keys.BATTERY_HEALTH, int(msg.health))
            self.safety.set(keys.BAT_TEMP, self.bat_temp.average)


def ready(blackboard: TreeBlackboard, required: Iterable[str]) -> bool:
    """True once every required entry arrived (the C++ SystemReady check)."""
    return all(blackboard.exists(key) for key in required)
