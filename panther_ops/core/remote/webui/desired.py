"""``desired.webui`` of the inventory, for `apply` and `config diff`.

Planning reads the snap's state on the robot's User Computer (no sudo: ``snap get``), or a
demo robot's recording, and lists every key that differs (current -> new), with
``ros.namespace`` defaulting to the robot's (`defaults`). The change is carried out by
`apply_desired_webui` with the same `remote.apply_settings` as `webui set` (sudo snap set,
restart when running, read back). A robot without ``user_computer:`` in the inventory is
skipped with a warning: `apply` converges a fleet, and a Panther may have no User Computer
(the `webui` commands, asked for one robot, try the manual's 10.15.20.3). A demo robot has
none to change: its drift is shown, and applying it is reported skipped.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds.webui_settings import SNAP, SettingError, validate
from panther_ops.core.remote.webui.defaults import KEY as NS_KEY
from panther_ops.core.remote.webui.defaults import RobotNamespace, robot_namespace, with_robot_namespace
from panther_ops.core.remote.webui.remote import (
    apply_settings,
    open_webui_session,
    plan_changes,
    plan_text,
    read_webui,
)
from panther_ops.errors import RemoteStateError, UsageError
from panther_ops.results import Outcome
from panther_ops.transport.base import Secret

ACTION = "webui"


@dataclass
class WebuiPlan:
    """What converging ``desired.webui`` changes on one robot (``changes`` empty: nothing)."""

    changes: list[tuple[str, str, str]]
    wanted: dict[str, str]
    running: bool = False
    host: str = ""
    warnings: list[str] | None = None
    note: str = ""

    @property
    def summary(self) -> str:
        return f"set WebUI {plan_text(self.changes, self.note)}" + (" and restart it" if self.running else "")

    def to_json(self) -> dict[str, Any]:
        return {"user_computer": self.host, "running": self.running, "namespace": self.note,
                "plan": [{"key": k, "current": c, "new": n} for k, c, n in self.changes]}


def plan_desired_webui(ctx: RobotContext, desired: dict[str, Any], robot_ns: RobotNamespace | None = None
                       ) -> WebuiPlan:
    """The WebUI's plan for ``desired`` (the inventory's desired.webui, already validated when
    it loaded). ``robot_ns``: the robot's namespace as the plan leaves it (a desired namespace
    change of the driver), else read. Raises UsageError for a value this User Computer lacks
    (a custom transport without its DDS profile)."""
    wanted = validate(desired)
    if ctx.robot.transport != "local" and ctx.robot.user_computer is None:
        return WebuiPlan([], wanted, warnings=[f"desired.webui not converged: no user_computer: for {ctx.robot.name} "
                                               "in the inventory (add `user_computer: {}` for the manual's "
                                               "husarion@10.15.20.3, or host/user/key)"])
    try:
        state, host = read_webui(ctx, None)
    except RemoteStateError as exc:
        if ctx.robot.transport == "local":
            return WebuiPlan([], wanted, warnings=[f"desired.webui not converged: demo robot: {exc.message}"])
        raise
    if not state.installed:
        return WebuiPlan([], wanted, host=host, warnings=[
            f"desired.webui not converged: {SNAP} is not installed on {host} (panther-ops webui install)"])
    full, note = with_robot_namespace(wanted, state.value(NS_KEY), robot_ns or robot_namespace(ctx))
    try:
        validate(full, state.profiles)
    except SettingError as exc:
        raise UsageError(f"desired.webui: {exc}", hint=f"add the DDS profile on {host} (panther-ops webui set "
                                                        "--dds-file FILE) or change the inventory") from None
    return WebuiPlan(plan_changes(state, full), full, state.running, host, note=note)


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
