"""`webui install`: the clocks checked first (the manual asks for time synchronization before
installing anything on the User Computer), then `sudo snap install husarion-webui`, and
``ros.namespace`` set to the robot's where the snap has none (`defaults`); idempotent."""

from __future__ import annotations

import time
from collections.abc import Callable

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds.webui_settings import SNAP
from panther_ops.core.remote.webui.apply import apply_settings, sudo
from panther_ops.core.remote.webui.read import (
    Task,
    demo_change,
    read_state,
    robot_namespace,
    webui_session,
)
from panther_ops.core.remote.webui.state import WebuiState
from panther_ops.errors import RemoteStateError
from panther_ops.results import Outcome, RobotResult
from panther_ops.secret import Secret
from panther_ops.transport.base import Command
from panther_ops.transport.user_computer import UserComputerSession

DEFAULT_CHANNEL = "humble"
CLOCK_LIMIT_S = 1.0
CLOCK_FIX = ("synchronize the clocks first (the manual: time synchronization before installing anything on the "
             "User Computer): e.g. on the User Computer `sudo chronyc makestep` with the robot as its time "
             "server, or `sudo timedatectl set-ntp true`")


def install_task(channel: str, password: Secret | None) -> Task:
    """Clocks checked, `sudo snap install`, and ``ros.namespace`` set to the robot's where the
    snap has none (see `defaults`); idempotent."""
    def task(ctx: RobotContext) -> RobotResult:
        if ctx.robot.transport == "local":
            return _demo_install(ctx, channel)
        robot = robot_namespace(ctx)
        with webui_session(ctx, password) as session:
            offsets = clock_offsets(ctx, session)
            worst = max(offsets.values(), key=abs)
            if abs(worst) > CLOCK_LIMIT_S:
                shown = ", ".join(f"{k} {v:+.1f} s" for k, v in offsets.items())
                return RobotResult(ctx.robot.name, Outcome.FAILED, f"refused: clocks differ ({shown}; limit "
                                   f"{CLOCK_LIMIT_S:g} s)", data={"clock_offsets": offsets, "hint": CLOCK_FIX})
            state = read_state(session)
            want = channel if "/" in channel else f"{channel}/stable"
            installed_now = not (state.installed and state.channel == want)
            if installed_now:
                sudo(session, "snap", "install", SNAP, f"--channel={channel}")
            after = read_state(session)
            changes = []
            if after.installed:
                applied = apply_settings(session, {}, robot)
                after, changes = applied.after, applied.changes
        data = {"clock_offsets": offsets, **after.to_json()}
        if not after.installed:
            return RobotResult(ctx.robot.name, Outcome.FAILED, f"{SNAP} not installed after snap install", data=data)
        done = [f"installed {SNAP} {after.channel} rev {after.revision}"] if installed_now else []
        done += [f"set {k}={v} ({robot.note})" for k, _, v in changes]
        if not done:
            return RobotResult(ctx.robot.name, Outcome.OK, f"{SNAP} {want} already installed", data=data)
        return RobotResult(ctx.robot.name, Outcome.CHANGED, "; ".join(done), data=data)
    return task


def _demo_install(ctx: RobotContext, channel: str) -> RobotResult:
    want = channel if "/" in channel else f"{channel}/stable"

    def needless(state: WebuiState) -> RobotResult | None:
        if state.installed and state.channel == want:
            return RobotResult(ctx.robot.name, Outcome.OK, f"{SNAP} {want} already installed (recorded: demo robot)",
                               data=state.to_json())
        return None

    return demo_change(ctx, "install on", needless)


def clock_offsets(ctx: RobotContext, session: UserComputerSession) -> dict[str, float]:
    """Seconds each clock is ahead: the User Computer and the robot against this machine,
    and the User Computer against the robot (round trips halved)."""
    def remote(run: Callable[[], str]) -> float:
        before = time.time()
        text = run()
        after = time.time()
        try:
            return float(text.strip().splitlines()[-1]) - (before + after) / 2
        except (ValueError, IndexError):
            raise RemoteStateError(f"cannot read the clock: {text.strip()[-200:]!r}") from None

    uc = remote(lambda: session.run(Command.of("date", "+%s.%N")).stdout)
    robot = remote(lambda: ctx.transport.run(Command.of("date", "+%s.%N")).stdout)
    return {"user computer vs this machine": round(uc, 3), "robot vs this machine": round(robot, 3),
            "user computer vs robot": round(uc - robot, 3)}
