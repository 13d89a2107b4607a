"""`gps router set` and `gps enable --router`, carried out: the PUTs of the plan's
:class:`~panther_ops.core.gps.router.plan.RouterPuts` step (`plan.py`, pure) through the
robot's connection, then the router's state read back (`read.py`) must be as asked."""

from __future__ import annotations

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.gps.router.plan import RouterPuts, changes, describe_puts, summary_of
from panther_ops.core.gps.router.read import open_router, read_state
from panther_ops.errors import UsageError
from panther_ops.results import Outcome, RobotResult


@executes(RouterPuts)
def put_router(ctx: RobotContext, plan: RobotPlan, step: RouterPuts, opts: ApplyOptions, write: Write) -> RobotResult:
    """The PUTs, then the state read back must be as asked (else failed); after the driver's
    write (``after_driver``) only when that went well."""
    if step.after_driver:
        result = write(opts)
        if result.outcome not in (Outcome.CHANGED, Outcome.OK) or opts.dry_run:
            return result
    else:
        result = RobotResult(ctx.robot.name, Outcome.CHANGED, plan.summary, warnings=list(plan.warnings),
                             data=dict(plan.data))
    if step.creds is None:
        raise UsageError(f"no router credentials for {ctx.robot.name}")
    api = open_router(ctx, step.address, step.creds)
    for path, body in step.puts.items():
        api.call("PUT", path, {"data": body})
    state = read_state(api)
    result.data["router_after" if step.after_driver else "after"] = summary_of(state)
    left = changes(state, step.request)
    if left:
        result.outcome = Outcome.FAILED
        result.message = (f"{plan.summary}; " if step.after_driver else "") + \
            f"the router did not keep: {describe_puts(state, left)}"
    elif step.after_driver:
        result.outcome = Outcome.CHANGED
        result.message = plan.summary
    return result
