"""What a deployed manager is: its names and paths on the robot, its settings from the inventory, its scenarios."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.templates import template_file
from panther_ops.errors import UsageError

SERVICE = "panther_ops_manager"


ROBOT_DIR = "panther-ops/manager"
"""Under the robot user's home: ``/home/husarion/panther-ops/manager``."""


CONTAINER_DIR = "/opt/panther-ops/manager"


STATE_FILE = "deployed.json"


DISABLE_ARG = "disable_manager"


DISABLE_SINCE = (2, 0, 1)


BT_FILES = ("PantherLightsBT.btproj", "lights.xml", "PantherSafetyBT.btproj", "safety.xml", "shutdown.xml")


HOSTS_TARGET = "/etc/panther-ops/shutdown_hosts.yaml"


DBUS_SOCKET = "/run/dbus/system_bus_socket"


#: the 2.2 stack powers the Built-in Computer off over D-Bus (panther-stack.md 1.10)
DBUS_POWEROFF = ("dbus-send --system --print-reply --dest=org.freedesktop.login1 /org/freedesktop/login1 "
                 "org.freedesktop.login1.Manager.PowerOff boolean:true")


#: 2.0/2.1 shut the computer down from the container over SSH as husarion (ShutdownSingleHost localhost)
SSH_POWEROFF = ("ssh -o BatchMode=yes -o StrictHostKeyChecking=accept-new -i /root/.ssh/id_rsa "
                "husarion@127.0.0.1 sudo shutdown now")


#: driver volumes the manager gets too (read-only): robot environment, SSH key
_SHARED_TARGETS = ("/root/.ssh/id_rsa", "/run/husarion/")


SETTINGS = {
    "enabled": "deploy the manager on this robot (default true)",
    "mode": "ros2 (default, on the robot's ROS 2 graph) or sim (the simulation adapter, for labs)",
    "scenario": "sim: a shipped scenario name (charging, low_battery, ...) or a local scenario file",
    "params": "manager parameters (docs/manager.md), e.g. battery.percent.threshold.low: 0.3",
    "shutdown_hosts": "robot path of the shutdown hosts file (default: the one the driver uses)",
}


MODES = ("ros2", "sim")


@dataclass(frozen=True)
class ManagerSettings:
    """What to deploy on one robot: the inventory's ``desired.manager`` plus command-line overrides."""

    enabled: bool = True
    mode: str = "ros2"
    scenario: str = "charging"
    params: Mapping[str, Any] = field(default_factory=dict)
    shutdown_hosts: str | None = None


def manager_settings(desired: Mapping[str, Any], *, sim: bool | None = None,
                     scenario: str | None = None) -> ManagerSettings:
    """Read ``desired.manager`` (unknown keys and values: UsageError); ``sim``/``scenario`` override it."""
    raw = desired.get("manager") or {}
    if not isinstance(raw, Mapping):
        raise UsageError("desired.manager must be a mapping", hint="keys: " + ", ".join(SETTINGS))
    unknown = sorted(set(raw) - set(SETTINGS))
    if unknown:
        raise UsageError(f"desired.manager: unknown setting {unknown[0]!r}", hint="allowed: " + ", ".join(SETTINGS))
    mode = str(raw.get("mode", "ros2"))
    if mode not in MODES:
        raise UsageError(f"desired.manager.mode {mode!r}: use ros2 or sim")
    if sim is not None:
        mode = "sim" if sim else "ros2"
    params = raw.get("params") or {}
    if not isinstance(params, Mapping):
        raise UsageError("desired.manager.params must be a mapping of manager parameters")
    hosts = raw.get("shutdown_hosts")
    if hosts is not None and (not isinstance(hosts, str) or not hosts.startswith("/")):
        raise UsageError("desired.manager.shutdown_hosts must be an absolute path on the robot")
    return ManagerSettings(bool(raw.get("enabled", True)), mode, str(scenario or raw.get("scenario", "charging")),
                           dict(params), hosts)


def scenario_path(name: str) -> Path:
    """A shipped scenario by name (``charging``), else a local file."""
    if "/" not in name and not name.endswith((".yaml", ".yml")):
        path = template_file("manager", "scenarios", f"{name}.yaml") if _shipped(name) else Path(name)
    else:
        path = Path(name)
    if not path.is_file():
        raise UsageError(f"scenario {name}: no such shipped scenario or file",
                         hint="shipped: " + ", ".join(sorted(p.stem for p in _scenarios())))
    return path


def _scenarios() -> list[Path]:
    from panther_ops.core.fleet.templates import template_path

    return sorted(template_path("manager", "scenarios").glob("*.yaml"))


def _shipped(name: str) -> bool:
    return any(p.stem == name for p in _scenarios())
