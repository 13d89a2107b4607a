"""`doctor`'s GPS check, for robots whose inventory says they have GNSS (``desired.gps.enabled``,
i.e. an ANT02 on the router): `gps status` with a short window, as one finding."""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.runner import RobotContext, Task
from panther_ops.core.gps.plan import DEFAULT_PORT
from panther_ops.core.gps.status import (
    BUSY,
    FIX,
    NO_DATA,
    NO_FIX,
    NO_MESSAGE,
    NOT_FORWARDING,
    WRONG_TARGET,
    StatusOptions,
    status_task,
)
from panther_ops.core.health.doctor import Finding
from panther_ops.errors import OpsError

WINDOW_S = 1.5

_FIXES = {
    NO_FIX: ("warn", "the antenna needs open sky; a cold start takes minutes"),
    NOT_FORWARDING: ("fail", "panther-ops gps router set -r ROBOT --enable (or gps enable --router)"),
    WRONG_TARGET: ("fail", "panther-ops gps router set -r ROBOT --hostname 10.15.20.2 --port 5000"),
    NO_DATA: ("fail", "panther-ops gps status -r ROBOT --router tells why (router credentials needed)"),
    NO_MESSAGE: ("fail", "panther-ops gps status -r ROBOT --router tells whether NMEA reaches the robot"),
    BUSY: ("warn", "a listener other than compose.yaml's NMEA driver holds the port (ss -ulpn on the robot)"),
}


def wants_gps(desired: Any) -> bool:
    gps = desired.get("gps") if isinstance(desired, dict) else None
    return isinstance(gps, dict) and gps.get("enabled") is True


def gps_task(ctx: RobotContext) -> Task:
    """`gps status` of the robot as doctor reads it: its inventory's port, a short window."""
    gps = ctx.robot.desired.get("gps") or {}
    port = gps.get("port", DEFAULT_PORT)  # a port: the inventory checked desired.gps when it loaded
    return status_task(StatusOptions(port=port, window_s=WINDOW_S))  # type: ignore[no-any-return]


def gps_finding(ctx: RobotContext, read: Task | None = None) -> Finding:
    """The finding of the robot's `gps status` (``read``: how it is read, default :func:`gps_task`)."""
    try:
        result = (read or gps_task(ctx))(ctx)
    except OpsError as exc:
        return Finding("gps", "warn", f"could not check: {exc}", f"panther-ops gps status -r {ctx.robot.name}")
    d = result.data
    verdict, detail = d.get("verdict", "?"), d.get("detail", result.message)
    driver = (d.get("driver") or {}).get("mode")
    if verdict == FIX:
        state, fix = "ok", None
    else:
        state, fix = _FIXES.get(verdict, ("warn", "panther-ops gps status -r ROBOT"))
    if driver == "off":
        detail += "; no NMEA driver in compose.yaml"
        fix = fix or "panther-ops gps enable -r ROBOT"
        state = "warn" if state == "ok" else state
    return Finding("gps", state, f"{verdict}: {detail}", fix.replace("ROBOT", ctx.robot.name) if fix else None)
