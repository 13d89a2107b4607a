"""`panther-ops apply` and `config diff` on one robot: read compose.yaml (kept for the write
when there is a desired state to converge) and the files the planner (`plan_desired.py`) asks for."""

from __future__ import annotations

from panther_ops.core.apply import plan_desired as planner
from panther_ops.core.config.robot import read_compose
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext


def plan_desired(ctx: RobotContext, *, force: bool = False) -> RobotPlan:
    """Converge the robot to the inventory's ``desired:`` launch_args, controller and image."""
    desired = ctx.robot.desired
    raw = read_compose(ctx, keep=bool(desired))
    return read_and_plan(ctx, lambda reads: planner.plan_desired(raw, reads, desired, force=force))
