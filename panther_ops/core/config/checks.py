"""Checks of `config` input that need no robot: refuse what no supported stack accepts."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from panther_ops.core.robot.launch_args import validate_arg
from panther_ops.core.stack import stack_from_version
from panther_ops.errors import UsageError

REPRESENTATIVE = ("2.0.0", "2.0.4", "2.1.0", "2.1.1", "2.2.0", "2.2.2", "2.3.0", "2.3.1", "2.3.2")
"""A version of every generation and the last of each release line (`stack.LINES`): a key or value
that one of them accepts passes the robot-less check (tests/config/test_checks_versions.py)."""


def precheck_key(key: str, *, known: bool = True) -> None:
    """Refuse a key no robot can have before any robot is read: a controller limit key that
    does not parse, a launch argument name with characters no name has, or (``known``) a
    launch argument not in the catalogue.

    Raises:
        UsageError: naming the key, with close names where there are some.
    """
    if key.startswith("controller."):
        from panther_ops.core.kinds.controller_limits import parse_limit_key

        parse_limit_key(key)
        return
    from panther_ops.core.robot.launch_args import check_arg_text, spec

    check_arg_text(key, "")
    if known:
        spec(key)


def precheck(values: Mapping[str, Any], *, force: bool = False) -> None:
    """Raise the first error when a key/value is refused on every supported stack.

    A value that some stack accepts passes here; each robot's plan then checks it against
    that robot's own stack.
    """
    for key, value in values.items():
        if key.startswith("controller."):  # loaded only for controller keys: start-up stays short
            from panther_ops.core.kinds.controller_limits import parse_limit_key, validate_limit
        errors: list[UsageError] = []
        relevant: list[UsageError] = []
        """errors of stacks that have the key: they are about the value, not about a version"""
        for version in REPRESENTATIVE:
            stack = stack_from_version(version)
            try:
                if key.startswith("controller."):
                    lk = parse_limit_key(key)
                    wheels = ("WH02",) if lk.axis == "linear.y" else ("WH01", "WH02", "WH04")
                    wheel_errors: list[UsageError] = []
                    for wheel in wheels:
                        try:
                            validate_limit(stack, wheel, key, value, force=force)
                        except UsageError as exc:
                            wheel_errors.append(exc)
                    if len(wheel_errors) == len(wheels):
                        raise wheel_errors[0]
                else:
                    validate_arg(stack, key, str(value), force=force)
            except UsageError as exc:
                errors.append(exc)
                if key.startswith("controller.") or _has_key(stack, key):
                    relevant.append(exc)
        if len(errors) == len(REPRESENTATIVE):
            # no robot is at hand here: a "needs version X; this robot runs Y" of one stack would
            # name a version the robot may not run; the value's own error is the one that holds
            raise (relevant or errors)[0]


def _has_key(stack: Any, key: str) -> bool:
    from panther_ops.core.robot.launch_args import spec

    try:
        return spec(key).available(stack)
    except UsageError:
        return False


def parse_value(text: str) -> Any:
    """A controller limit's value as typed: true/false, a number in ASCII digits, else the text
    (which the limit's validator refuses, naming it)."""
    from panther_ops.core.parse.numbers import NumberError, ascii_int, decimal

    lowered = text.strip().lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    try:
        return decimal(text.strip()) if any(c in text for c in ".eE") else ascii_int(text.strip(), signed=True)
    except NumberError:
        return text
