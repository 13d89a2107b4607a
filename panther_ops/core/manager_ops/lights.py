"""`lights test`: call the lights' set-animation service inside the robot's driver container.

The service, its type and the namespace follow the robot's stack (`panther_ops.manager.adapters.
interfaces`, the one table the deployed manager uses too): ``/<ns>/lights/controller/set/animation``
with ``panther_msgs`` on panther_ros 2.0.x, ``/<ns>/lights/set_animation`` with ``panther_msgs`` on
2.1.x and with ``husarion_ugv_msgs`` on husarion_ugv 2.2. The namespace is the one the driver runs
under: the inventory's ``namespace:``, else the driver's ``namespace:=`` argument (2.0.x), else
``ROBOT_NAMESPACE`` of its ``environment`` (2.1), else of its ``env_file`` (2.2:
``~/config/common/.env``), read on the robot.
"""

from __future__ import annotations

import json
import posixpath
import re

from panther_ops.core.config.robot import read_config
from panther_ops.core.config.robot_config import RobotConfig
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import RemoteStateError
from panther_ops.manager.adapters.interfaces import RosInterfaces, interfaces_for
from panther_ops.results import Outcome, RobotResult

_DEFAULTED = re.compile(r"^\$\{[A-Za-z_][A-Za-z0-9_]*:?-([^}]*)\}$")


def service_call_argv(ros: RosInterfaces, namespace: str, anim_id: int, param: str, repeating: bool) -> list[str]:
    """The manual's `ros2 service call .../lights/set_animation ...` as an argv (no shell)."""
    request = "{animation: {id: %d, param: %s}, repeating: %s}" % (  # noqa: UP031 - YAML, not Python
        anim_id, json.dumps(param), "true" if repeating else "false")
    return ["ros2", "service", "call", ros.service_path("lights/set_animation", namespace),
            ros.set_led_animation_type, request]


def _plain(value: str | None) -> str | None:
    """A compose value as the container sees it: ``${VAR:-default}`` -> default (no variables here)."""
    if value is None:
        return None
    value = value.strip().strip("'\"")
    m = _DEFAULTED.match(value)
    return m.group(1) if m else value


def _dotenv(text: str, key: str) -> str | None:
    found = None
    for raw in text.splitlines():
        line = raw.strip()
        line = line[7:].lstrip() if line.startswith("export ") else line
        if line.startswith(f"{key}="):
            found = _plain(line.split("=", 1)[1].split(" #", 1)[0])
    return found


def robot_namespace(ctx: RobotContext, cfg: RobotConfig) -> str:
    """The ROS namespace the robot's driver runs under ("" = none)."""
    if ctx.robot.namespace:
        return ctx.robot.namespace
    arg = cfg.compose.args.get("namespace")
    if arg:
        return arg
    env = _plain(cfg.compose.environment(cfg.service).get("ROBOT_NAMESPACE"))
    if env is not None:
        return env
    found = None
    for name in cfg.compose.env_files(cfg.service):  # later files win, as in compose
        path = name.replace("~", cfg.home, 1) if name.startswith("~/") else name
        path = path if path.startswith("/") else posixpath.join(posixpath.dirname(cfg.compose_path), path)
        try:
            text = ctx.transport.read_file(path).decode(errors="replace")
        except FileNotFoundError:
            continue
        found = _dotenv(text, "ROBOT_NAMESPACE") or found
    return found or ""


def set_animation(ctx: RobotContext, anim_id: int, param: str, repeating: bool) -> RobotResult:
    cfg = read_config(ctx)
    client = ctx.transport.docker()
    if client is None:
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, "no docker engine on this robot (demo robot)")
    containers = client.containers.list(filters={"label": f"com.docker.compose.service={cfg.service}"})
    if not containers:
        raise RemoteStateError(f"the driver ({cfg.service}) is not running", hint="panther-ops driver status")
    ros = interfaces_for(cfg.stack.version)
    argv = service_call_argv(ros, robot_namespace(ctx, cfg), anim_id, param, repeating)
    # the image's entrypoint sources the ROS environment, then runs the command (no shell in between)
    code, output = containers[0].exec_run(["/ros_entrypoint.sh", *argv], demux=False)
    text = (output or b"").decode(errors="replace").strip()
    if code != 0:
        return RobotResult(ctx.robot.name, Outcome.FAILED, f"service call failed (exit {code}): {text[-300:]}")
    return RobotResult(ctx.robot.name, Outcome.CHANGED, f"animation {anim_id} requested on {argv[3]}",
                       data={"argv": argv, "response": text[-500:]})
