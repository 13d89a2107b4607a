"""The plan of ``desired.webui`` (`apply`, `config diff`): a pure function of the snap's state
as read on the robot's User Computer (fact ``webui``, read by `desired.py`), the robot's
namespace (`defaults`) and the inventory's desired.webui.

Every key that differs is listed (current -> new), with ``ros.namespace`` defaulting to the
robot's. A robot without a User Computer to read (no ``user_computer:``, or a demo robot
without a recording) is skipped with a warning, as `desired.py` explains.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from panther_ops.core.fleet.plan import RobotPlan, Step
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds.webui_settings import SNAP, SettingError, validate
from panther_ops.core.remote.webui.defaults import KEY as NS_KEY
from panther_ops.core.remote.webui.defaults import RobotNamespace, with_robot_namespace
from panther_ops.core.remote.webui.state import WebuiState, plan_changes, plan_text
from panther_ops.errors import UsageError

ACTION = "webui"
FACT = "webui"
"""Fact: the snap's state on the robot's User Computer (:class:`WebuiRead`)."""


@dataclass(frozen=True)
class SetWebui(Step):
    """`apply`'s ``desired.webui`` after the robot's files: ``wanted`` set on the User Computer
    (`apply.apply_settings`; the namespace default already decided). ``files_summary``: what
    the files' part of the plan says (empty: the plan has no file edits)."""

    wanted: Mapping[str, str]
    files_summary: str


@dataclass(frozen=True)
class SetKeys(Step):
    """`webui set`: ``wanted`` set on the User Computer (`apply.apply_settings`: the DDS
    profile uploaded first when ``dds`` holds one, ``ros.namespace`` defaulting to the robot's,
    a restart when it was running, read back)."""

    wanted: Mapping[str, str]
    dds: tuple[str, bytes] | None


@dataclass(frozen=True)
class WebuiRead:
    """The snap's state and the User Computer's address; or (``state`` None) why none was read."""

    state: WebuiState | None
    host: str = ""
    warning: str = ""


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


def plan_desired_webui(reads: Reads, desired: dict[str, Any], robot_ns: RobotNamespace) -> WebuiPlan:
    """The WebUI's plan for ``desired`` (the inventory's desired.webui, already validated when
    it loaded). ``robot_ns``: the robot's namespace as the plan leaves it. Raises UsageError
    for a value this User Computer lacks (a custom transport without its DDS profile)."""
    wanted = validate(desired)
    read: WebuiRead = reads.fact(FACT)
    if read.state is None:
        return WebuiPlan([], wanted, warnings=[read.warning])
    state, host = read.state, read.host
    if not state.installed:
        return WebuiPlan([], wanted, host=host, warnings=[
            f"desired.webui not converged: {SNAP} is not installed on {host} (panther-ops webui install)"])
    full, note = with_robot_namespace(wanted, state.value(NS_KEY), robot_ns)
    try:
        validate(full, state.profiles)
    except SettingError as exc:
        raise UsageError(f"desired.webui: {exc}", hint=f"add the DDS profile on {host} (panther-ops webui set "
                                                        "--dds-file FILE) or change the inventory") from None
    return WebuiPlan(plan_changes(state, full), full, state.running, host, note=note)


def plan_set(robot: str, state: WebuiState, wanted: dict[str, str], ns: RobotNamespace,
             dds: tuple[str, bytes] | None) -> RobotPlan:
    """`webui set` on one robot: every key that differs (current -> new), checked with the snap's
    rules and the robot's custom DDS profiles (a refusal is the operator's: UsageError, nothing
    is sent anywhere). ``dds``: a profile to upload, which selects ``ros.transport`` itself (the
    profile is not on the computer yet: its name is not checked against it)."""
    from panther_ops.errors import RemoteStateError

    if not state.installed:
        raise RemoteStateError(f"{SNAP} is not installed",
                               hint=f"panther-ops webui install -r {robot} --ask-sudo-password")
    checked = {k: v for k, v in wanted.items() if dds is None or k != "ros.transport"}
    full, note = with_robot_namespace(checked, state.value(NS_KEY), ns)
    try:
        validate(full, state.profiles)
    except SettingError as exc:
        raise UsageError(f"refused before sending: {exc}") from None
    changes = plan_changes(state, full)
    data: dict[str, Any] = {"plan": [{"key": k, "current": c, "new": n} for k, c, n in changes],
                            "running": state.running, "ready": bool(changes) or dds is not None, "namespace": note}
    if not changes and dds is None:
        return RobotPlan(robot, "", noop="nothing to change", data=data)
    text = plan_text(changes, note) if changes else ""
    if dds is not None:
        text = f"upload {dds[0]} and select it" + (f"; {text}" if text else "")
    return RobotPlan(robot, f"change: {text}", data=data, steps=[SetKeys(dict(wanted), dds)])
