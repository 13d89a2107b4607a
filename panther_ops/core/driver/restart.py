"""`driver restart`: recreate the driver's containers through the pipeline and verify them."""

from __future__ import annotations

from panther_ops.core.config.robot import read_config
from panther_ops.core.containers.engine import engine
from panther_ops.core.driver.containers import compose_argv, service_containers
from panther_ops.core.fleet.pipeline import ApplyOptions, recreate_and_verify
from panther_ops.core.fleet.plan import RobotPlan, Verify
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.stack import Family
from panther_ops.results import Outcome, RobotResult

DEFAULT_SERVICE = {Family.PANTHER_ROS: "panther_ros", Family.HUSARION_UGV: "husarion_ugv_ros"}


def plan_restart(ctx: RobotContext) -> RobotPlan:
    """`driver restart`: what will be recreated (reads compose.yaml only)."""
    cfg = read_config(ctx)
    words = tuple(f"{k}:={v}" for k, v in cfg.compose.args.items()) if compose_argv(cfg) else ()
    plan = RobotPlan(ctx.robot.name, f"recreate {cfg.service} ({cfg.compose.driver_image})", [], (cfg.service,),
                     cfg.compose_path, [Verify(cfg.service, words)])
    plan.data.update(action="recreate", service=cfg.service, image=cfg.compose.driver_image)
    return plan


def apply_restart(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """``docker compose up -d --force-recreate <driver>`` as the robot user, then watch it for the settle time."""
    name = ctx.robot.name
    client, why = engine(ctx)
    if client is None:
        return RobotResult(name, Outcome.SKIPPED, f"{why}: nothing to restart", data=dict(plan.data))
    service = plan.recreate[0]
    before = service_containers(client, service)
    result = RobotResult(name, Outcome.CHANGED, "", data=dict(plan.data))
    result.data["previous_container"] = before[0].id[:12] if before else None
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem:
        result.outcome = Outcome.FAILED
        result.message = problem
        result.data["hint"] = "see panther-ops driver logs"
        return result
    after = service_containers(client, service)
    result.data["container"] = after[0].id[:12] if after else None
    result.message = f"recreated {service} ({plan.data.get('image')}); running after {opts.settle_s:g} s"
    return result
