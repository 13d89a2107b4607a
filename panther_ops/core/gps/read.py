"""The reads of `gps enable|disable`: compose.yaml (kept for the write) and the files the
planners (`plan.py`, pure) ask for, over the robot's one connection; then the plan."""

from __future__ import annotations

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps import plan as planner
from panther_ops.core.gps.plan import GpsOptions
from panther_ops.core.robot.read import read_compose


def read_and_plan_enable(ctx: RobotContext, opts: GpsOptions) -> RobotPlan:
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planner.plan_enable(raw, reads, opts))


def read_and_plan_disable(ctx: RobotContext) -> RobotPlan:
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planner.plan_disable(raw, reads))
