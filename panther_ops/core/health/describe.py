"""`panther-ops describe ROBOT`: one robot as a whole, read over its one connection.

Each part is the reader its own command uses: `status` (stack, image, containers, the WebUI),
`gps status` (doctor's short window), `estop status`, `config history` (the newest backup and
the change it came before) and `doctor` (without the default-password check, which would open
a second connection). A part that cannot be read says why in its place; the robot is
unreachable only when its connection or its probe fails (as for `status`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import OpsError
from panther_ops.results import RobotResult

PARTS = ("status", "gps", "estop", "history", "doctor")
"""The parts of a description, in the order they are read and shown."""


def where(ctx: RobotContext) -> str:
    """How the robot is reached, as the inventory says."""
    r = ctx.robot
    if r.transport == "local":
        return f"demo robot: the directory {r.root}"
    port = f":{r.port}" if r.port else ""
    return f"{r.user}@{r.host}{port}" + (f" via {r.jump}" if r.jump else "")


def _part(read: Callable[[], RobotResult]) -> dict[str, Any]:
    """A part's result as data: its outcome, message, data and warnings, or the error that
    stopped it (``error``, with ``hint``)."""
    try:
        res = read()
    except OpsError as exc:
        return {"error": exc.message, **({"hint": exc.hint} if exc.hint else {})}
    return {"outcome": res.outcome.value, "message": res.message, "data": res.data,
            **({"warnings": res.warnings} if res.warnings else {})}


def _last_change(ctx: RobotContext) -> RobotResult:
    """The newest backup and the change it was taken before (`config history`'s reader)."""
    from panther_ops.core.fleet.history import list_history
    from panther_ops.results import Outcome

    entries = list_history(ctx)
    last = entries[-1] if entries else None
    if last is not None:
        last = {k: v for k, v in last.items() if k in ("id", "created", "command", "summary", "status")} | {
            "files": [f.get("path") for f in last.get("files", [])]}
    return RobotResult(ctx.robot.name, Outcome.OK, f"{len(entries)} backups",
                       data={"backups": len(entries), "last": last})


def describe_task(ctx: RobotContext) -> RobotResult:
    """Every part of one robot; the result carries `status`'s outcome and message (an
    unreachable robot raises, as `status` does), the parts in ``data``."""
    from panther_ops.core.health.doctor import make_doctor_task
    from panther_ops.core.health.gps_check import gps_task
    from panther_ops.core.health.status import status_task
    from panther_ops.core.remote.estop.calls import status_task as estop_task

    status = status_task(ctx)
    gps_read: list[RobotResult | OpsError] = []

    def gps(c: RobotContext) -> RobotResult:  # read once: the GPS part and doctor's GPS check share it
        if not gps_read:
            try:
                gps_read.append(gps_task(c)(c))
            except OpsError as exc:
                gps_read.append(exc)
        got = gps_read[0]
        if isinstance(got, OpsError):
            raise got
        return got

    data: dict[str, Any] = {"where": where(ctx), "status": status.data}
    data["gps"] = _part(lambda: gps(ctx))
    data["estop"] = _part(lambda: estop_task(ctx))
    data["history"] = _part(lambda: _last_change(ctx))
    data["doctor"] = _part(lambda: make_doctor_task(password_check=False, gps=gps)(ctx))
    return RobotResult(ctx.robot.name, status.outcome, status.message, data=data, warnings=status.warnings)
