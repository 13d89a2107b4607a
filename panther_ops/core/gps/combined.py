"""`gps enable --router`: the NMEA driver on the robot and the router's forwarding to it, in
one plan per robot (the driver first, then the router: data flows once the driver listens).

The router is asked to forward to ``--ip``:``--port`` (the Built-in Computer's address and
the driver's port), with the GNSS and forwarding on and proto udp.
"""

from __future__ import annotations

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.credentials import Credentials
from panther_ops.core.gps.plan import GpsOptions
from panther_ops.core.gps.read import read_and_plan_enable
from panther_ops.core.gps.router.plan import RouterRequest, with_router
from panther_ops.core.gps.router.read import NoRouter, open_router, read_state


def router_request(opts: GpsOptions) -> RouterRequest:
    return RouterRequest(enabled=True, hostname=opts.ip, port=opts.port)


def plan_enable_with_router(ctx: RobotContext, opts: GpsOptions, address: str, creds: Credentials) -> RobotPlan:
    plan = read_and_plan_enable(ctx, opts)
    try:
        api = open_router(ctx, address, creds)
    except NoRouter as exc:  # a demo robot: the driver's part planned, the router's said to be left out
        plan.warnings.append(f"router not set: {exc.message}")
        return plan
    return with_router(plan, address, read_state(api), router_request(opts), api.fingerprint, api.pinned_now, creds)
