"""`driver restart`: recreate the driver's containers through the pipeline and verify them."""

from __future__ import annotations

from panther_ops.core.config.robot import read_compose
from panther_ops.core.containers.engine import engine
from panther_ops.core.driver import planners
from panther_ops.core.fleet.pipeline import ApplyOptions, recreate_and_verify
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import project_dir, service_containers
from panther_ops.results import Outcome, RobotResult


def plan_restart(ctx: RobotContext) -> RobotPlan:
    """`driver restart`: what will be recreated (reads compose.yaml only)."""
    return planners.plan_restart(read_compose(ctx), Reads(ctx.robot.name, ctx.robot.stack))


def apply_restart(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """``docker compose up -d --force-recreate <driver>`` as the robot user, then watch it for the settle time."""
    name = ctx.robot.name
    client, why = engine(ctx)
    if client is None:
        return RobotResult(name, Outcome.SKIPPED, f"{why}: nothing to restart", data=dict(plan.data))
    service = plan.recreate[0]
    wd = project_dir(ctx, plan.compose_file, plan.home)
    before = service_containers(client, service, wd, own_only=True)
    result = RobotResult(name, Outcome.CHANGED, "", data=dict(plan.data))
    result.data["previous_container"] = before[0].id[:12] if before else None
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem:
        result.outcome = Outcome.FAILED
        result.message = problem
        result.data["hint"] = "see panther-ops driver logs"
        return result
    after = service_containers(client, service, wd, own_only=True)
    result.data["container"] = after[0].id[:12] if after else None
    result.message = f"recreated {service} ({plan.data.get('image')}); running after {opts.settle_s:g} s"
    return result
