"""The reader side of read -> plan -> apply: run a pure planner, reading what it asks for.

Every read goes over the robot's one open transport (``ctx.transport``), one round trip per
file, as the planner asks for it (see `reads.py`); nothing here decides what a plan holds.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, TypeVar

from panther_ops.core.fleet.confine import compose_path_problem
from panther_ops.core.fleet.reads import Need, NotRead, Reads
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import OpsError, UsageError

T = TypeVar("T")

FactReader = Callable[[RobotContext, str], Any]


def compose_file(ctx: RobotContext) -> str:
    """The robot's compose file as the inventory names it, once checked (UsageError otherwise)."""
    path = ctx.robot.compose_file
    problem = compose_path_problem(path)
    if problem is not None:
        raise UsageError(problem[0], hint=problem[1])
    local_path = getattr(ctx.transport, "local_path", None)
    if local_path is not None:  # a demo robot: the file must be inside the robot's directory, links resolved
        try:
            local_path(path)
        except OpsError as exc:
            raise UsageError(f"compose_file {path} leaves the robot's directory ({exc.message})") from None
    return path


def read_file(ctx: RobotContext, path: str) -> bytes | None:
    """A robot file's content (None: it does not exist)."""
    try:
        return ctx.transport.read_file(path)
    except FileNotFoundError:
        return None


def read_and_plan(ctx: RobotContext, planner: Callable[[Reads], T],
                  facts: Mapping[str, FactReader] | None = None, reads: Reads | None = None) -> T:
    """``planner(reads)``, reading each file (or fact, with ``facts[kind]``) it asks for first."""
    reads = reads or Reads(ctx.robot.name, ctx.robot.stack, ctx.robot.namespace)
    while True:
        try:
            return planner(reads)
        except NotRead as exc:
            reads_one(ctx, reads, exc.need, facts or {})


def reads_one(ctx: RobotContext, reads: Reads, need: Need, facts: Mapping[str, FactReader]) -> None:
    if need.kind == "file":
        if need.key in reads.files:  # asked twice: the planner is not a function of its reads
            raise RuntimeError(f"planner asked again for {need.key}")
        reads.files[need.key] = read_file(ctx, need.key)
        return
    if need in reads.facts or need.kind not in facts:
        raise RuntimeError(f"planner asked for {need.kind} {need.key!r}, which this reader cannot read")
    reads.facts[need] = facts[need.kind](ctx, need.key)
