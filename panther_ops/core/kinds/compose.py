"""The robot's compose file: what every configuration plan writes back.

docker compose on the robot has the last word (the pipeline asks it before a rename); this
check refuses, before any robot is touched, content that cannot be a compose file at all,
and the ROS namespaces the file gives its services that no node could start under: a
``namespace:=``, ``robot_namespace:=`` or ``__ns:=`` word of a service's command, and
``ROBOT_NAMESPACE`` of a service's environment (the bringup's default namespace), by the one
parser of ROS names (`core/parse/ros_names.py`). The whole file is checked, so a value no
command changed is refused too: the plan would otherwise recreate a driver that stops at once.
A value with ``$`` (compose interpolation, a launch substitution) is left to compose.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from panther_ops.core.kinds.common import load_mapping
from panther_ops.core.kinds.registry import FileKindError, Target
from panther_ops.core.parse.ros_names import RosNameError, namespace

WHAT = "compose file"
ENV_KEY = "ROBOT_NAMESPACE"
_NS_WORD = re.compile(r"""(?:^|[\s'"])((?:robot_)?namespace|__ns):=([^\s'"]*)""")


def _namespace(value: str, where: str, errors: list[str]) -> None:
    if "$" in value:
        return
    try:
        namespace(value)
    except RosNameError as exc:
        errors.append(f"{where}={value!r}: {exc}")


def _command_namespaces(name: str, command: Any, errors: list[str]) -> None:
    if isinstance(command, list):
        command = " ".join(str(w) for w in command)
    if not isinstance(command, str):
        return
    for m in _NS_WORD.finditer(command):
        _namespace(m.group(2), f"services.{name}.command: {m.group(1)}:", errors)


def _env_namespace(name: str, env: Any, errors: list[str]) -> None:
    value: Any = None
    if isinstance(env, dict):
        value = env.get(ENV_KEY)
    elif isinstance(env, list):
        for entry in env:
            key, sep, rest = str(entry).partition("=")
            if key == ENV_KEY and sep:
                value = rest
    if isinstance(value, str):
        _namespace(value.strip().strip("'\""), f"services.{name}.environment.{ENV_KEY}", errors)


def check_compose(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    doc = load_mapping(source, data, WHAT)
    services = doc.get("services")
    errors: list[str] = []
    if not isinstance(services, dict) or not services:
        errors.append("services must be a mapping of at least one service")
    else:
        for name, svc in services.items():
            if not isinstance(svc, dict):
                errors.append(f"services.{name} must be a mapping")
                continue
            command = svc.get("command")
            if isinstance(command, str) and any(ord(c) < 32 and c not in "\n\t" for c in command):
                errors.append(f"services.{name}.command holds a control character")
            _command_namespaces(str(name), command, errors)
            _env_namespace(str(name), svc.get("environment"), errors)
    if errors:
        raise FileKindError(source, WHAT, errors)
    return []
