"""Scenario files: a simulated robot's start state and timed events.

.. code-block:: yaml

    name: battery overheats
    duration: 90                 # simulated seconds
    battery:                     # Linear Battery Plugin parameters
      simulate_discharging: true
      initial_charge_percentage: 70.0
    robot: {bat_temp: 30, cpu_temp: 50, driver_temp: 30, aux: true, fan: false}
    params: {cpu.temp.fan_on: 75}          # manager parameters (lights/safety_manager keys)
    shutdown_hosts:              # simulated computers for the Shutdown tree
      - {ip: 10.15.20.3, username: husarion, shutdown_delay: 3}
    events:
      - {at: 10, set: {charger: true}}
      - {at: 20, ramp: {bat_temp: 60}, over: 30}   # linear, from the value at t=20
      - {at: 60, set: {health: OVERVOLTAGE}}
      - {at: 70, press: power_button}
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.manager.config import config_with_params
from panther_ops.manager.errors import ManagerError, ScenarioError
from panther_ops.manager.sim.model import BatteryPlugin, PantherModel, SimHost
from panther_ops.manager.yaml_io import read_yaml

RAMPABLE = {"bat_temp", "cpu_temp", "driver_temp", "driver_front_temp", "driver_rear_temp",
            "charge"}
SETTABLE = RAMPABLE | {"charger", "e_stop", "aux", "fan", "status", "health", "mux_source"}
PRESSABLE = {"power_button"}


@dataclass(frozen=True)
class Event:
    """Something that happens at `at` seconds: values set, ramps started, buttons pressed."""

    at: float
    set: Mapping[str, Any] = field(default_factory=dict)
    ramp: Mapping[str, float] = field(default_factory=dict)
    over: float = 0.0
    press: tuple[str, ...] = ()


@dataclass(frozen=True)
class Scenario:
    """A whole scenario file."""

    name: str
    duration: float
    battery: BatteryPlugin
    robot: Mapping[str, Any]
    params: Mapping[str, Any]
    hosts: tuple[Mapping[str, Any], ...]
    events: tuple[Event, ...]
    description: str = ""
    source: str = ""

    def build_model(self) -> PantherModel:
        """The simulated robot at t=0."""
        model = PantherModel(battery=self.battery)
        for key, value in self.robot.items():
            model.set(key, value)
        for host in self.hosts:
            model.hosts[str(host["ip"])] = SimHost(
                str(host["ip"]), bool(host.get("reachable", True)),
                float(host.get("shutdown_delay", 2.0)))
        return model


def _section(doc: Mapping[str, Any], key: str, kind: type, where: str) -> Any:
    """``doc[key]`` (empty when missing or null), which must be a ``kind`` (dict or list)."""
    value = doc.get(key)
    if value is None:
        return kind()
    if kind is dict and isinstance(value, Mapping):
        return dict(value)
    if kind is list and isinstance(value, list):
        return list(value)
    raise ScenarioError(f"{where}: '{key}' must be a {'mapping' if kind is dict else 'list'}, "
                        f"got {type(value).__name__}")


def _seconds(value: Any, what: str, where: str, *, positive: bool = False) -> float:
    """A finite number of seconds (>= 0, or > 0 when ``positive``)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or value < 0 or (positive and value == 0):
        raise ScenarioError(f"{where}: '{what}' must be a finite number of seconds "
                            f"{'> 0' if positive else '>= 0'}, got {value!r}")
    return float(value)


def _event(raw: Any, where: str) -> Event:
    if not isinstance(raw, Mapping) or "at" not in raw:
        raise ScenarioError(f"{where}: an event needs 'at' (seconds)")
    unknown = set(raw) - {"at", "set", "ramp", "over", "press"}
    if unknown:
        raise ScenarioError(f"{where}: unknown keys {', '.join(sorted(unknown))}")
    sets, ramps = _section(raw, "set", dict, where), _section(raw, "ramp", dict, where)
    press = raw.get("press") or ()
    press = (press,) if isinstance(press, str) else press
    if not isinstance(press, (list, tuple)) or not all(isinstance(p, str) for p in press):
        raise ScenarioError(f"{where}: 'press' must be a button name or a list of them")
    press = tuple(press)
    for key in sets:
        if key not in SETTABLE:
            raise ScenarioError(f"{where}: cannot set '{key}' (settable: {', '.join(sorted(SETTABLE))})")
    for key in ramps:
        if key not in RAMPABLE:
            raise ScenarioError(f"{where}: cannot ramp '{key}' (rampable: {', '.join(sorted(RAMPABLE))})")
    for key in press:
        if key not in PRESSABLE:
            raise ScenarioError(f"{where}: cannot press '{key}'")
    at, over = _seconds(raw["at"], "at", where), _seconds(raw.get("over", 0.0), "over", where)
    try:
        ramps = {k: float(v) for k, v in ramps.items()}
    except (TypeError, ValueError):
        raise ScenarioError(f"{where}: ramp targets must be numbers") from None
    if not all(math.isfinite(v) for v in ramps.values()):
        raise ScenarioError(f"{where}: ramp targets must be finite numbers")
    if ramps and over <= 0:
        raise ScenarioError(f"{where}: a ramp needs 'over' (seconds, positive)")
    return Event(at, sets, ramps, over, press)


def parse_scenario(doc: Any, source: str = "<scenario>") -> Scenario:
    """A scenario from its loaded YAML; raise ScenarioError naming the bad key."""
    if not isinstance(doc, Mapping):
        raise ScenarioError(f"{source}: expected a mapping (name, duration, battery, robot, params, "
                            "shutdown_hosts, events)")
    unknown = {str(k) for k in doc} - {"name", "description", "duration", "battery", "robot", "params",
                                       "shutdown_hosts", "events"}
    if unknown:
        raise ScenarioError(f"{source}: unknown keys {', '.join(sorted(unknown))}")
    events = tuple(sorted((_event(e, f"{source}: events[{i}]")
                           for i, e in enumerate(_section(doc, "events", list, source))), key=lambda e: e.at))
    hosts = tuple(_section(doc, "shutdown_hosts", list, source))
    for i, host in enumerate(hosts):
        if not isinstance(host, Mapping) or "ip" not in host:
            raise ScenarioError(f"{source}: shutdown_hosts[{i}] needs an 'ip'")
        _seconds(host.get("shutdown_delay", 2.0), "shutdown_delay", f"{source}: shutdown_hosts[{i}]")
    for key in ("name", "description"):
        if isinstance(doc.get(key), (Mapping, list)):
            raise ScenarioError(f"{source}: '{key}' must be text")
    default_duration = max((e.at + e.over for e in events), default=0) + 10
    battery_params = _section(doc, "battery", dict, source)
    battery = _checked(lambda: BatteryPlugin.from_params(battery_params), source)
    params = _section(doc, "params", dict, source)
    _checked(lambda: config_with_params(params, source=source), f"{source}: params")
    scenario = Scenario(
        name=str(doc.get("name") or Path(source).stem),
        duration=_seconds(doc.get("duration", default_duration), "duration", source, positive=True),
        battery=battery,
        robot={str(k): v for k, v in _section(doc, "robot", dict, source).items()},
        params=params,
        hosts=hosts,
        events=events,
        description=str(doc.get("description") or ""),
        source=source,
    )
    # the robot keys and every event's values, checked now rather than mid-run
    model = _checked(scenario.build_model, f"{source}: robot")
    for i, event in enumerate(events):
        for key, value in [*event.set.items(), *event.ramp.items()]:
            _checked(lambda k=key, v=value: model.set(k, v), f"{source}: events[{i}]")
    return scenario


def _checked(step: Any, where: str) -> Any:
    """``step()``; a value it cannot take becomes a ScenarioError naming ``where``."""
    try:
        return step()
    except (TypeError, ValueError, ManagerError) as exc:
        raise ScenarioError(f"{where}: {exc}") from None


def load_scenario(path: str | Path) -> Scenario:
    """Read a scenario YAML file."""
    return parse_scenario(read_yaml(path, ScenarioError), str(path))


@dataclass
class _Ramp:
    key: str
    start_time: float
    start: float
    target: float
    over: float


class ScenarioPlayer:
    """Applies a scenario's events to a model as time passes."""

    def __init__(self, scenario: Scenario) -> None:
        self.pending = list(scenario.events)
        self.ramps: dict[str, _Ramp] = {}

    def apply(self, model: PantherModel, now: float) -> None:
        """Fire every event due by `now` and move the ramps on."""
        while self.pending and self.pending[0].at <= now + 1e-9:
            event = self.pending.pop(0)
            for key, value in event.set.items():
                self.ramps.pop(key, None)
                model.set(key, value)
            for key, target in event.ramp.items():
                self.ramps[key] = _Ramp(key, event.at, model.get(key), target, event.over)
            if "power_button" in event.press:
                model.power_button = True
        for key, ramp in list(self.ramps.items()):
            share = min(1.0, max(0.0, (now - ramp.start_time) / ramp.over))
            model.set(key, ramp.start + (ramp.target - ramp.start) * share)
            if share >= 1.0:
                del self.ramps[key]
