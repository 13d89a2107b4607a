"""husarion-webui on the robot's User Computer, read: the snap's state (or a demo robot's
recording), whether its UI answers, the robot's namespace (the default of ``ros.namespace``),
and the read-only tasks (`webui status|url`, the plan of `webui set`, the status column, the
fact ``desired.webui`` plans from). Planners: `plan.py` and `state.py` (pure); changes:
`apply.py`.

Everything runs on the User Computer through a fabric session over the robot's connection
(:mod:`panther_ops.core.remote.user_computer.access`): one read of the snap's state (``snap list``,
``snap get -d``, ``snap services``, the DDS profiles ``dds-config-*.xml``). Whether
``http://<host>:<port>/ui`` answers is asked from the robot (curl there), i.e. through the
robot's connection.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds.webui_settings import COMMON_DIR, SNAP
from panther_ops.core.remote.user_computer.access import open_session
from panther_ops.core.remote.webui.defaults import (
    RobotNamespace,
    robot_namespace_of,
    unknown_namespace,
)
from panther_ops.core.remote.webui.plan import WebuiRead, plan_set
from panther_ops.core.remote.webui.state import WebuiState, parse_state
from panther_ops.errors import OpsError, RemoteStateError
from panther_ops.results import Outcome, RobotResult
from panther_ops.secret import Secret
from panther_ops.transport.base import Command
from panther_ops.transport.user_computer import UserComputerSession

READ = r"""for part in list get services profiles; do
    echo "@@$part"
    case $part in
        list) snap list "$1" 2>&1 ;;
        get) snap get -d "$1" 2>&1 ;;
        services) snap services "$1" 2>&1 ;;
        profiles) ls -1 "$2" 2>/dev/null ;;
    esac
    echo "@@exit $?"
done
"""
UI_CHECK = 'curl -s -o /dev/null -m "$2" -w "%{http_code}" "$1"; echo " $?"'


def read_state(session: UserComputerSession) -> WebuiState:
    res = session.run(Command.sh(READ, SNAP, COMMON_DIR))
    return parse_state(res.stdout)


def ui_url(host: str, port: str) -> str:
    return f"http://{host}:{port}/ui"


def ui_answers(ctx: RobotContext, url: str, timeout: float = 3.0) -> int | None:
    """The HTTP status of ``url`` fetched on the robot (None: no answer)."""
    res = ctx.transport.run(Command.sh(UI_CHECK, url, f"{timeout:g}"))
    code, _, _ = res.stdout.strip().partition(" ")
    return int(code) if code.isdigit() and code != "000" else None


@contextmanager
def webui_session(ctx: RobotContext, password: Secret | None) -> Iterator[UserComputerSession]:
    """A connected session on the robot's User Computer (raises UnreachableError), closed when
    the block ends."""
    session = open_session(ctx, password)
    try:
        yield session
    finally:
        session.close()


Task = Callable[[RobotContext], RobotResult]


def robot_namespace(ctx: RobotContext) -> RobotNamespace:
    """The driver's namespace as the WebUI's default (`defaults`), read from the robot."""
    from panther_ops.core.fleet.reading import read_and_plan
    from panther_ops.core.robot.read import read_config

    try:
        cfg = read_config(ctx)
    except OpsError as exc:
        return unknown_namespace(exc)
    return read_and_plan(ctx, lambda reads: robot_namespace_of(reads, cfg))


def status_task(password: Secret | None) -> Task:
    def task(ctx: RobotContext) -> RobotResult:
        if ctx.robot.transport == "local":
            return _demo_status(ctx)
        with webui_session(ctx, password) as session:
            state = read_state(session)
        data: dict[str, Any] = {"user_computer": session.address.host, **state.to_json()}
        if not state.installed:
            return RobotResult(ctx.robot.name, Outcome.OK, f"{SNAP} not installed", data=data)
        url = ui_url(session.address.host, state.value("webui.port"))
        code = ui_answers(ctx, url)
        data.update(url=url, ui_http=code)
        answered = f"{url} answers {code}" if code else f"{url} does not answer"
        return RobotResult(ctx.robot.name, Outcome.OK, f"{SNAP} {state.channel} rev {state.revision}, "
                           f"{'running' if state.running else 'stopped'}; {answered}", data=data)
    return task


def _recording(ctx: RobotContext) -> dict[str, Any] | None:
    """A demo robot's recorded User Computer (in the robot's directory); None: none recorded."""
    from panther_ops.core.remote.estop.calls import DEMO_RECORDING

    try:
        raw = json.loads(ctx.transport.read_file(DEMO_RECORDING).decode())
    except FileNotFoundError:
        raise RemoteStateError(f"no recorded answers ({DEMO_RECORDING})",
                               hint="recreate the demo fleet: panther-ops demo init --force") from None
    rec = raw.get("webui")
    return rec if isinstance(rec, dict) else None


def read_webui(ctx: RobotContext, password: Secret | None) -> tuple[WebuiState, str]:
    """The snap's state and the User Computer's address: read there, or a demo robot's recording."""
    if ctx.robot.transport == "local":
        rec = _recording(ctx)
        if rec is None:
            raise RemoteStateError("no User Computer recorded (demo robot)")
        return parse_state(str(rec.get("state", ""))), str(rec.get("host", "10.15.20.3"))
    with webui_session(ctx, password) as session:
        return read_state(session), session.address.host


NO_DEMO_USER_COMPUTER = "demo robot: no User Computer recorded (the WebUI runs on one)"


def no_user_computer(ctx: RobotContext) -> RobotResult | None:
    """A demo robot without a recorded User Computer: skipped with why, by every `webui`
    command alike (as `apply` skips its WebUI); None for any other robot."""
    return _no_recording(ctx) if ctx.robot.transport == "local" and _recording(ctx) is None else None


def _no_recording(ctx: RobotContext) -> RobotResult:
    return RobotResult(ctx.robot.name, Outcome.SKIPPED, NO_DEMO_USER_COMPUTER,
                       data={"recorded": True, "installed": False})


def demo_skip(ctx: RobotContext, what: str) -> RobotResult:
    """A change a demo robot cannot make: reported, nothing pretended."""
    return RobotResult(ctx.robot.name, Outcome.SKIPPED, f"demo robot: no User Computer to {what}")


def demo_change(ctx: RobotContext, what: str, needless: Callable[[WebuiState], RobotResult | None]) -> RobotResult:
    """A change asked of a demo robot: skipped without a recorded User Computer; else
    ``needless``'s result where the recorded state needs no change, or skipped (`demo_skip`)."""
    if (skipped := no_user_computer(ctx)) is not None:
        return skipped
    state, _ = read_webui(ctx, None)
    return needless(state) or demo_skip(ctx, what)


def _demo_status(ctx: RobotContext) -> RobotResult:
    """A demo robot: its User Computer's recorded answers."""
    rec = _recording(ctx)
    if rec is None:
        return _no_recording(ctx)
    state = parse_state(str(rec.get("state", "")))
    code = rec.get("ui_http")
    url = ui_url(str(rec.get("host", "10.15.20.3")), state.value("webui.port"))
    data = {"user_computer": rec.get("host"), **state.to_json(), "url": url, "ui_http": code, "recorded": True}
    answered = f"{url} answers {code}" if code else f"{url} does not answer"
    return RobotResult(ctx.robot.name, Outcome.OK, f"{SNAP} {state.channel} rev {state.revision}, "
                       f"{'running' if state.running else 'stopped'}; {answered} (recorded: demo robot)", data=data)


def read_and_plan_set(ctx: RobotContext, wanted: dict[str, str], password: Secret | None,
                      dds: tuple[str, bytes] | None) -> RobotPlan:
    """`webui set`'s read (the snap's state, the robot's namespace), then its plan (`plan.py`);
    a demo robot without a recorded User Computer is skipped."""
    if (skipped := no_user_computer(ctx)) is not None:
        return RobotPlan(ctx.robot.name, "", skipped=skipped.message)
    state, _ = read_webui(ctx, password)
    ns = robot_namespace(ctx) if state.installed else RobotNamespace(None, "not read: no WebUI installed")
    return plan_set(ctx.robot.name, state, wanted, ns, dds)


def url_task(password: Secret | None) -> Task:
    def task(ctx: RobotContext) -> RobotResult:
        if (skipped := no_user_computer(ctx)) is not None:
            return skipped
        state, host = read_webui(ctx, password)
        port = state.value("webui.port")
        lan = ui_url(host, port)
        husarnet = ui_url("<husarnet-hostname>", port)
        return RobotResult(ctx.robot.name, Outcome.OK, f"{lan} (LAN); {husarnet} (Husarnet)",
                           data={"lan": lan, "husarnet": husarnet, "port": port})
    return task


def status_column(ctx: RobotContext) -> dict[str, Any] | None:
    """The WebUI as `panther-ops status` shows it: for a robot with ``user_computer:`` in the
    inventory (or a demo robot's recording), read without sudo; None when there is none."""
    if ctx.robot.transport == "local":
        try:
            res = _demo_status(ctx)
        except OpsError:  # a demo fleet from before the recordings
            return None
        return None if not res.data.get("installed") else _column(res.data, str(res.data.get("user_computer")))
    if ctx.robot.user_computer is None:
        return None
    try:
        with webui_session(ctx, None) as session:
            state = read_state(session)
    except OpsError as exc:
        return {"error": exc.message}
    return _column({"installed": state.installed, "running": state.running,
                    "settings": state.to_json()["settings"]}, session.address.host)


def _column(data: dict[str, Any], host: str) -> dict[str, Any]:
    """Installed, running, its port and the URL of its UI on the robot's LAN."""
    port = (data.get("settings") or {}).get("webui.port")
    return {"installed": bool(data.get("installed")), "running": bool(data.get("running")), "port": port,
            "url": ui_url(host, str(port)) if port else None}


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
