"""The WebUI's ``ros.namespace`` defaults to the robot's namespace.

The snap leaves ``ros.namespace`` unset (topics and TF without a namespace), while the driver
runs under the robot's namespace (``panther`` on every stock Panther): the WebUI would then
show nothing. So when `webui install`, `webui set` or `apply` (``desired.webui``) do not give
``ros.namespace`` and the snap has none, the robot's namespace is set, read from its compose
file and config as `config get namespace` reads it (``namespace:=``, else ``ROBOT_NAMESPACE``
of the compose environment or env_file). A namespace set on the snap is kept as it is.

Pure: the robot's namespace is a function of compose.yaml as read and the files it asks for
(:class:`Reads`); `remote.robot_namespace` reads them.
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds.webui_settings import NAMESPACE
from panther_ops.core.robot.namespace import driver_namespace
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import OpsError

KEY = "ros.namespace"


@dataclass(frozen=True)
class RobotNamespace:
    """The robot's namespace for the WebUI (None: none to use) and why."""

    value: str | None
    note: str


def unknown_namespace(exc: OpsError) -> RobotNamespace:
    return RobotNamespace(None, f"the robot's namespace is unknown ({exc.message}): ros.namespace left as is")


def robot_namespace_of(reads: Reads, cfg: RobotConfig) -> RobotNamespace:
    """The driver's namespace as the WebUI's default, from the robot's compose file (``cfg``:
    as read, or as a plan leaves it) and config."""
    try:
        value, source = driver_namespace(reads, cfg)
    except OpsError as exc:
        return unknown_namespace(exc)
    value = value.strip("/")
    if not value:
        return RobotNamespace(None, "the robot's driver runs without a namespace: ros.namespace left unset")
    if not NAMESPACE.match(value):
        return RobotNamespace(None, f"the robot's namespace {value!r} ({source}) is not one the snap accepts "
                                    "(1-20 of a-z, 0-9, '_', not starting with a digit): ros.namespace left as "
                                    "is; set it with "
                                    "`webui set ros.namespace=...`")
    return RobotNamespace(value, f"the robot's namespace, {source}")


def with_robot_namespace(wanted: dict[str, str], current: str, robot: RobotNamespace) -> tuple[dict[str, str], str]:
    """``wanted`` with ``ros.namespace`` added when it does not give one, the snap has none and
    the robot has one; and a note of what was decided ("" when ros.namespace was given)."""
    if KEY in wanted:
        return wanted, ""
    if current:
        note = f"ros.namespace {current} kept"
        if robot.value and robot.value != current:
            note += f" (the robot's namespace is {robot.value}: `webui set ros.namespace={robot.value}` to follow it)"
        return wanted, note
    if robot.value is None:
        return wanted, robot.note
    return {**wanted, KEY: robot.value}, f"ros.namespace {robot.value}: {robot.note}"
