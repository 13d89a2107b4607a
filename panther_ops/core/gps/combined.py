"""`gps enable --router`: the NMEA driver on the robot and the router's forwarding to it, in
one plan per robot (the driver first, then the router: data flows once the driver listens).

The router is asked to forward to ``--ip``:``--port`` (the Built-in Computer's address and
the driver's port), with the GNSS and forwarding on and proto udp.
"""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.apply import apply_gps
from panther_ops.core.gps.credentials import Credentials
from panther_ops.core.gps.plan import GpsOptions
from panther_ops.core.gps.read import read_and_plan_enable
from panther_ops.core.gps.router.plan import RouterRequest, changes, describe_puts, summary_of, with_router
from panther_ops.core.gps.router.read import NoRouter, open_router, read_state
from panther_ops.results import Outcome, RobotResult


def router_request(opts: GpsOptions) -> RouterRequest:
    return RouterRequest(enabled=True, hostname=opts.ip, port=opts.port)


def plan_enable_with_router(ctx: RobotContext, opts: GpsOptions, address: str, creds: Credentials) -> RobotPlan:
    plan = read_and_plan_enable(ctx, opts)
    try:
        api = open_router(ctx, address, creds)
    except NoRouter as exc:  # a demo robot: the driver's part planned, the router's said to be left out
        plan.warnings.append(f"router not set: {exc.message}")
        return plan
    return with_router(plan, address, read_state(api), router_request(opts), api.fingerprint, api.pinned_now)


def enable_applier(address: str, creds: Credentials, opts: GpsOptions) -> Any:
    def apply(ctx: RobotContext, plan: RobotPlan, apply_opts: ApplyOptions) -> RobotResult:
        result = apply_gps(ctx, plan, apply_opts)
        puts = plan.data.get("router_puts")
        if not puts or result.outcome not in (Outcome.CHANGED, Outcome.OK) or apply_opts.dry_run:
            return result
        api = open_router(ctx, address, creds)
        for path, body in puts.items():
            api.call("PUT", path, {"data": body})
        state = read_state(api)
        result.data["router_after"] = summary_of(state)
        left = changes(state, router_request(opts))
        if left:
            result.outcome = Outcome.FAILED
            result.message = f"{plan.summary}; the router did not keep: {describe_puts(state, left)}"
        else:
            result.outcome = Outcome.CHANGED
            result.message = plan.summary
        return result

    return apply
