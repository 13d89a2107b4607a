"""husarion-webui on the robot's User Computer, changed: `apply_settings` (the one path that
changes keys: the DDS profile uploaded, ``sudo snap set`` what differs, a restart when it was
running, read back) for `webui set` and for ``desired.webui`` of `apply`, and `webui
start|stop`, as the manual does (``sudo snap ...`` / ``sudo husarion-webui.start|stop``).
Reads: `read.py`; planners: `plan.py` and `state.py` (pure).

``desired.webui``: a robot without ``user_computer:`` in the inventory is skipped with a
warning (`read.read_desired_webui`): `apply` converges a fleet, and a Panther may have no
User Computer (the `webui` commands, asked for one robot, try the manual's 10.15.20.3). A demo
robot has none to change: its drift is shown, and applying it is reported skipped.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.kinds.webui_settings import SNAP, profile_path
from panther_ops.core.remote.webui.defaults import KEY as NS_KEY
from panther_ops.core.remote.webui.defaults import RobotNamespace, with_robot_namespace
from panther_ops.core.remote.webui.plan import SetKeys, SetWebui
from panther_ops.core.remote.webui.read import (
    Task,
    demo_change,
    demo_skip,
    read_state,
    robot_namespace,
    webui_session,
)
from panther_ops.core.remote.webui.state import WebuiState, plan_changes
from panther_ops.errors import OpsError, RemoteStateError
from panther_ops.results import Outcome, RobotResult
from panther_ops.secret import Secret
from panther_ops.transport.base import Command
from panther_ops.transport.user_computer import UserComputerSession


def sudo(session: UserComputerSession, *argv: str) -> None:
    res = session.sudo(Command.of(*argv), timeout=120)
    if not res.ok:
        why = (res.stderr.strip() or res.stdout.strip())[-400:]
        if "password is required" in why:
            raise RemoteStateError(f"sudo on {session.address.name} needs a password",
                                   hint="pass --ask-sudo-password or set PANTHER_OPS_SUDO_PASSWORD")
        raise RemoteStateError(f"`sudo {' '.join(argv)}` failed on {session.address.name}: {why}")


@dataclass
class Applied:
    """What `apply_settings` did: the state before and after, the changes, a restart."""

    before: WebuiState
    after: WebuiState
    wanted: dict[str, str]
    changes: list[tuple[str, str, str]]
    restarted: bool

    @property
    def wrong(self) -> list[str]:
        """Keys that did not read back as set."""
        return [k for k in self.wanted if self.after.value(k) != self.wanted[k]]


def apply_settings(session: UserComputerSession, wanted: dict[str, str], robot: RobotNamespace,
                   dds: tuple[str, bytes] | None = None) -> Applied:
    """Upload the DDS profile, `sudo snap set` what differs (``ros.namespace`` defaulting to the
    robot's), restart the WebUI when it was running, read back: one path for `webui set` and
    `apply`."""
    before = read_state(session)
    wanted, _ = with_robot_namespace(wanted, before.value(NS_KEY), robot)
    if dds is not None:
        name, data = dds
        _upload(session, profile_path(name), data)  # where the configure hook resolves <name> to
    plan = plan_changes(before, wanted)
    if plan:
        sudo(session, "snap", "set", SNAP, *(f"{k}={v}" for k, _, v in plan))
    restarted = False
    if plan and before.running:
        sudo(session, f"{SNAP}.stop")
        sudo(session, f"{SNAP}.start")
        restarted = True
    return Applied(before, read_state(session), wanted, plan, restarted)


@executes(SetKeys)
def set_keys(ctx: RobotContext, plan: RobotPlan, step: SetKeys, opts: ApplyOptions, write: Write) -> RobotResult:
    """`webui set`: `apply_settings` on the robot's User Computer (a demo robot: skipped)."""
    if ctx.robot.transport == "local":
        return demo_skip(ctx, "set")
    robot = robot_namespace(ctx)
    with webui_session(ctx, opts.sudo_password) as session:
        done = apply_settings(session, dict(step.wanted), robot, step.dds)
    data_out: dict[str, Any] = {**done.after.to_json(), "restarted": done.restarted}
    if done.wrong:
        return RobotResult(ctx.robot.name, Outcome.FAILED, f"read back: {', '.join(done.wrong)} not as set",
                           data=data_out)
    if not done.changes and step.dds is None:
        return RobotResult(ctx.robot.name, Outcome.OK, "nothing to change", data=data_out)
    text = ", ".join(f"{k}={v}" for k, _, v in done.changes) or "DDS profile uploaded"
    return RobotResult(ctx.robot.name, Outcome.CHANGED, f"set {text}" + ("; restarted" if done.restarted else ""),
                       data=data_out)


def _upload(session: UserComputerSession, target: str, data: bytes) -> None:
    """Write ``data`` to ``target`` as root (a here-document of the validated XML)."""
    import base64

    encoded = base64.b64encode(data).decode()
    sudo(session, "sh", "-c", 'printf %s "$1" | base64 -d > "$2.tmp" && chmod 644 "$2.tmp" && mv "$2.tmp" "$2"',
          "sh", encoded, target)


def start_stop_task(start: bool, password: Secret | None) -> Task:
    def task(ctx: RobotContext) -> RobotResult:
        if ctx.robot.transport == "local":
            return demo_change(ctx, "start" if start else "stop", lambda state: _start_stop_needless(ctx, state, start))
        with webui_session(ctx, password) as session:
            state = read_state(session)
            done = _start_stop_needless(ctx, state, start)
            if done is not None:
                return done
            sudo(session, f"{SNAP}.{'start' if start else 'stop'}")
            after = read_state(session)
        if after.running != start:
            return RobotResult(ctx.robot.name, Outcome.FAILED, f"still {'stopped' if start else 'running'}",
                               data=after.to_json())
        return RobotResult(ctx.robot.name, Outcome.CHANGED, "started" if start else "stopped", data=after.to_json())
    return task


def _start_stop_needless(ctx: RobotContext, state: WebuiState, start: bool) -> RobotResult | None:
    """The result when there is nothing to start or stop (not installed, or already so)."""
    if not state.installed:
        return RobotResult(ctx.robot.name, Outcome.FAILED, f"{SNAP} is not installed",
                           data={"hint": f"panther-ops webui install -r {ctx.robot.name} --ask-sudo-password"})
    if state.running == start:
        return RobotResult(ctx.robot.name, Outcome.OK, f"already {'running' if start else 'stopped'}",
                           data=state.to_json())
    return None


def apply_desired_webui(ctx: RobotContext, wanted: dict[str, str], password: Secret | None
                        ) -> tuple[Outcome, str, dict[str, Any]]:
    """Carry out a planned WebUI change (``wanted``: the plan's, the namespace default decided
    already): outcome, message and what was read back."""
    if ctx.robot.transport == "local":
        return Outcome.SKIPPED, "WebUI not set: demo robot, no User Computer to change", {}
    with webui_session(ctx, password) as session:
        done = apply_settings(session, wanted, RobotNamespace(None, "decided by the plan"))
    data = {**done.after.to_json(), "restarted": done.restarted}
    if done.wrong:
        return Outcome.FAILED, f"WebUI read back: {', '.join(done.wrong)} not as set", data
    if not done.changes:
        return Outcome.OK, "WebUI already as desired", data
    text = ", ".join(f"{k}={v}" for k, _, v in done.changes)
    return Outcome.CHANGED, f"set WebUI {text}" + ("; restarted it" if done.restarted else ""), data


@executes(SetWebui)
def set_webui(ctx: RobotContext, plan: RobotPlan, step: SetWebui, opts: ApplyOptions, write: Write) -> RobotResult:
    """`apply`'s plans: the files through the pipeline, then the WebUI's settings (files that
    failed or rolled back leave the WebUI untouched; ``sudo`` with ``opts.sudo_password``)."""
    result = write(opts)
    if opts.dry_run or (plan.edits and result.outcome is not Outcome.CHANGED):
        return result
    files = f"{step.files_summary}; " if plan.edits else ""
    try:
        outcome, message, after = apply_desired_webui(ctx, dict(step.wanted), opts.sudo_password)
    except OpsError as exc:
        outcome, message, after = Outcome.FAILED, f"WebUI: {exc.message}", {}
        if exc.hint:
            result.warnings.append(exc.hint)
    result.data["webui_after"] = after
    if outcome is Outcome.SKIPPED and plan.edits:
        result.warnings.append(message)
        result.message = step.files_summary or result.message
    else:
        result.outcome = outcome if outcome is not Outcome.OK or not plan.edits else Outcome.CHANGED
        result.message = files + message
    return result
