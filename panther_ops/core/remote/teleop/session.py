"""`teleop`'s interactive session: the prepared command run with a pseudo-terminal on the
robot over its one SSH connection, this terminal's keys sent to it (``transport.interactive``)."""

from __future__ import annotations

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.remote.teleop.keyboard import TeleopPlan
from panther_ops.errors import UsageError
from panther_ops.transport.interactive import run_interactive


def drive(ctx: RobotContext, plan: TeleopPlan) -> int:
    """Run ``plan``'s keyboard program interactively; its exit status."""
    client = getattr(ctx.transport, "client", None)
    if client is None:
        raise UsageError("teleop needs an SSH robot", hint="a demo robot has no ROS to drive")
    return run_interactive(client, ctx.robot.name, plan.command)
