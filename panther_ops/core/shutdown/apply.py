"""`shutdown robot`'s executor: the robot's hosts, then the robot itself (`run.shutdown_robot`);
`shutdown --hosts FILE`'s: one host of the file."""

from __future__ import annotations

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.shutdown.plan import ShutdownFileHost, ShutdownRobot
from panther_ops.core.shutdown.run import shutdown_robot
from panther_ops.results import RobotResult


@executes(ShutdownRobot)
def shut_down(ctx: RobotContext, plan: RobotPlan, step: ShutdownRobot, opts: ApplyOptions, write: Write) -> RobotResult:
    return shutdown_robot(ctx, step.plan)


@executes(ShutdownFileHost)
def shut_file_host_down(ctx: RobotContext, plan: RobotPlan, step: ShutdownFileHost, opts: ApplyOptions,
                        write: Write) -> RobotResult:
    """One host of a hosts file, from here or through the robot (the target's connection)."""
    from dataclasses import replace

    from panther_ops.core.shutdown.links import backends_here, backends_via
    from panther_ops.core.shutdown.run import shutdown_hosts
    from panther_ops.transport.lan import RobotLink

    backends = backends_via(RobotLink(ctx.transport, step.via)) if step.via else \
        backends_here(step.known_hosts, step.identity)
    (result,) = shutdown_hosts([step.host], backends, command=opts.command).results
    return replace(result, robot=ctx.robot.name, data={**plan.data, **result.data})
