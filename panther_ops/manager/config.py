"""Manager parameters, loaded like the ROS parameters of lights_manager and safety_manager.

Accepted file shapes (all under ``<node or /**>: ros__parameters:``), nested or dotted keys:

* 2.1.1+ ``lights_manager.yaml`` / ``safety_manager.yaml``: ``battery.percent.window_len``,
  ``cpu.temp.fan_on`` ...
* 2.0.2–2.1.0 ``lights_manager_config.yaml`` / node defaults: ``low_battery_threshold_percent`` ...
* 2.0.0 ``manager_bt_config.yaml``: ``lights.low_battery_anim_period``, ``safety.cpu_fan_on_temp`` ...

Where the sources disagree the defaults follow the manual (the seed):

* fan thresholds: CPU on/off 70/60 °C, driver 45/35 °C — the node code defaults the manual
  documents. The shipped 2.0/2.1 YAML files set 75/70 and 50/45; load them to get those.
* battery temperatures: the Faults Handle table acts at 55 °C (e-stop, AUX off) and 62 °C
  (shutdown): ``CRITICAL_BAT_TEMP`` = 55 and ``FATAL_BAT_TEMP`` = 62, as in 2.1.
  The 2.0 constants ``HIGH_BAT_TEMP`` 55 and ``CRITICAL_BAT_TEMP`` 59 that the manual's constant
  list still shows are accepted (``safety.high_bat_temp``, ``safety.critical_bat_temp``).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from panther_ops.manager.constants import (
    ANIMATION_ID_CONSTANTS,
    HEALTH_CONSTANTS,
    STATUS_CONSTANTS,
)
from panther_ops.manager.errors import ConfigError
from panther_ops.manager.yaml_io import read_yaml


@dataclass(frozen=True)
class TreeParams:
    """What both manager nodes take: tick rate, service timeouts, their BT project."""

    timer_frequency: float = 10.0
    service_availability_timeout: float = 1.0
    service_response_timeout: float = 1.0
    bt_project_path: str = ""

    @property
    def service_timeout(self) -> float:
        """How long a service call may take: waiting for the server, then for the answer."""
        return self.service_availability_timeout + self.service_response_timeout


@dataclass(frozen=True)
class LightsParams(TreeParams):
    """Parameters of the Lights tree (lights_manager node)."""

    battery_percent_window_len: int = 6
    low_battery_threshold_percent: float = 0.4
    critical_battery_threshold_percent: float = 0.1
    low_battery_anim_period: float = 30.0
    critical_battery_anim_period: float = 15.0
    battery_state_anim_period: float = 120.0
    update_charging_anim_step: float = 0.1


@dataclass(frozen=True)
class SafetyParams(TreeParams):
    """Parameters of the Safety and Shutdown trees (safety_manager node)."""

    fan_turn_off_timeout: float = 60.0
    battery_temp_window_len: int = 6
    cpu_temp_window_len: int = 6
    driver_temp_window_len: int = 6
    cpu_fan_on_temp: float = 70.0
    cpu_fan_off_temp: float = 60.0
    driver_fan_on_temp: float = 45.0
    driver_fan_off_temp: float = 35.0
    high_bat_temp: float = 55.0
    critical_bat_temp: float = 55.0
    fatal_bat_temp: float = 62.0
    shutdown_hosts_path: str = ""
    shutdown_localhost_command: str = "sudo shutdown now"
    shutdown_frequency: float = 30.0


@dataclass(frozen=True)
class ManagerConfig:
    """Both parameter sets, the files they came from and what was noticed while reading."""

    lights: LightsParams = field(default_factory=LightsParams)
    safety: SafetyParams = field(default_factory=SafetyParams)
    sources: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()


# parameter key (flattened, dotted) -> (section, field)
_KEYS: dict[str, tuple[str, str]] = {
    # lights, 2.1.1+ names
    "battery.percent.window_len": ("lights", "battery_percent_window_len"),
    "battery.percent.threshold.low": ("lights", "low_battery_threshold_percent"),
    "battery.percent.threshold.critical": ("lights", "critical_battery_threshold_percent"),
    "battery.animation_period.low": ("lights", "low_battery_anim_period"),
    "battery.animation_period.critical": ("lights", "critical_battery_anim_period"),
    "battery.animation_period.battery_state": ("lights", "battery_state_anim_period"),
    "battery.charging_anim_step": ("lights", "update_charging_anim_step"),
    # lights, 2.0.x names (also under the 2.0.0 "lights." prefix, stripped below)
    "battery_percent_window_len": ("lights", "battery_percent_window_len"),
    "low_battery_threshold_percent": ("lights", "low_battery_threshold_percent"),
    "critical_battery_threshold_percent": ("lights", "critical_battery_threshold_percent"),
    "low_battery_anim_period": ("lights", "low_battery_anim_period"),
    "critical_battery_anim_period": ("lights", "critical_battery_anim_period"),
    "battery_state_anim_period": ("lights", "battery_state_anim_period"),
    "update_charging_anim_step": ("lights", "update_charging_anim_step"),
    # safety, 2.1.1+ names
    "fan_turn_off_timeout": ("safety", "fan_turn_off_timeout"),
    "battery.temp.window_len": ("safety", "battery_temp_window_len"),
    "cpu.temp.window_len": ("safety", "cpu_temp_window_len"),
    "cpu.temp.fan_on": ("safety", "cpu_fan_on_temp"),
    "cpu.temp.fan_off": ("safety", "cpu_fan_off_temp"),
    "driver.temp.window_len": ("safety", "driver_temp_window_len"),
    "driver.temp.fan_on": ("safety", "driver_fan_on_temp"),
    "driver.temp.fan_off": ("safety", "driver_fan_off_temp"),
    "battery.temp.high": ("safety", "high_bat_temp"),
    "battery.temp.critical": ("safety", "critical_bat_temp"),
    "battery.temp.fatal": ("safety", "fatal_bat_temp"),
    "shutdown_hosts_path": ("safety", "shutdown_hosts_path"),
    "shutdown_hosts_config_path": ("safety", "shutdown_hosts_path"),
    "shutdown_localhost_command": ("safety", "shutdown_localhost_command"),
    # safety, 2.0.x names
    "battery_temp_window_len": ("safety", "battery_temp_window_len"),
    "cpu_temp_window_len": ("safety", "cpu_temp_window_len"),
    "driver_temp_window_len": ("safety", "driver_temp_window_len"),
    "cpu_fan_on_temp": ("safety", "cpu_fan_on_temp"),
    "cpu_fan_off_temp": ("safety", "cpu_fan_off_temp"),
    "driver_fan_on_temp": ("safety", "driver_fan_on_temp"),
    "driver_fan_off_temp": ("safety", "driver_fan_off_temp"),
    "high_bat_temp": ("safety", "high_bat_temp"),
    "critical_bat_temp": ("safety", "critical_bat_temp"),
}
# keys that exist in both node files: which node the file section names decides
_SHARED = {"timer_frequency", "bt_project_path"}
_TIMEOUT_KEYS = {"ros_communication_timeout.availability", "ros_communication_timeout.response"}
_IGNORED = {"plugin_libs", "ros_plugin_libs", "use_sim_time", "shutdown_timeout",
            "launch_lights_tree", "launch_safety_tree", "launch_shutdown_tree", "bt_server_port"}


def flatten(tree: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested mappings to dotted keys: {"a": {"b": 1}} -> {"a.b": 1}."""
    flat: dict[str, Any] = {}
    for key, value in tree.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            flat.update(flatten(value, name + "."))
        else:
            flat[name] = value
    return flat


def _node_sections(document: Any, path: str) -> list[tuple[str, dict[str, Any]]]:
    if not isinstance(document, Mapping):
        raise ConfigError(f"{path}: expected a mapping of node names to ros__parameters")
    sections: list[tuple[str, dict[str, Any]]] = []
    for node, body in document.items():
        if isinstance(body, Mapping) and isinstance(body.get("ros__parameters"), Mapping):
            sections.append((str(node), flatten(body["ros__parameters"])))
        elif isinstance(body, Mapping):
            # "/**": {node: {ros__parameters}} nesting
            sections.extend(_node_sections(body, path))
    if not sections and "ros__parameters" in document:
        sections.append(("", flatten(document["ros__parameters"])))
    return sections


def _coerce(value: Any, like: Any, key: str, path: str) -> Any:
    try:
        if isinstance(like, bool):
            return bool(value)
        if isinstance(like, int):
            if isinstance(value, bool) or float(value) != int(float(value)):
                raise ValueError
            return int(float(value))
        if isinstance(like, float):
            if isinstance(value, bool):
                raise ValueError
            return float(value)
        return str(value)
    except (TypeError, ValueError):
        kind = type(like).__name__
        raise ConfigError(f"{path}: {key}: expected {kind}, got {value!r}") from None


def _section_for(node: str, key: str) -> str | None:
    lowered = node.lower()
    if key in _SHARED or key in _TIMEOUT_KEYS:
        if "light" in lowered:
            return "lights"
        if "safety" in lowered:
            return "safety"
        return None
    return _KEYS[key][0] if key in _KEYS else None


def _strip_v2_0_prefix(node: str, key: str) -> tuple[str, str]:
    """2.0.0 manager_bt_config.yaml nests parameters under "lights." and "safety."."""
    for prefix in ("lights.", "safety."):
        rest = key[len(prefix):]
        if key.startswith(prefix) and (rest in _KEYS or rest in _SHARED or rest in _TIMEOUT_KEYS):
            return prefix[:-1], rest
    return node, key


_IGNORED_TARGET = ("", "")


def _node_of(node: str, params: Mapping[str, Any], source: str) -> str:
    """The node a section's keys belong to: "/**" or no node name takes the node of the
    section's other keys (else the file's name)."""
    if _section_for(node, "timer_frequency") is not None:
        return node
    own = {_KEYS[k][0] for k in (_strip_v2_0_prefix(node, f)[1] for f in params) if k in _KEYS}
    hint = next(iter(own)) if len(own) == 1 else Path(source).stem
    return f"{node} {hint}"


def _target(node: str, full_key: str) -> tuple[str, str] | None:
    """(section, field) a key sets; `_IGNORED_TARGET` for a stock key the manager ignores;
    None for a key that is not a manager parameter."""
    section_node, key = _strip_v2_0_prefix(node, full_key)
    if key in _IGNORED:
        return _IGNORED_TARGET
    section = _section_for(section_node, key)
    if section is None:
        return None
    if key in _TIMEOUT_KEYS:
        return section, f"service_{key.rsplit('.', 1)[1]}_timeout"
    return section, key if key in _SHARED else _KEYS[key][1]


def _apply(values: dict[str, dict[str, Any]], node: str, params: Mapping[str, Any],
           source: str, notes: list[str]) -> None:
    defaults: dict[str, Any] = {"lights": LightsParams(), "safety": SafetyParams()}
    node = _node_of(node, params, source)
    for full_key, value in params.items():
        where = _target(node, full_key)
        if where is None:
            notes.append(f"{source}: {full_key}: not a manager parameter, ignored")
            continue
        if where == _IGNORED_TARGET:
            continue
        section, target = where
        like = getattr(defaults[section], target)
        values[section][target] = _coerce(value, like, full_key, source)


def param_targets(params: Mapping[str, Any], source: str = "<params>") -> dict[str, str | None]:
    """What each key of ``params`` (as `config_with_params` takes them) sets: ``section.field``
    (``lights.low_battery_threshold_percent`` for ``battery.percent.threshold.low`` and for
    its 2.0 name alike), ``""`` for a stock key the manager ignores, None for a key that is
    not a manager parameter."""
    flat = flatten(params)
    node = _node_of("", flat, source)
    out: dict[str, str | None] = {}
    for key in flat:
        where = _target(node, key)
        out[key] = None if where is None else ".".join(where).strip(".")
    return out


def _build(values: dict[str, dict[str, Any]], sources: list[str], notes: list[str],
           base: ManagerConfig | None = None) -> ManagerConfig:
    start = base or ManagerConfig()
    lights = replace(start.lights, **values["lights"])
    safety = replace(start.safety, **values["safety"])
    notes.extend(check_params(lights, safety))
    return ManagerConfig(lights, safety, tuple(start.sources) + tuple(sources),
                         tuple(start.notes) + tuple(notes))


def load_manager_config(paths: Iterable[str | Path] = ()) -> ManagerConfig:
    """Read lights/safety parameter files (later files override earlier ones).

    Args:
        paths: YAML files shaped like the shipped lights_manager.yaml / safety_manager.yaml
            (or the 2.0 manager_bt_config.yaml). No paths gives the manual's defaults.

    Returns:
        The parameters, the files read and notes (ignored or unknown keys, odd values).

    Raises:
        ConfigError: unreadable file, wrong value type, or a value out of its range.
    """
    values: dict[str, dict[str, Any]] = {"lights": {}, "safety": {}}
    notes: list[str] = []
    sources: list[str] = []
    for raw in paths:
        path = str(raw)
        sources.append(path)
        for node, params in _node_sections(read_yaml(path, ConfigError), path):
            _apply(values, node, params, path, notes)
    return _build(values, sources, notes)


def config_with_params(params: Mapping[str, Any], base: ManagerConfig | None = None,
                       source: str = "<params>") -> ManagerConfig:
    """`base` (default: the manual's defaults) with parameters given as a (nested) mapping.

    Keys are those of the parameter files; ``lights.`` / ``safety.`` prefixes select the node
    for keys both nodes have (``timer_frequency``, ``ros_communication_timeout.*``).
    """
    values: dict[str, dict[str, Any]] = {"lights": {}, "safety": {}}
    notes: list[str] = []
    _apply(values, "", flatten(params), source, notes)
    return _build(values, [], notes, base)


def check_params(lights: LightsParams, safety: SafetyParams) -> list[str]:
    """Raise on impossible values; return warnings for unusual but workable ones."""
    for params in (lights, safety):
        for f in fields(params):
            value = getattr(params, f.name)
            if f.name.endswith("window_len") and value < 1:
                raise ConfigError(f"{f.name} must be at least 1, got {value}")
            if (f.name.endswith(("frequency", "period", "timeout"))) and value <= 0:
                raise ConfigError(f"{f.name} must be positive, got {value}")
    for name in ("low_battery_threshold_percent", "critical_battery_threshold_percent",
                 "update_charging_anim_step"):
        value = getattr(lights, name)
        if not 0.0 <= value <= 1.0:
            raise ConfigError(f"{name} is a fraction in [0, 1], got {value}")
    if lights.update_charging_anim_step <= 0:
        raise ConfigError("update_charging_anim_step must be positive")
    warnings: list[str] = []
    if lights.critical_battery_threshold_percent > lights.low_battery_threshold_percent:
        warnings.append("critical battery threshold is above the low battery threshold")
    if safety.cpu_fan_off_temp >= safety.cpu_fan_on_temp:
        warnings.append("cpu fan_off temperature is not below fan_on: no hysteresis")
    if safety.driver_fan_off_temp >= safety.driver_fan_on_temp:
        warnings.append("driver fan_off temperature is not below fan_on: no hysteresis")
    if safety.critical_bat_temp >= safety.fatal_bat_temp:
        warnings.append("critical battery temperature is not below the fatal one")
    return warnings


def _upper_names(params: LightsParams | SafetyParams, names: str) -> dict[str, Any]:
    """`names` (space-separated fields of `params`) as constants: the manual spells them upper case."""
    return {name.upper(): getattr(params, name) for name in names.split()}


def lights_constants(p: LightsParams) -> dict[str, Any]:
    """The Lights tree's constant blackboard entries, by the manual's names."""
    return {
        **_upper_names(p, "battery_state_anim_period critical_battery_anim_period"
                          " critical_battery_threshold_percent low_battery_anim_period"
                          " low_battery_threshold_percent"),
        **ANIMATION_ID_CONSTANTS,
        **STATUS_CONSTANTS,
        **HEALTH_CONSTANTS,
    }


def safety_constants(p: SafetyParams) -> dict[str, Any]:
    """The Safety tree's constant blackboard entries, by the manual's (and 2.1's) names."""
    return {
        **_upper_names(p, "cpu_fan_off_temp cpu_fan_on_temp driver_fan_off_temp driver_fan_on_temp"
                          " fan_turn_off_timeout high_bat_temp critical_bat_temp fatal_bat_temp"),
        **HEALTH_CONSTANTS,
        **STATUS_CONSTANTS,
    }


def shutdown_constants(p: SafetyParams) -> dict[str, Any]:
    """The Shutdown tree's constant entries (the manual's and 2.1's name for the hosts file)."""
    return {
        "SHUTDOWN_HOSTS_PATH": p.shutdown_hosts_path,
        "SHUTDOWN_HOSTS_FILE": p.shutdown_hosts_path,
        "SHUTDOWN_LOCALHOST_COMMAND": p.shutdown_localhost_command,
    }


def default_config(shutdown_hosts_path: str | Path | None = None) -> ManagerConfig:
    """The manual's defaults, optionally with a shutdown hosts file."""
    config = ManagerConfig()
    if shutdown_hosts_path is not None:
        config = replace(config, safety=replace(config.safety,
                                                shutdown_hosts_path=str(Path(shutdown_hosts_path))))
    return config
