"""The robot's own shutdown hosts file, read: the file in use (see `plan.py`, whose
planners are pure) and the pipeline plan of an edit of it."""

from __future__ import annotations

from pathlib import Path

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds import FileKind
from panther_ops.core.kinds.hostsfile import POWER_BUDGET_S
from panther_ops.core.robot.files import config_file
from panther_ops.core.robot.pull import pull
from panther_ops.core.robot.push import Bundle, checked_for, push_plan
from panther_ops.core.robot.read import read_compose, read_config
from panther_ops.core.robot.robot_config import parse_config
from panther_ops.core.shutdown.plan import (
    Editor,
    RobotHostsFile,
    as_hosts_push,
    hosts_edit,
    hosts_in_use,
    plan_in_place,
)

__all__ = ["Editor", "RobotHostsFile", "plan_hosts_edit", "read_robot_hosts"]


def read_robot_hosts(ctx: RobotContext) -> RobotHostsFile:
    """The hosts file in use on the robot (see `plan.py` for the order)."""
    cfg = read_config(ctx)
    rf = read_and_plan(ctx, lambda reads: hosts_in_use(cfg, reads))
    if rf is not None:
        return rf
    data, source = pull(ctx, FileKind.SHUTDOWN_HOSTS)
    return RobotHostsFile(data.decode(errors="replace"), None, source, cfg.stack, cfg)


def plan_hosts_edit(ctx: RobotContext, editor: Editor, *, power_budget: float = POWER_BUDGET_S) -> RobotPlan:
    """A pipeline plan for an edit of the robot's hosts file (refused when it adds errors)."""
    rf = read_robot_hosts(ctx)
    edit, warnings = hosts_edit(rf, editor, power_budget, robot=ctx.robot.name)
    plan = plan_in_place(ctx.robot.name, rf, edit, warnings)
    if plan is not None:
        return plan
    cf = config_file(rf.stack, FileKind.SHUTDOWN_HOSTS)
    raw, bundle = read_compose(ctx), Bundle(Path(cf.filename), edit.text.encode())

    def pushed(reads: Reads) -> tuple[RobotPlan, list[str]]:
        plan = push_plan(reads, parse_config(raw, reads.stack), FileKind.SHUTDOWN_HOSTS, bundle)
        # the push's own check of the file (memoised: the very findings it put in the plan)
        return plan, checked_for(reads, parse_config(raw, reads.stack), FileKind.SHUTDOWN_HOSTS, bundle.main,
                                 bundle.data, False)

    plan, checked = read_and_plan(ctx, pushed)
    return as_hosts_push(plan, edit, warnings, checked)
