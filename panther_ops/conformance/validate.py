"""Run a kind's validator (the registry's, the one every writing path uses) on a robot of a release."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from panther_ops.conformance.preview import kinds_stack
from panther_ops.core.kinds import FileKind, FileKindError, Target, check_file
from panther_ops.core.robot.launch_args import spec
from panther_ops.errors import OpsError


def target_for(tag: str, wheel_type: str | None, robot_model: str) -> Target:
    """The robot an upstream default file of ``tag`` is meant for (on a release panther-ops does
    not support yet: its preview's stack, `preview.kinds_stack`).

    Raises:
        OpsError: panther-ops does not support the release, and no preview covers it.
    """
    stack = kinds_stack(tag)
    return Target(stack, wheel_type or spec("wheel_type").default_for(stack, robot_model))


def run_validator(tag: str, kind: str, source: str, data: bytes, local: Path | None,
                  wheel_type: str | None, robot_model: str) -> dict[str, Any]:
    """``{"accepted": True/False/None, "errors": [...], "warnings": [...]}`` (None: not run)."""
    try:
        target = target_for(tag, wheel_type, robot_model)
    except (OpsError, ValueError) as exc:
        return {"accepted": None, "errors": [f"not run: {exc}"], "warnings": []}
    try:
        warnings = check_file(FileKind(kind), source, data, local=local, target=target)
    except FileKindError as exc:
        return {"accepted": False, "errors": list(exc.errors), "warnings": []}
    except OpsError as exc:
        return {"accepted": False, "errors": [exc.message], "warnings": []}
    return {"accepted": True, "errors": [], "warnings": list(warnings)}
