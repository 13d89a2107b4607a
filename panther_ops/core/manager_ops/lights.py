"""`lights test`: call lights/set_animation inside the robot's driver container."""

from __future__ import annotations

import json

from panther_ops.core.config.robot import read_config
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import RemoteStateError
from panther_ops.results import Outcome, RobotResult


def service_call_argv(msg_pkg: str, namespace: str, anim_id: int, param: str, repeating: bool) -> list[str]:
    """The manual's `ros2 service call .../lights/set_animation ...` as an argv (no shell)."""
    request = "{animation: {id: %d, param: %s}, repeating: %s}" % (  # noqa: UP031 - YAML, not Python
        anim_id, json.dumps(param), "true" if repeating else "false")
    service = f"/{namespace.strip('/')}/lights/set_animation" if namespace.strip("/") else "/lights/set_animation"
    return ["ros2", "service", "call", service, f"{msg_pkg}/srv/SetLEDAnimation", request]


def set_animation(ctx: RobotContext, anim_id: int, param: str, repeating: bool) -> RobotResult:
    cfg = read_config(ctx)
    client = ctx.transport.docker()
    if client is None:
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, "no docker engine on this robot (demo robot)")
    containers = client.containers.list(filters={"label": f"com.docker.compose.service={cfg.service}"})
    if not containers:
        raise RemoteStateError(f"the driver ({cfg.service}) is not running", hint="panther-ops driver status")
    env_ns = cfg.compose.environment(cfg.service).get("ROBOT_NAMESPACE")
    namespace = ctx.robot.namespace or cfg.compose.args.get("namespace") or env_ns or ""
    msg_pkg = "husarion_ugv_msgs" if cfg.stack.has_config_tree else "panther_msgs"
    argv = service_call_argv(msg_pkg, namespace, anim_id, param, repeating)
    # the image's entrypoint sources the ROS environment, then runs the command (no shell in between)
    code, output = containers[0].exec_run(["/ros_entrypoint.sh", *argv], demux=False)
    text = (output or b"").decode(errors="replace").strip()
    if code != 0:
        return RobotResult(ctx.robot.name, Outcome.FAILED, f"service call failed (exit {code}): {text[-300:]}")
    return RobotResult(ctx.robot.name, Outcome.CHANGED, f"animation {anim_id} requested", data={"argv": argv,
                       "response": text[-500:]})
