"""`gps router set`, carried out: the PUTs of the plan (`plan.py`, pure) through the robot's
connection, then the router's state read back (`read.py`) must be as asked."""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.credentials import Credentials
from panther_ops.core.gps.router.plan import RouterRequest, changes, describe_puts, summary_of
from panther_ops.core.gps.router.read import open_router, read_state
from panther_ops.results import Outcome, RobotResult


def apply_router(address: str, creds: Credentials, req: RouterRequest) -> Any:
    """Carry out a plan: the PUTs, then the state read back must be as asked (else failed)."""
    def apply(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
        result = RobotResult(ctx.robot.name, Outcome.CHANGED, plan.summary, warnings=list(plan.warnings),
                             data=dict(plan.data))
        api = open_router(ctx, address, creds)
        for path, body in plan.data["puts"].items():
            api.call("PUT", path, {"data": body})
        state = read_state(api)
        result.data["after"] = summary_of(state)
        left = changes(state, req)
        if left:
            result.outcome = Outcome.FAILED
            result.message = f"the router did not keep: {describe_puts(state, left)}"
        return result

    return apply
