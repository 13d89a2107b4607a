"""The registry: file kind -> its one validator.

A validator gets the new content (and, for a local file, where it is: a BT project's
includes and an animation's images are found next to it), the robot it is meant for when
known (stack and wheel type: the controller limits and the shutdown hosts format depend on
them) and ``force``. It returns warnings, or raises `FileKindError` (exit 2) naming the
file and every error, with the message of the kind's dedicated validator.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

from panther_ops.core.stack import Stack
from panther_ops.errors import UsageError


class FileKind(str, Enum):
    """What a file is: every configuration file panther-ops knows (where a stack keeps it:
    `core.robot.files`), and the kinds it writes (each with its one validator, below). The
    values are `config push --as` names (`PUSHABLE`)."""

    CONTROLLER = "controller"
    WHEEL = "wheel"
    COMPONENTS = "components"
    LED = "led"
    USER_ANIMATIONS = "user-animations"
    BT_LIGHTS = "bt-lights"
    BT_SAFETY = "bt-safety"
    SHUTDOWN_HOSTS = "shutdown-hosts"
    BATTERY = "battery"
    JOY2TWIST = "joy2twist"
    COMPOSE = "compose"
    WORLD = "world"
    LIGHTS_DRIVER = "lights-driver"
    MANAGER_BT = "manager-bt"
    LIGHTS_MANAGER = "lights-manager"
    SAFETY_MANAGER = "safety-manager"


KNOWN_ONLY: tuple[FileKind, ...] = (FileKind.LIGHTS_DRIVER, FileKind.MANAGER_BT, FileKind.LIGHTS_MANAGER,
                                    FileKind.SAFETY_MANAGER)
"""Kinds panther-ops knows the place and default of (templates, conformance) but never writes:
no validator, not pushable (the lights driver's and the managers' node parameters)."""
CHECKED: tuple[FileKind, ...] = tuple(k for k in FileKind if k not in KNOWN_ONLY)
"""The kinds panther-ops writes or deploys: each has its one validator."""
PUSHABLE: tuple[FileKind, ...] = tuple(k for k in CHECKED if k not in (FileKind.COMPOSE, FileKind.WORLD))
"""The kinds `config push --as` and `config pull` take (compose.yaml itself is edited by the
commands that change it: config set/unset, gps enable, driver update...; a Gazebo world lives
on the simulation's machine, edited by `sim world set`)."""


@dataclass(frozen=True)
class Target:
    """The robot a file is meant for (None: not known yet, e.g. before any robot is read)."""

    stack: Stack | None = None
    wheel_type: str | None = None
    namespace: str | None = None
    """The driver's ROS namespace ("": none); the controller file's IMU broadcaster depends on it."""


class FileKindError(UsageError):
    """A file of a kind that its validator refuses (exit 2)."""

    def __init__(self, source: str, what: str, errors: Sequence[str], *, hint: str | None = None) -> None:
        lines = "\n".join(f"  {e}" for e in errors)
        count = f"{len(errors)} error" + ("" if len(errors) == 1 else "s")
        super().__init__(f"{source}: {what} refused ({count}):\n{lines}", hint=hint)
        self.source = source
        self.errors = list(errors)


Validator = Callable[[str, bytes, "Path | None", Target, bool], list[str]]
"""(source, content, local path or None, target, force) -> warnings; raises FileKindError."""


def _registry() -> dict[FileKind, Validator]:
    from panther_ops.core.kinds import bt, compose, controller, hosts, joy2twist, lights, simple, wheel, world

    return {
        FileKind.CONTROLLER: controller.check_controller,
        FileKind.WHEEL: wheel.check_wheel,
        FileKind.COMPONENTS: simple.check_components,
        FileKind.BATTERY: simple.check_battery,
        FileKind.LED: lights.check_led,
        FileKind.USER_ANIMATIONS: lights.check_user_animations,
        FileKind.BT_LIGHTS: bt.check_lights_project,
        FileKind.BT_SAFETY: bt.check_safety_project,
        FileKind.SHUTDOWN_HOSTS: hosts.check_shutdown_hosts,
        FileKind.COMPOSE: compose.check_compose,
        FileKind.JOY2TWIST: joy2twist.check_joy2twist,
        FileKind.WORLD: world.check_world,
    }


def check_file(kind: FileKind, source: str, data: bytes, *, local: Path | None = None,
               target: Target | None = None, force: bool = False) -> list[str]:
    """Check ``data`` as a file of ``kind``: its warnings, or `FileKindError` (exit 2)."""
    return validator(kind)(source, data, local, target or Target(), force)


def validator(kind: FileKind) -> Validator:
    """The one validator of ``kind`` (a kind of `CHECKED`).

    Raises:
        UsageError: ``kind`` is one panther-ops does not write (`KNOWN_ONLY`).
    """
    if kind in KNOWN_ONLY:
        raise UsageError(f"panther-ops does not write {kind.value} files",
                         hint="kinds it checks: " + ", ".join(k.value for k in CHECKED))
    return _registry()[kind]
