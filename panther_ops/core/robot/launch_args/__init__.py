"""The driver's launch arguments: one public interface over the catalogue of each stack's
arguments (`catalogue.py`: the name a stack declares, the value it takes) and the rules across
the arguments of one command (`rules.py`). Import from here, not from the two modules."""

from __future__ import annotations

from panther_ops.core.robot.launch_args.catalogue import (
    ArgConflictError,
    InvalidArgValueError,
    LaunchArgError,
    UnavailableArgError,
    UnknownArgError,
    ValidatedArg,
    args_for,
    bool_word,
    check_arg_text,
    spec,
    unavailable_text,
    validate_arg,
)
from panther_ops.core.robot.launch_args.rules import (
    RULES,
    ArgRule,
    Finding,
    canonical_args,
    check_args,
    raise_for_errors,
)

__all__ = [
    "RULES",
    "ArgConflictError",
    "ArgRule",
    "Finding",
    "InvalidArgValueError",
    "LaunchArgError",
    "UnavailableArgError",
    "UnknownArgError",
    "ValidatedArg",
    "args_for",
    "bool_word",
    "canonical_args",
    "check_arg_text",
    "check_args",
    "raise_for_errors",
    "spec",
    "unavailable_text",
    "validate_arg",
]
