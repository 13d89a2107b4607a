"""`estop reset`'s executor: the reset service called (`calls.reset_task`), the E-stop read back."""

from __future__ import annotations

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.remote.estop.calls import reset_task
from panther_ops.core.remote.estop.plan import ResetEstop
from panther_ops.results import RobotResult


@executes(ResetEstop)
def reset(ctx: RobotContext, plan: RobotPlan, step: ResetEstop, opts: ApplyOptions, write: Write) -> RobotResult:
    """The reset (a demo robot: skipped, it has no driver to call)."""
    return reset_task(ctx, plan.data)
