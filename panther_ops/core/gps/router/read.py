"""`gps router show|set`, read: the RUTX11's NMEA forwarding, through its REST API.

The router sits on the robot's LAN (10.15.20.1); panther-ops reaches it through the robot's
SSH connection (a direct-tcpip channel), logs in (``POST /api/login``) and reads or writes
three resources, every value a string (the API takes only ``"0"``/``"1"`` for switches):

- ``/api/gps/global``: ``enabled`` (the GNSS receiver);
- ``/api/gps/nmea/config/nmea_forwarding``: ``enabled``, ``hostname``, ``port``, ``proto``;
- ``/api/gps/nmea/rules/config``: per sentence ``id``, ``forwarding_enabled``,
  ``forwarding_interval``.

Reads are ``GET`` on the same paths. Credentials: `core.gps.credentials`. This module reads
(and runs `gps router show`); the planner is `plan.py` (pure), the PUTs are `apply.py`'s.
"""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.credentials import Credentials
from panther_ops.core.gps.router.plan import FORWARDING, GLOBAL, RULES, RouterRequest, router_plan, summary_of
from panther_ops.errors import UsageError
from panther_ops.results import Outcome, RobotResult


def open_router(ctx: RobotContext, address: str, creds: Credentials) -> Any:
    from panther_ops.transport import pins
    from panther_ops.transport.rutx import RouterClient
    from panther_ops.transport.tunnel import open_tcp

    client = getattr(ctx.transport, "client", None)
    if client is None:
        raise NoRouter("demo robot: reached without SSH, no router behind it")
    key = f"{ctx.robot.name}/{address}"
    api = RouterClient(lambda: open_tcp(client, ctx.robot.name, address, 443), ctx.robot.name, address,
                       pinned=pins.pinned(key), pin=lambda fp: pins.pin(key, fp))
    username, password = creds.for_robot(ctx.robot.name)
    api.login(username, password)
    return api


class NoRouter(UsageError):
    pass


def read_state(api: Any) -> dict[str, Any]:
    rules = api.call("GET", RULES) or []
    return {"global": dict(api.call("GET", GLOBAL) or {}), "forwarding": dict(api.call("GET", FORWARDING) or {}),
            "rules": {str(r.get("id")): dict(r) for r in rules if isinstance(r, dict)}}


def show_task(address: str, creds: Credentials) -> Any:
    def task(ctx: RobotContext) -> RobotResult:
        try:
            api = open_router(ctx, address, creds)
        except NoRouter as exc:
            return RobotResult(ctx.robot.name, Outcome.SKIPPED, exc.message)
        state = summary_of(read_state(api))
        data = {"router": address, **state, "certificate": api.fingerprint}
        warnings = [f"router certificate pinned on first use: {api.fingerprint}"] if api.pinned_now else []
        where = f"{state['hostname']}:{state['port']}/{state['proto']}"
        msg = f"forwarding {'on' if state['forwarding'] else 'off'} to {where}; {len(state['sentences'])} sentences"
        return RobotResult(ctx.robot.name, Outcome.OK, msg, warnings=warnings, data=data)

    return task


def read_and_plan_router(ctx: RobotContext, address: str, creds: Credentials, req: RouterRequest) -> RobotPlan:
    """Read the router's state over the robot's connection; plan (`plan.py`). A demo
    robot has no router: skipped, as `gps router show` skips it."""
    try:
        api = open_router(ctx, address, creds)
    except NoRouter as exc:
        return RobotPlan(ctx.robot.name, "", skipped=exc.message)
    return router_plan(ctx.robot.name, address, read_state(api), req, api.fingerprint, api.pinned_now, creds)
