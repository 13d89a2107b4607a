"""The robot's compose file: what every configuration plan writes back.

docker compose on the robot has the last word (the pipeline asks it before a rename); this
check refuses, before any robot is touched, content that cannot be a compose file at all.
"""

from __future__ import annotations

from pathlib import Path

from panther_ops.core.kinds.common import load_mapping
from panther_ops.core.kinds.registry import FileKindError, Target

WHAT = "compose file"


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
    if errors:
        raise FileKindError(source, WHAT, errors)
    return []
