"""``desired.webui`` of the inventory, for `apply` and `config diff`.

Reading here: the snap's state on the robot's User Computer (no sudo: ``snap get``), or a
demo robot's recording; the plan (`plan.py`, pure) lists every key that differs
(current -> new), with ``ros.namespace`` defaulting to the robot's (`defaults`). The change
is carried out by `apply_desired_webui` with the same `remote.apply_settings` as `webui set` (sudo snap set,
restart when running, read back). A robot without ``user_computer:`` in the inventory is
skipped with a warning: `apply` converges a fleet, and a Panther may have no User Computer
(the `webui` commands, asked for one robot, try the manual's 10.15.20.3). A demo robot has
none to change: its drift is shown, and applying it is reported skipped.
"""

from __future__ import annotations

from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.remote.webui.defaults import RobotNamespace
from panther_ops.core.remote.webui.plan import WebuiRead
from panther_ops.core.remote.webui.remote import apply_settings, open_webui_session, read_webui
from panther_ops.errors import RemoteStateError
from panther_ops.results import Outcome
from panther_ops.secret import Secret


def read_desired_webui(ctx: RobotContext, _key: str = "") -> WebuiRead:
    """The fact `plan.py` plans from: the snap's state on the User Computer (no sudo),
    or a demo robot's recording; or why there is none to converge."""
    if ctx.robot.transport != "local" and ctx.robot.user_computer is None:
        return WebuiRead(None, warning=f"desired.webui not converged: no user_computer: for {ctx.robot.name} "
                                       "in the inventory (add `user_computer: {}` for the manual's "
                                       "husarion@10.15.20.3, or host/user/key)")
    try:
        state, host = read_webui(ctx, None)
    except RemoteStateError as exc:
        if ctx.robot.transport == "local":
            return WebuiRead(None, warning=f"desired.webui not converged: demo robot: {exc.message}")
        raise
    return WebuiRead(state, host)


def apply_desired_webui(ctx: RobotContext, wanted: dict[str, str], password: Secret | None
                        ) -> tuple[Outcome, str, dict[str, Any]]:
    """Carry out a planned WebUI change (``wanted``: the plan's, the namespace default decided
    already): outcome, message and what was read back."""
    if ctx.robot.transport == "local":
        return Outcome.SKIPPED, "WebUI not set: demo robot, no User Computer to change", {}
    session = open_webui_session(ctx, password)
    try:
        done = apply_settings(session, wanted, RobotNamespace(None, "decided by the plan"))
    finally:
        session.close()
    data = {**done.after.to_json(), "restarted": done.restarted}
    if done.wrong:
        return Outcome.FAILED, f"WebUI read back: {', '.join(done.wrong)} not as set", data
    if not done.changes:
        return Outcome.OK, "WebUI already as desired", data
    text = ", ".join(f"{k}={v}" for k, _, v in done.changes)
    return Outcome.CHANGED, f"set WebUI {text}" + ("; restarted it" if done.restarted else ""), data
