"""`panther-ops status`: what each robot is, runs and how it is doing, in one connection."""

from __future__ import annotations

import time
from typing import Any

from panther_ops.core.fleet.facts import RobotFacts, clock_offset, parse_probe, probe_command
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.stack import Stack, find_driver, parse_image, stack_from_version
from panther_ops.errors import OpsError, TransportError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command


def gather_facts(ctx: RobotContext) -> tuple[RobotFacts, float | None]:
    """Run the probe; returns the facts and the clock offset (robot - here, seconds)."""
    res = ctx.transport.run(probe_command(ctx.robot.compose_file), timeout=30)
    if "@@end" not in res.stdout:
        raise TransportError(ctx.robot.name, f"probe failed (exit {res.exit_status}): {res.stderr.strip()[:200]}")
    facts = parse_probe(res.stdout)
    # The clock is read apart, on the now warm connection: one short round trip bounds the error.
    t0 = time.time()
    clock = ctx.transport.run(Command.of("date", "+%s.%N"), timeout=10)
    t1 = time.time()
    return facts, clock_offset(clock.stdout, t0, t1)


def detect_stack(ctx: RobotContext, facts: RobotFacts) -> tuple[Stack | None, str | None, str | None]:
    """(stack, driver service, problem) from the inventory's ``stack:`` or compose.yaml."""
    service: str | None = None
    if facts.compose_text is not None:
        import yaml

        try:
            found = find_driver(yaml.safe_load(facts.compose_text))
        except yaml.YAMLError as exc:
            return None, None, f"{ctx.robot.compose_file} is not valid YAML: {exc}"
        if found:
            service = found[0]
            if ctx.robot.stack == "auto":
                try:
                    return parse_image(found[1]), service, None
                except OpsError as exc:
                    return None, service, exc.message
    if ctx.robot.stack != "auto":
        return stack_from_version(ctx.robot.stack), service, None
    if facts.compose_text is None:
        return None, None, f"no {ctx.robot.compose_file} on the robot"
    return None, None, f"no Panther driver service in {ctx.robot.compose_file}"


def containers(ctx: RobotContext, facts: RobotFacts) -> tuple[list[dict[str, Any]] | None, str | None]:
    """Container list from the docker SDK (None + reason when there is no engine)."""
    if ctx.robot.transport == "local":
        return None, "demo robot: no docker engine"
    if facts.docker_server is None:
        return None, facts.docker_error or "no docker engine on this robot"
    client = ctx.transport.docker(facts.docker_api)
    if client is None:
        return None, "no docker engine on this robot"
    out: list[dict[str, Any]] = []
    for c in client.containers.list(all=True):
        attrs = c.attrs
        state = attrs.get("State", {})
        out.append(
            {
                "name": c.name,
                "image": attrs.get("Config", {}).get("Image", ""),
                "state": state.get("Status", c.status),
                "restart_count": attrs.get("RestartCount", 0),
                "started_at": state.get("StartedAt"),
                "exit_code": state.get("ExitCode"),
                "service": attrs.get("Config", {}).get("Labels", {}).get("com.docker.compose.service"),
            }
        )
    out.sort(key=lambda x: x["name"])
    return out, None


def status_task(ctx: RobotContext) -> RobotResult:
    facts, offset = gather_facts(ctx)
    stack, service, problem = detect_stack(ctx, facts)
    data: dict[str, Any] = {
        "reachable": True,
        "hostname": facts.hostname,
        "system_build_version": facts.system_build_version,
        "os": facts.os_name or None,
        "robot_model": facts.robot_model,
        "robot_serial": facts.serial,
        "robot_version": facts.robot_version,
        "stack": stack.family.value if stack else None,
        "stack_version": stack.version_str if stack else None,
        "stack_generation": stack.generation.value if stack else None,
        "driver_image": stack.image if stack else None,
        "driver_service": service,
        "disk_free_bytes": facts.disk_free_bytes,
        "disk_total_bytes": facts.disk_total_bytes,
        "clock_offset_s": None if offset is None else round(offset, 3),
        "docker": facts.docker_server,
        "compose": facts.compose_version,
    }
    warnings: list[str] = []
    if problem:
        warnings.append(problem)
    ctrs, why = containers(ctx, facts)
    data["containers"] = ctrs
    if ctrs is None:
        data["docker_skipped"] = why
        message = f"{stack.label() if stack else 'stack unknown'}; docker skipped: {why}"
    else:
        driver = next((c for c in ctrs if service and (c["service"] == service or c["name"] == service)), None)
        data["driver_state"] = driver["state"] if driver else None
        data["driver_restart_count"] = driver["restart_count"] if driver else None
        if driver and stack and driver["image"] != stack.image:
            warnings.append(
                f"driver container runs {driver['image']} but compose.yaml says {stack.image}: "
                "recreate it (panther-ops driver restart)"
            )
        state = driver["state"] if driver else "no driver container"
        message = f"{stack.label() if stack else 'stack unknown'}; driver {state}"
    from panther_ops.core.remote.webui.read import status_column

    data["webui"] = status_column(ctx)
    if data["webui"] and "error" in data["webui"]:
        warnings.append(f"WebUI on the User Computer: {data['webui']['error']}")
    return RobotResult(ctx.robot.name, Outcome.OK, message, data=data, warnings=warnings)
