"""The ROS namespace a robot's driver runs under, read from its compose file and config.

One reading for every command that needs it (`config get namespace`, `lights test`, the
WebUI's default ``ros.namespace``): the driver's ``namespace:=`` launch argument (2.0.x), else
``ROBOT_NAMESPACE`` of the driver's compose ``environment`` (2.1: ``x-common-config``), else
of its ``env_file`` (2.2: ``/home/husarion/config/common/.env``, read on the robot), else the
bringup's default (the empty namespace). Each launch file declares ``namespace`` with the
default ``EnvironmentVariable("ROBOT_NAMESPACE", default_value="")`` (panther_ros 2.0.2+ and
husarion_ugv_ros 2.2: ``*_bringup/launch/bringup.launch.py``), hence this order.

Pure: a function of compose.yaml as read and the env files it asks for (:class:`Reads`).
"""

from __future__ import annotations

import posixpath
import re

from panther_ops.core.fleet.reads import Reads
from panther_ops.core.robot.robot_config import RobotConfig

ENV_KEY = "ROBOT_NAMESPACE"
_DEFAULTED = re.compile(r"^\$\{[A-Za-z_][A-Za-z0-9_]*:?-([^}]*)\}$")


def _plain(value: str | None) -> str | None:
    """A compose value as the container sees it: ``${VAR:-default}`` -> default (no variables here)."""
    if value is None:
        return None
    value = value.strip().strip("'\"")
    m = _DEFAULTED.match(value)
    return m.group(1) if m else value


def dotenv_value(text: str, key: str) -> str | None:
    """``key``'s value in a dotenv text (the last one wins, as in compose); None: not there."""
    found = None
    for raw in text.splitlines():
        line = raw.strip()
        line = line[7:].lstrip() if line.startswith("export ") else line
        if line.startswith(f"{key}="):
            found = _plain(line.split("=", 1)[1].split(" #", 1)[0])
    return found


def driver_namespace(reads: Reads, cfg: RobotConfig) -> tuple[str, str]:
    """The driver's namespace ("" = none) and where it came from."""
    arg = cfg.compose.args.get("namespace")
    if arg:
        return arg, "compose.yaml"
    env = _plain(cfg.compose.environment(cfg.service).get(ENV_KEY))
    if env is not None:
        return env, f"{ENV_KEY} in compose.yaml"
    found: tuple[str, str] | None = None
    for name in cfg.compose.env_files(cfg.service):  # later files win, as in compose
        path = name.replace("~", cfg.home, 1) if name.startswith("~/") else name
        path = path if path.startswith("/") else posixpath.join(posixpath.dirname(cfg.compose_path), path)
        raw = reads.file(path)
        if raw is None:
            continue
        value = dotenv_value(raw.decode(errors="replace"), ENV_KEY)
        if value:
            found = (value, f"{ENV_KEY} in {name}")
    return found or ("", "default")
