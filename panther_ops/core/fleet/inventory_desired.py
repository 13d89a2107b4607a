"""The inventory's ``desired:`` blocks: one validator per block, run when the inventory loads.

Each layer (``defaults``, each group, each robot) is checked whole: unknown keys, every value
(``enabled: false`` or not), types, numbers (ASCII digits, `core/parse/numbers.py`), and two
names of one setting in one block (a launch argument under two of its names, a controller
limit with and without ``controller.``, a manager parameter under its 2.0 and 2.1 names, the
manager's shutdown hosts file given twice). Each robot's merged block is checked again, for
names of one setting that come from different layers. So `inventory validate`, `doctor`,
`apply` and `config diff` refuse the same block with the same message (exit 2, nothing
contacted); the commands that use a block (`gps/desired.py`, `manager_ops/settings.py`,
`health/gps_check.py`) read values checked here, and what only a robot can tell (its stack's
arguments, its wheels' limits, a file on it) is still checked by them.

A refusal is a `DesiredError`: the path of the key inside ``desired:`` (the inventory names
the file, line and ``robots.NAME.desired...`` key), the value and what is allowed.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.inventory_values import DESIRED_KEYS
from panther_ops.core.parse.numbers import NumberError, port
from panther_ops.core.parse.ros_names import RosNameError, namespace
from panther_ops.errors import UsageError

KeyPath = tuple[str | int, ...]


class DesiredError(Exception):
    """A desired block that is not allowed: ``path`` inside ``desired:``, what is wrong, what is allowed."""

    def __init__(self, path: KeyPath, message: str, hint: str | None = None, other: KeyPath | None = None) -> None:
        super().__init__(message)
        self.path = path
        self.message = message
        self.hint = hint
        self.other = other
        """The other name of the same setting, for two names of one setting."""

    @property
    def key(self) -> str:
        return _dotted(self.path)


def check_desired(block: Mapping[str, Any]) -> dict[str, Any]:
    """A whole ``desired:`` block, checked; its values as the commands read them (a port
    written ``"5000"`` is 5000). Raises DesiredError."""
    out: dict[str, Any] = {}
    for key, value in block.items():
        check = BLOCKS.get(key)
        if check is None:
            raise DesiredError((key,), f"unknown desired setting {key!r}",
                               "allowed: " + ", ".join(sorted(DESIRED_KEYS)))
        out[key] = check(value)
    return out


def usage_error(bad: DesiredError) -> UsageError:
    """A refusal for a command given a block directly (a planner's caller), not through the inventory."""
    return UsageError(f"desired.{bad.message}", hint=bad.hint)


def _mapping(path: KeyPath, value: Any, keys: str) -> Mapping[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise DesiredError(path, f"{_dotted(path)} must be a mapping, not {value!r}", keys)
    return value


def _dotted(path: KeyPath) -> str:
    return ".".join(str(p) for p in path)


def _same(path: KeyPath, first: str, second: str, what: str) -> DesiredError:
    block = _dotted(path)
    return DesiredError((*path, second), f"{block}.{first} and {block}.{second} are one {what}: "
                        "they would overwrite each other", f"keep one of them ({first} or {second})",
                        other=(*path, first))


def _unknown(path: KeyPath, value: Mapping[str, Any], allowed: Mapping[str, str] | tuple[str, ...]) -> None:
    for key in value:
        if key not in allowed:
            raise DesiredError((*path, key), f"{_dotted((*path, key))}: unknown key",
                               "allowed: " + ", ".join(allowed))


def _bool(path: KeyPath, value: Any) -> bool:
    if not isinstance(value, bool):
        raise DesiredError(path, f"{_dotted(path)} {value!r} is not allowed", "true or false")
    return value


# ---------------------------------------------------------------------------------- gps
GPS_KEYS = {
    "enabled": "true: run the NMEA driver (as `gps enable`); false: take launch_nmea_gps off the driver",
    "port": "UDP port the router forwards NMEA to (default 5000)",
    "ip": "the Built-in Computer's address the driver listens on (default 10.15.20.2)",
    "namespace": "ROS namespace of the fix topic (default: the robot's)",
    "container": "true: the nmea-gps service on any stack (`gps enable --container`)",
    "router": "the router's forwarding: set by `gps router set`, not by apply (reported)",
}


_IPV4 = re.compile(r"^(25[0-5]|2[0-4]\d|1\d\d|[1-9]?\d)(\.(25[0-5]|2[0-4]\d|1\d\d|[1-9]?\d)){3}$", re.ASCII)


IP_RULE = "an IPv4 address of the Built-in Computer, e.g. 10.15.20.2"


NAMESPACE_RULE = "a ROS namespace (letters, digits and _, e.g. panther)"


def nmea_ip(value: object) -> bool:
    """An address the NMEA driver can listen on (``gps enable --ip``, ``desired.gps.ip``)."""
    return isinstance(value, str) and bool(_IPV4.match(value))


def nmea_namespace(value: object) -> bool:
    """A namespace the NMEA launch file takes as ``robot_namespace:=`` and the service as
    ``__ns:=/<ns>``: a valid ROS namespace (core/parse/ros_names) of one token."""
    if not isinstance(value, str) or not value or "/" in value:
        return False
    try:
        namespace(value)
    except RosNameError:
        return False
    return True


def _namespace_why(value: object) -> str:
    """What the ROS name rules say of a namespace the NMEA driver cannot take ('' if only the
    one-token rule refuses it)."""
    try:
        namespace(value)
    except RosNameError as exc:
        return f": {exc}"
    return ": one token, without '/'"


def gps_block(value: Any) -> dict[str, Any]:
    """``desired.gps`` (docs/gps.md): every key, enabled or not."""
    path: KeyPath = ("gps",)
    gps = _mapping(path, value, "keys: " + ", ".join(GPS_KEYS))
    _unknown(path, gps, GPS_KEYS)
    out = dict(gps)
    for key in ("enabled", "container"):
        if key in gps:
            _bool((*path, key), gps[key])
    if "port" in gps:
        try:
            out["port"] = port(gps["port"])
        except NumberError as exc:
            raise DesiredError((*path, "port"), f"gps.port {gps['port']!r} is not a UDP port", str(exc)) from None
    if "ip" in gps and not nmea_ip(gps["ip"]):
        raise DesiredError((*path, "ip"), f"gps.ip {gps['ip']!r} is not allowed", IP_RULE)
    if "namespace" in gps and not nmea_namespace(gps["namespace"]):
        raise DesiredError((*path, "namespace"), f"gps.namespace {gps['namespace']!r} is not allowed"
                           + _namespace_why(gps["namespace"]), NAMESPACE_RULE)
    if "router" in gps and not isinstance(gps["router"], (bool, Mapping)):
        raise DesiredError((*path, "router"), f"gps.router {gps['router']!r} is not allowed",
                           "true/false or a mapping of `gps router set` settings")
    return out


# ---------------------------------------------------------------------------------- manager
MANAGER_KEYS = {
    "enabled": "deploy the manager on this robot (default true)",
    "mode": "ros2 (default, on the robot's ROS 2 graph) or sim (the simulation adapter, for labs)",
    "scenario": "sim: a shipped scenario name (charging, low_battery, ...) or a local scenario file",
    "params": "manager parameters (docs/manager.md), e.g. battery.percent.threshold.low: 0.3",
    "shutdown_hosts": "robot path of the shutdown hosts file (default: the one the driver uses)",
}


MODES = ("ros2", "sim")


_HOSTS_PARAMS = ("shutdown_hosts_path", "shutdown_hosts_config_path")
"""Manager parameters that name the shutdown hosts file, as ``manager.shutdown_hosts`` does."""


def manager_block(value: Any) -> dict[str, Any]:
    """``desired.manager`` (docs/manager-deploy.md): every key, enabled or not."""
    path: KeyPath = ("manager",)
    manager = _mapping(path, value, "keys: " + ", ".join(MANAGER_KEYS))
    _unknown(path, manager, MANAGER_KEYS)
    if "enabled" in manager:
        _bool((*path, "enabled"), manager["enabled"])
    if "mode" in manager and manager["mode"] not in MODES:
        raise DesiredError((*path, "mode"), f"manager.mode {manager['mode']!r} is not allowed", "ros2 or sim")
    if "scenario" in manager:
        name = manager["scenario"]
        if not isinstance(name, str) or not name.strip():
            raise DesiredError((*path, "scenario"), f"manager.scenario {name!r} is not allowed",
                               "a shipped scenario name or a scenario file")
        try:
            scenario_path(name)
        except ScenarioError as exc:
            raise DesiredError((*path, "scenario"), f"manager.scenario {exc}", exc.hint) from None
    hosts = manager.get("shutdown_hosts")
    if hosts is not None and (not isinstance(hosts, str) or not hosts.startswith("/") or ".." in hosts.split("/")):
        raise DesiredError((*path, "shutdown_hosts"), f"manager.shutdown_hosts {hosts!r} is not allowed",
                           "an absolute path on the robot, without '..' (e.g. /home/husarion/shutdown_hosts.yaml)")
    if "params" in manager:
        params = _mapping((*path, "params"), manager["params"], "a mapping of manager parameters (docs/manager.md)")
        _manager_params((*path, "params"), params)
        given = [k for k in _HOSTS_PARAMS if k in params]
        if hosts is not None and given:
            raise DesiredError((*path, "params", given[0]),
                               f"manager.shutdown_hosts and manager.params.{given[0]} both choose the shutdown "
                               "hosts file", "keep manager.shutdown_hosts (a file on the robot, mounted for "
                               "the manager)")
    return dict(manager)


def _manager_params(path: KeyPath, params: Mapping[str, Any]) -> None:
    from panther_ops.manager.config import config_with_params, param_targets
    from panther_ops.manager.errors import ManagerError

    seen: dict[str, str] = {}
    for key, target in param_targets(params).items():
        if target is None:
            raise DesiredError((*path, key), f"manager.params.{key}: not a manager parameter",
                               "the names of docs/manager.md (e.g. battery.percent.threshold.low, "
                               "cpu.temp.fan_on); timer_frequency and ros_communication_timeout.* "
                               "need the node: lights.timer_frequency, safety.timer_frequency")
        if target and target in seen:
            raise _same(path, seen[target], key, "manager parameter")
        seen[target] = key
    try:
        config_with_params(params, source="desired.manager.params")
    except ManagerError as exc:
        raise DesiredError(path, f"manager.params: {exc}",
                           "the types and ranges of docs/manager.md") from None


class ScenarioError(Exception):
    def __init__(self, message: str, hint: str) -> None:
        super().__init__(message)
        self.hint = hint


def scenario_path(name: str) -> Path:
    """A shipped scenario by name (``charging``), else a local file. Raises ScenarioError."""
    from panther_ops.core.fleet.templates import template_file

    if "/" not in name and not name.endswith((".yaml", ".yml")):
        path = template_file("manager", "scenarios", f"{name}.yaml") if _shipped(name) else Path(name)
    else:
        path = Path(name)
    if not path.is_file():
        raise ScenarioError(f"{name}: no such shipped scenario or file",
                            "shipped: " + ", ".join(shipped_scenarios()))
    return path


def _scenarios() -> list[Path]:
    from panther_ops.core.fleet.templates import template_path

    return sorted(template_path("manager", "scenarios").glob("*.yaml"))


def shipped_scenarios() -> list[str]:
    """The names of the scenarios panther-ops ships (``--scenario NAME``), sorted."""
    return [p.stem for p in _scenarios()]


def _shipped(name: str) -> bool:
    return name in shipped_scenarios()


# ---------------------------------------------------------------------------------- launch_args, controller
def launch_args_block(value: Any) -> dict[str, Any]:
    """``desired.launch_args``: argument -> one value. Names and values that no stack takes,
    and two names of one argument; whether the robot's stack declares the argument and takes
    the value is `apply`'s check (its ``--force`` writes what the catalogue does not know)."""
    from panther_ops.core.kinds.arg_catalogue import arg_text_problem, catalogue_key

    path: KeyPath = ("launch_args",)
    args = _mapping(path, value, "a mapping of launch argument -> value (e.g. wheel_type: WH02)")
    seen: dict[str, str] = {}
    for key, arg in args.items():
        if not isinstance(arg, (str, int, float)):  # bool is an int
            raise DesiredError((*path, key), f"launch_args.{key} {arg!r} is not allowed",
                               "one value: text, a number, true or false")
        problem = arg_text_problem(str(key), str(arg).strip())
        if problem is not None:
            raise DesiredError((*path, key), f"launch_args: {problem[0]}", problem[1])
        canonical = catalogue_key(str(key)) or str(key)
        if canonical in seen:
            raise _same(path, seen[canonical], key, "launch argument")
        seen[canonical] = key
    return dict(args)


def controller_block(value: Any) -> dict[str, Any]:
    """``desired.controller``: limit -> value, the key known and the value of its type; the
    wheels' limits are `apply`'s check (the robot's wheel type)."""
    from panther_ops.core.kinds.controller_limits import ControllerError, limit_value

    path: KeyPath = ("controller",)
    limits = _mapping(path, value, "a mapping of controller limit -> value (e.g. linear.x.max_velocity: 1.0)")
    seen: dict[str, str] = {}
    for key, limit in limits.items():
        try:
            lk, _ = limit_value(str(key), limit)
        except ControllerError as exc:
            message = exc.message if exc.message.startswith("controller.") else f"controller.{key}: {exc.message}"
            raise DesiredError((*path, key), message,
                               exc.hint or "a number (true or false for has_*_limits)") from None
        if lk.dotted in seen:
            raise _same(path, seen[lk.dotted], key, "controller limit")
        seen[lk.dotted] = key
    return dict(limits)


# ---------------------------------------------------------------------------------- the others
def image_value(value: Any) -> str:
    if not isinstance(value, str) or ":" not in value:
        raise DesiredError(("image",), f"image {value!r} is not allowed",
                           "REPOSITORY:TAG, e.g. husarion/panther:humble-2.1.1-20240828")
    return value


def webui_block(value: Any) -> dict[str, Any]:
    """``desired.webui``: the snap's keys (or their short names) with its configure hook's rules."""
    from panther_ops.core.kinds.webui_settings import SettingError, canonical_key, validate

    path: KeyPath = ("webui",)
    webui = _mapping(path, value, "a mapping of WebUI settings (docs/remote.md)")
    seen: dict[str, str] = {}
    for key, setting in webui.items():
        try:
            validate({key: setting})
        except SettingError as bad:
            raise DesiredError((*path, key), str(bad)) from None
        name = canonical_key(str(key))
        if name in seen:  # `port` and `webui.port`: which one is meant is not known
            first = seen[name]
            raise DesiredError((*path, key), f"{first}={webui[first]!r} and {key}={setting!r} both set {name}",
                               "keep one of them (in desired.webui)", other=(*path, first))
        seen[name] = str(key)
    return dict(webui)


def shutdown_hosts_block(value: Any) -> list[Any]:
    """``desired.shutdown_hosts``: entries of a shutdown hosts file, each checked by its one
    validator (either format: the robot's stack decides which it uses)."""
    from panther_ops.core.kinds.hostsfile import check_entry

    path: KeyPath = ("shutdown_hosts",)
    if not isinstance(value, list) or not all(isinstance(h, Mapping) for h in value):
        raise DesiredError(path, "shutdown_hosts must be a list of mappings (ip, username, ...)",
                           "docs/shutdown.md: ip, username, port, command, timeout, ping_for_success "
                           "(SSH) or ip, port, secret, timeout (HTTP, 2.2.1+)")
    for i, entry in enumerate(value):
        for finding in check_entry(entry):
            if finding.level == "error":
                field = finding.where.split(".", 1)[1] if "." in finding.where else None
                where: KeyPath = (*path, i) if field is None else (*path, i, field)
                raise DesiredError(where, f"shutdown_hosts[{i}]{'.' + field if field else ''}: {finding.message}",
                                   "docs/shutdown.md")
    return list(value)


BLOCKS: dict[str, Callable[[Any], Any]] = {
    "launch_args": launch_args_block,
    "controller": controller_block,
    "image": image_value,
    "webui": webui_block,
    "gps": gps_block,
    "shutdown_hosts": shutdown_hosts_block,
    "manager": manager_block,
}
"""One validator per key of ``desired:`` (`inventory_values.DESIRED_KEYS`)."""
