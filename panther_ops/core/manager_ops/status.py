"""`panther-ops manager status|logs`: the deployed manager service on each robot.

Status reads compose.yaml (is the service there, is ``disable_manager`` set on the driver),
``~/panther-ops/manager/deployed.json`` (version, build, mode) and the container through the
docker SDK on the robot's own connection (state, restart count, uptime on the engine's
clock, the archive its command runs).
"""

from __future__ import annotations

import re
from datetime import datetime
from typing import Any

from panther_ops.core.containers.logs import LogOptions, read_logs
from panther_ops.core.containers.times import engine_now, human_duration, parse_timestamp
from panther_ops.core.fleet.reading import read_file
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.manager_ops.apply import manager_containers
from panther_ops.core.manager_ops.layout import parse_state, state_path
from panther_ops.core.manager_ops.settings import DISABLE_ARG, SERVICE
from panther_ops.core.robot.read import read_config
from panther_ops.errors import RemoteStateError
from panther_ops.results import Outcome, RobotResult

_VERSION_IN_CMD = re.compile(r"/opt/panther-ops/manager/([^/]+)/panther_ops_manager\.pyz$")








def running_version(cmd: list[str]) -> str | None:
    """The deployed version a container runs, from the archive path in its command."""
    for word in cmd:
        m = _VERSION_IN_CMD.search(word)
        if m:
            return m.group(1)
    return None


def describe(attrs: dict[str, Any], now: datetime) -> dict[str, Any]:
    """The container facts status reports (pure: inspect data in, plain values out)."""
    state = attrs.get("State") or {}
    started = parse_timestamp(state.get("StartedAt"))
    running = bool(state.get("Running")) and not state.get("Restarting")
    cmd = list((attrs.get("Config") or {}).get("Cmd") or [])
    return {
        "container": str(attrs.get("Name", "")).lstrip("/"),
        "state": "restarting" if state.get("Restarting") else str(state.get("Status", "?")),
        "exit_code": state.get("ExitCode"),
        "restart_count": int(attrs.get("RestartCount", 0)),
        "started_at": started.isoformat() if started else None,
        "uptime_s": round((now - started).total_seconds(), 1) if running and started else None,
        "running_version": running_version(cmd),
        "image": (attrs.get("Config") or {}).get("Image"),
    }


def status_task(ctx: RobotContext) -> RobotResult:
    """`manager status` on one robot."""
    name = ctx.robot.name
    cfg = read_config(ctx)
    state = parse_state(read_file(ctx, state_path(cfg.home)))
    in_compose = SERVICE in cfg.compose.services()
    disable = cfg.compose.args.get(DISABLE_ARG)
    data: dict[str, Any] = {
        "service": SERVICE, "in_compose": in_compose, "driver_service": cfg.service,
        "disable_manager": disable, "deployed": state is not None,
        "version": (state or {}).get("version"), "mode": (state or {}).get("mode"),
        "stack": cfg.stack.label(),
    }
    stock = "stock manager stood down" if _true(disable) else "stock manager running"
    if not in_compose and state is None:
        return RobotResult(name, Outcome.OK, f"not deployed ({DISABLE_ARG} {disable or 'not set'}: {stock})",
                           data=data)
    warnings: list[str] = []
    if not _true(disable):
        warnings.append(f"{DISABLE_ARG} is not set on {cfg.service}: the stock manager runs beside this one")
    if state is None:
        warnings.append("no deployed.json: deployed by hand or half removed; deploy again or remove")
    client = ctx.transport.docker() if ctx.robot.transport != "local" else None
    if client is None:
        return RobotResult(name, Outcome.SKIPPED, f"no docker engine; {_what(data)}", data=data, warnings=warnings)
    ctrs = manager_containers(client)
    if not ctrs:
        data["state"] = "missing"
        return RobotResult(name, Outcome.FAILED, f"{_what(data)}: no container for service {SERVICE}", data=data,
                           warnings=warnings)
    data.update(describe(ctrs[0].attrs, engine_now(client)))
    if data["running_version"] and data["version"] and data["running_version"] != data["version"]:
        warnings.append(f"the container runs {data['running_version']}, deployed.json says {data['version']}")
    if not in_compose:
        warnings.append(f"{SERVICE} is not in compose.yaml but its container exists (an orphan)")
    elif cfg.compose.image(SERVICE) != cfg.compose.driver_image:
        warnings.append(f"{SERVICE} runs {cfg.compose.image(SERVICE)}, the driver {cfg.compose.driver_image}: "
                        "deploy again after a driver update")
    if data["state"] != "running":
        return RobotResult(name, Outcome.FAILED,
                           f"{_what(data)}: container {data['state']} (exit code {data['exit_code']}, "
                           f"{data['restart_count']} restarts)", data=data, warnings=warnings)
    msg = (f"{_what(data)}: running {human_duration(data['uptime_s'])}, {data['restart_count']} restarts; "
           f"{DISABLE_ARG}:={disable}" if disable else f"{_what(data)}: running; {DISABLE_ARG} not set")
    outcome = Outcome.OK if _true(disable) else Outcome.FAILED
    return RobotResult(name, outcome, msg, data=data, warnings=warnings)


def _true(value: str | None) -> bool:
    return value is not None and value.strip().lower() in ("true", "1")


def _what(data: dict[str, Any]) -> str:
    return f"manager {data.get('version') or '?'} ({data.get('mode') or '?'})"


def open_logs(ctx: RobotContext, opts: LogOptions) -> tuple[str, Any]:
    """(container name, logs): bytes, or an iterator of chunks when following.

    Raises:
        NoEngineError: no docker engine (a demo robot).
        RemoteStateError: no manager container.
    """
    from panther_ops.core.containers.engine import NoEngineError, engine

    client, why = engine(ctx)
    if client is None:  # a demo robot: skipped, as the driver's logs are
        raise NoEngineError(why or "no docker engine on this robot")
    ctrs = manager_containers(client)
    if not ctrs:
        raise RemoteStateError(f"no container for service {SERVICE}: the manager is not deployed",
                               hint=f"panther-ops manager deploy -r {ctx.robot.name}")
    ctr = ctrs[0]
    return read_logs(client, ctr, opts)


