"""`driver status|logs|versions`: the driver container as the robot's docker engine shows it."""

from __future__ import annotations

import posixpath
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any

from panther_ops.core.containers.engine import NoEngineError, engine
from panther_ops.core.containers.logs import LogOptions, read_logs
from panther_ops.core.containers.times import engine_now, human_duration, parse_timestamp
from panther_ops.core.driver.images import HubTag, local_images, newer_tags
from panther_ops.core.driver.plan import compose_argv
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import service_containers
from panther_ops.core.parse.shell_words import CommandSyntaxError, command_words
from panther_ops.core.robot.read import read_config
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import RemoteStateError, UsageError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.docker_client import NotInEngine, engine_errors

_DURATION_PART = re.compile(r"([0-9]+(?:\.[0-9]+)?)([smhd])")


_UNIT_S = {"s": 1.0, "m": 60.0, "h": 3600.0, "d": 86400.0}


def parse_duration(text: str) -> float:
    """``90`` / ``90s`` / ``10m`` / ``1h30m`` / ``2d`` -> seconds.

    Raises:
        UsageError: anything else.
    """
    from panther_ops.core.parse.numbers import decimal

    t = text.strip().lower()
    if re.fullmatch(r"[0-9]+(?:\.[0-9]+)?", t):
        return decimal(t)
    if t and re.fullmatch(r"(?:[0-9]+(?:\.[0-9]+)?[smhd])+", t):
        return sum(decimal(n) * _UNIT_S[u] for n, u in _DURATION_PART.findall(t))
    raise UsageError(f"{text!r} is not a duration", hint="e.g. 90s, 10m, 1h30m, 2d")


_INTERPOLATED = re.compile(r"\$[{$A-Za-z_]")
"""A word compose interpolates (``${VAR}``, ``$VAR``, ``$$``); ``$(...)`` it leaves to the shell."""


def argv_matches(running: list[str], compose: list[str]) -> bool:
    """The container's command is compose.yaml's (a word compose interpolates matches any word).

    A ``bash -c "..."`` command is compared word by word inside its script: the script of
    husarion/panther-docker's gamepad holds ``$(ros2 pkg prefix joy2twist)``, which the
    container's ``Cmd`` keeps as written (the shell expands it)."""
    try:
        (shell_a, words_a), (shell_b, words_b) = command_words(running), command_words(compose)
    except CommandSyntaxError:
        (shell_a, words_a), (shell_b, words_b) = ((), running), ((), compose)
    if shell_a != shell_b or len(words_a) != len(words_b):
        return False
    return all(a == b or _INTERPOLATED.search(b) for a, b in zip(words_a, words_b, strict=True))


@dataclass
class ContainerView:
    data: dict[str, Any]
    warnings: list[str] = field(default_factory=list)
    healthy: bool = True
    problem: str | None = None


def describe_container(attrs: Mapping[str, Any], *, compose_image: str | None, compose_argv: list[str] | None,
                       now: datetime | None) -> ContainerView:
    """A driver container's inspect data as the `driver status` view (pure)."""
    state = attrs.get("State") or {}
    config = attrs.get("Config") or {}
    status = str(state.get("Status") or "?")
    restarting = bool(state.get("Restarting"))
    started = parse_timestamp(state.get("StartedAt"))
    finished = parse_timestamp(state.get("FinishedAt"))
    health = (state.get("Health") or {}).get("Status")
    cmd = [str(x) for x in (config.get("Cmd") or [])]
    running = status == "running" and not restarting
    uptime = (now - started).total_seconds() if running and started and now else None
    data: dict[str, Any] = {
        "container": str(attrs.get("Name", "")).lstrip("/"),
        "container_id": str(attrs.get("Id", ""))[:12],
        "image": config.get("Image"),
        "state": "restarting" if restarting else status,
        "started_at": state.get("StartedAt") if started else None,
        "finished_at": state.get("FinishedAt") if finished else None,
        "uptime_s": None if uptime is None else round(uptime, 1),
        "restart_count": int(attrs.get("RestartCount") or 0),
        "exit_code": state.get("ExitCode"),
        "health": health,
        "command": cmd,
        "compose_image": compose_image,
        "compose_command": compose_argv,
        "command_drift": None if compose_argv is None else not argv_matches(cmd, compose_argv),
        "image_drift": None if compose_image is None else config.get("Image") != compose_image,
    }
    view = ContainerView(data)
    if data["image_drift"]:
        view.warnings.append(f"the container runs {config.get('Image')} but compose.yaml says {compose_image}: "
                             "recreate it (panther-ops driver restart)")
    if data["command_drift"]:
        view.warnings.append("the container's launch command differs from compose.yaml's: recreate it "
                             "(panther-ops driver restart); running: " + " ".join(cmd))
    if data["restart_count"] and running:
        # no exit code: docker sets a container's to 0 when it starts it again
        view.warnings.append(f"restarted {data['restart_count']} time(s) since it was created: "
                             "panther-ops driver logs shows why it stopped")
    if health == "unhealthy":
        view.healthy = False
        view.problem = "unhealthy (healthcheck failing)"
    if not running:
        view.healthy = False
        view.problem = (f"restarting (exit code {state.get('ExitCode')}, {data['restart_count']} restarts)"
                        if restarting else f"{status} (exit code {state.get('ExitCode')})")
    return view


def driver_container(client: Any, cfg: RobotConfig) -> Any | None:
    """The driver's container: by compose service label, else by container_name."""
    service = cfg.service
    # cfg.compose_path is absolute (read with the robot user's home): its project's containers first
    found = service_containers(client, service, posixpath.dirname(cfg.compose_path))
    if found:
        return found[0]
    name = cfg.compose.service(service).get("container_name") or service
    try:
        with engine_errors():
            return client.containers.get(str(name))
    except NotInEngine:
        return None


def last_line(text: str, limit: int = 300) -> str:
    """The last non-empty line of a command's output (docker puts the error there), shortened."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[-1][-limit:] if lines else ""


def status_task(ctx: RobotContext) -> RobotResult:
    """`driver status`: the driver container against compose.yaml."""
    cfg = read_config(ctx)
    service, image, argv = cfg.service, cfg.compose.driver_image, compose_argv(cfg)
    base = {"service": service, "compose_image": image, "compose_command": argv, "stack": cfg.stack.label()}
    client, why = engine(ctx)
    if client is None:
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, str(why), data={**base, "docker_skipped": why})
    ctr = driver_container(client, cfg)
    if ctr is None:
        res = RobotResult(ctx.robot.name, Outcome.FAILED, f"no container for service {service}",
                          data={**base, "state": "missing"})
        res.data["hint"] = f"start it: panther-ops driver restart -r {ctx.robot.name}"
        return res
    view = describe_container(ctr.attrs, compose_image=image, compose_argv=argv, now=engine_now(client))
    data = {**base, **view.data}
    if view.problem:
        return RobotResult(ctx.robot.name, Outcome.FAILED, f"{service}: {view.problem}", data=data,
                           warnings=view.warnings)
    msg = f"{service} running {human_duration(data['uptime_s'])}, {data['image']}"
    return RobotResult(ctx.robot.name, Outcome.OK, msg, data=data, warnings=view.warnings)


def open_logs(ctx: RobotContext, opts: LogOptions) -> tuple[str, Any]:
    """(container name, logs): bytes, or an iterator of bytes chunks when following.

    Raises:
        NoEngineError: no docker engine.
        RemoteStateError: no driver container.
    """
    cfg = read_config(ctx)
    client, why = engine(ctx)
    if client is None:
        raise NoEngineError(str(why))
    ctr = driver_container(client, cfg)
    if ctr is None:
        raise RemoteStateError(f"no container for service {cfg.service}", hint="panther-ops driver restart")
    return read_logs(client, ctr, opts)


def versions_task(remote: Mapping[str, list[HubTag]] | None) -> Callable[[RobotContext], RobotResult]:
    """`driver versions`: driver images on each robot, and newer ones on Docker Hub when asked."""

    def task(ctx: RobotContext) -> RobotResult:
        cfg = read_config(ctx)
        image = cfg.compose.driver_image
        data: dict[str, Any] = {"compose_image": image, "service": cfg.service}
        if remote is not None:
            data["newer"] = newer_tags(image, [t for tags in remote.values() for t in tags])
        client, why = engine(ctx)
        if client is None:
            data["docker_skipped"] = why
            return RobotResult(ctx.robot.name, Outcome.SKIPPED, str(why), data=data)
        ctr = driver_container(client, cfg)
        running_id = ctr.attrs.get("Image") if ctr is not None else None
        data["running_image"] = ctr.attrs.get("Config", {}).get("Image") if ctr is not None else None
        data["local"] = local_images([i.attrs for i in client.images.list()], compose_image=image,
                                     running_ref=data["running_image"], running_image_id=running_id)
        used = next((e["image"] for e in data["local"] if e["in_use"]), None)
        msg = f"{len(data['local'])} driver image(s); in use: {used or 'none (no driver container)'}"
        if data.get("newer"):
            msg += f"; newer on Docker Hub: {data['newer'][0]}"
        return RobotResult(ctx.robot.name, Outcome.OK, msg, data=data)

    return task
