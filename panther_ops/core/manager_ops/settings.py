"""What a deployed manager is: its names and paths on the robot, its settings from the inventory, its scenarios."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.inventory_desired import (
    MANAGER_KEYS,
    DesiredError,
    ScenarioError,
    manager_block,
    usage_error,
)
from panther_ops.core.fleet.inventory_desired import scenario_path as _scenario_path
from panther_ops.errors import UsageError

SERVICE = "panther_ops_manager"


ROBOT_DIR = "panther-ops/manager"
"""Under the robot user's home: ``/home/husarion/panther-ops/manager``."""


CONTAINER_DIR = "/opt/panther-ops/manager"


STATE_FILE = "deployed.json"


DISABLE_ARG = "disable_manager"


DISABLE_SINCE = (2, 0, 1)


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


SETTINGS = MANAGER_KEYS
"""The keys of ``desired.manager``, checked when the inventory loads (`fleet/inventory_desired.manager_block`)."""


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
    """``desired.manager`` as the inventory checked it when it loaded (`manager_block`, called
    again for a caller that gives a block of its own: UsageError); ``sim``/``scenario`` override it."""
    try:
        raw = manager_block(desired.get("manager"))
    except DesiredError as bad:
        raise usage_error(bad) from None
    mode = raw.get("mode", "ros2")
    if sim is not None:
        mode = "sim" if sim else "ros2"
    return ManagerSettings(raw.get("enabled", True), mode, str(scenario or raw.get("scenario", "charging")),
                           dict(raw.get("params") or {}), raw.get("shutdown_hosts"))


def scenario_path(name: str) -> Path:
    """A shipped scenario by name (``charging``), else a local file (UsageError: neither)."""
    try:
        return _scenario_path(name)
    except ScenarioError as exc:
        raise UsageError(f"scenario {exc}", hint=exc.hint) from None
