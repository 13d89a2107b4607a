"""A robot's docker engine, reached over its one SSH connection (none on a demo robot)."""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import RemoteStateError


class NoEngineError(RemoteStateError):
    """The robot has no docker engine to ask (a demo robot, or docker not installed)."""


def engine(ctx: RobotContext) -> tuple[Any | None, str | None]:
    """The robot's docker SDK client over its SSH connection, or (None, why)."""
    if ctx.robot.transport == "local":
        return None, "demo robot: no docker engine"
    client = ctx.transport.docker()
    if client is None:
        return None, "no docker engine on this robot"
    return client, None
