"""`shutdown robot`'s executor: the robot's hosts, then the robot itself (`run.shutdown_robot`)."""

from __future__ import annotations

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.shutdown.plan import ShutdownRobot
from panther_ops.core.shutdown.run import shutdown_robot
from panther_ops.results import RobotResult


@executes(ShutdownRobot)
def shut_down(ctx: RobotContext, plan: RobotPlan, step: ShutdownRobot, opts: ApplyOptions, write: Write) -> RobotResult:
    return shutdown_robot(ctx, step.plan)
