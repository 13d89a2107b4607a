"""A simulated Panther: linear battery, temperatures, E-stop, fan, AUX, charger, hosts.

The battery follows the manual's Linear Battery Plugin parameters: ``simulate_discharging``,
``initial_charge_percentage`` (70.0 in 2.0.x, a percentage; 0.7 in 2.1.1+, a fraction:
both are accepted and `charge_scale` says which was read), ``charging_time`` [h],
``power_load`` [W] and ``capacity`` [Ah]. Without discharging the charge stays put; a
depleted battery stops the robot. Health comes from the temperature (OVERHEAT from 45 °C,
COLD below -10 °C, as the battery driver) unless a scenario forces it; status from the
charger (CHARGING, FULL when full, else DISCHARGING) unless a scenario forces it. A robot of
husarion_ugv 2.3.2 also publishes its twist mux's active input (``mux_source``: manual,
autonomous, unknown, not_published) on twist_mux_controller/source; None (the default): a
robot without the mux (before 2.3.2), which publishes nothing there.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.manager.constants import MUX_SOURCE_TOPIC, MUX_SOURCES, PowerSupplyHealth, PowerSupplyStatus
from panther_ops.manager.errors import ScenarioError
from panther_ops.manager.robot_io import (
    BatteryMsg,
    DriverStateMsg,
    EStopMsg,
    IOStateMsg,
    RobotMsg,
    StringMsg,
    SystemStatusMsg,
)
from panther_ops.manager.yaml_io import read_yaml

NOMINAL_VOLTAGE = 42.0
"""V: 20 Ah x 42 V / 120 W = 7 h, the 2.1.1 configuration's "~7 h with BAT01"."""
V_EMPTY, V_FULL = 32.0, 41.4
OVERHEAT_TEMP, COLD_TEMP = 45.0, -10.0


@dataclass(frozen=True)
class BatteryPlugin:
    """The Linear Battery Plugin parameters (battery_plugin_config.yaml)."""

    simulate_discharging: bool = False
    initial_charge: float = 0.7
    charge_scale: str = "fraction"
    charging_time: float = 6.0
    power_load: float = 120.0
    capacity: float = 20.0

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> BatteryPlugin:
        """Read the plugin's keys; ``initial_charge_percentage`` above 1 is a percentage."""
        known = {"simulate_discharging", "initial_charge_percentage", "charging_time",
                 "power_load", "capacity"}
        unknown = set(params) - known
        if unknown:
            raise ScenarioError(f"battery: unknown keys {', '.join(sorted(unknown))}")
        try:
            raw = float(params.get("initial_charge_percentage", 0.7))
            plugin = cls(
                simulate_discharging=bool(params.get("simulate_discharging", False)),
                initial_charge=raw / 100.0 if raw > 1.0 else raw,
                charge_scale="percent (2.0.0)" if raw > 1.0 else "fraction (2.0.1+)",
                charging_time=float(params.get("charging_time", 6.0)),
                power_load=float(params.get("power_load", 120.0)),
                capacity=float(params.get("capacity", 20.0)),
            )
        except (TypeError, ValueError) as exc:
            raise ScenarioError(f"battery: {exc}") from None
        if not 0.0 <= plugin.initial_charge <= 1.0:
            raise ScenarioError(f"battery: initial_charge_percentage {raw} is not 0-1 nor 0-100")
        if plugin.charging_time <= 0 or plugin.capacity <= 0 or plugin.power_load < 0:
            raise ScenarioError("battery: charging_time and capacity must be positive, "
                                "power_load not negative")
        return plugin

    @classmethod
    def from_file(cls, path: str | Path) -> BatteryPlugin:
        """Read a battery_plugin_config.yaml (2.0 percent scale or 2.1.1 fraction scale)."""
        doc = read_yaml(path, ScenarioError) or {}
        if not isinstance(doc, Mapping):
            raise ScenarioError(f"{path}: expected a mapping of battery plugin parameters")
        return cls.from_params(doc)

    @property
    def discharge_per_second(self) -> float:
        """Fraction of the battery used per second (0 without simulate_discharging)."""
        if not self.simulate_discharging:
            return 0.0
        return self.power_load / (self.capacity * NOMINAL_VOLTAGE * 3600.0)

    @property
    def charge_per_second(self) -> float:
        """Fraction charged per second with the charger connected."""
        return 1.0 / (self.charging_time * 3600.0)


@dataclass
class SimHost:
    """A computer on the simulated robot network (a shutdown target)."""

    ip: str
    reachable: bool = True
    shutdown_delay: float = 2.0
    down_at: float | None = None

    def up(self, now: float) -> bool:
        return self.reachable and (self.down_at is None or now < self.down_at)


@dataclass
class PantherModel:
    """The simulated robot's state; `advance(now)` moves the battery on."""

    battery: BatteryPlugin = field(default_factory=BatteryPlugin)
    charge: float = 0.7
    charger: bool = False
    bat_temp: float = 25.0
    cpu_temp: float = 45.0
    driver_front_temp: float = 30.0
    driver_rear_temp: float = 30.0
    e_stop: bool = False
    aux: bool = True
    fan: bool = False
    status_override: PowerSupplyStatus | None = None
    health_override: PowerSupplyHealth | None = None
    power_button: bool = False
    powered_off: bool = False
    mux_source: str | None = None
    hosts: dict[str, SimHost] = field(default_factory=dict)
    time: float | None = None

    def __post_init__(self) -> None:
        self.charge = self.battery.initial_charge

    @property
    def depleted(self) -> bool:
        """No charge left: the robot stops moving."""
        return self.charge <= 0.0

    def advance(self, now: float) -> None:
        """Charge or discharge the battery up to `now`."""
        if self.time is None or now <= self.time:
            self.time = now if self.time is None else self.time
            return
        dt, self.time = now - self.time, now
        if self.powered_off:
            return
        if self.charger:
            self.charge = min(1.0, self.charge + self.battery.charge_per_second * dt)
        else:
            self.charge = max(0.0, self.charge - self.battery.discharge_per_second * dt)

    def status(self) -> PowerSupplyStatus:
        if self.status_override is not None:
            return self.status_override
        if self.charger:
            return PowerSupplyStatus.FULL if self.charge >= 0.999 else PowerSupplyStatus.CHARGING
        return PowerSupplyStatus.DISCHARGING

    def health(self) -> PowerSupplyHealth:
        if self.health_override is not None:
            return self.health_override
        if self.bat_temp >= OVERHEAT_TEMP:
            return PowerSupplyHealth.OVERHEAT
        if self.bat_temp < COLD_TEMP:
            return PowerSupplyHealth.COLD
        return PowerSupplyHealth.GOOD

    @property
    def voltage(self) -> float:
        return V_EMPTY + (V_FULL - V_EMPTY) * self.charge

    def messages(self) -> list[RobotMsg]:
        """One message per topic, as the robot publishes them (none once powered off)."""
        if self.powered_off:
            return []
        pressed, self.power_button = self.power_button, False
        status = self.status()
        percent = float("nan") if status is PowerSupplyStatus.UNKNOWN else self.charge
        out: list[RobotMsg] = [
            BatteryMsg(percent, self.bat_temp, int(status), int(self.health()), self.voltage),
            EStopMsg(self.e_stop),
            IOStateMsg(self.aux, self.fan, pressed, self.charger),
            SystemStatusMsg(self.cpu_temp),
            DriverStateMsg(self.driver_front_temp, self.driver_rear_temp),
        ]
        if self.mux_source is not None:
            out.append(StringMsg(MUX_SOURCE_TOPIC, self.mux_source))
        return out

    @property
    def driver_temp(self) -> float:
        return max(self.driver_front_temp, self.driver_rear_temp)

    def set(self, key: str, value: Any) -> None:
        """Set a scenario key (see `scenario.SETTABLE`)."""
        if key in {"bat_temp", "cpu_temp", "driver_front_temp", "driver_rear_temp"}:
            setattr(self, key, float(value))
        elif key == "driver_temp":
            self.driver_front_temp = self.driver_rear_temp = float(value)
        elif key == "charge":
            if not 0.0 <= float(value) <= 1.0 or math.isnan(float(value)):
                raise ScenarioError(f"charge is a fraction 0-1, got {value!r}")
            self.charge = float(value)
        elif key in {"charger", "e_stop", "aux", "fan"}:
            setattr(self, key, bool(value))
        elif key == "mux_source":
            if value not in MUX_SOURCES:
                raise ScenarioError(f"mux_source is one of {', '.join(MUX_SOURCES)} (what husarion_ugv 2.3.2's "
                                    f"{MUX_SOURCE_TOPIC} says), got {value!r}")
            self.mux_source = str(value)
        elif key == "status":
            self.status_override = None if value == "auto" else _enum(PowerSupplyStatus, value)
        elif key == "health":
            self.health_override = None if value == "auto" else _enum(PowerSupplyHealth, value)
        else:
            raise ScenarioError(f"cannot set '{key}' on the simulated robot")

    def get(self, key: str) -> float:
        """A numeric key's value (ramps start from it)."""
        if key == "driver_temp":
            return self.driver_temp
        return float(getattr(self, key))


def _enum(kind: type[PowerSupplyStatus] | type[PowerSupplyHealth], value: Any) -> Any:
    try:
        return kind[str(value).upper()]
    except KeyError:
        names = ", ".join(m.name for m in kind)
        raise ScenarioError(f"{value!r} is not one of {names} (or auto)") from None
