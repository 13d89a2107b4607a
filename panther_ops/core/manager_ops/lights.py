"""`lights test`: call the lights' set-animation service inside the robot's driver container.

The service, its type and the namespace follow the robot's stack (`panther_ops.manager.adapters.
interfaces`, the one table the deployed manager uses too): ``/<ns>/lights/controller/set/animation``
with ``panther_msgs`` on panther_ros 2.0.x, ``/<ns>/lights/set_animation`` with ``panther_msgs`` on
2.1.x and with ``husarion_ugv_msgs`` on husarion_ugv 2.2. The namespace is the one the driver runs
under: the inventory's ``namespace:``, else the driver's ``namespace:=`` argument (2.0.x), else
``ROBOT_NAMESPACE`` of its ``environment`` (2.1), else of its ``env_file`` (2.2:
``~/config/common/.env``), read on the robot.

The call is bounded (``timeout``: ``ros2 service call`` waits for ever for a service nobody
serves, e.g. another release's name) and its answer judged: the lights controller answers
``success=False`` with why for an animation it does not have ("No animation with ID: N",
husarion/husarion_ugv_ros@2.0.4:panther_lights/src/controller_node.cpp ``AddAnimationToQueue``;
the same in 2.1.1 and 2.2.x), so only ``success=True`` is a change.
"""

from __future__ import annotations

import json
import posixpath
import re
from typing import Any

from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import running_containers
from panther_ops.core.robot.namespace import driver_namespace
from panther_ops.core.robot.read import read_config
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import RemoteStateError
from panther_ops.manager.adapters.interfaces import RosInterfaces, interfaces_for
from panther_ops.results import Outcome, RobotResult

CALL_TIMEOUT_S = 10
"""Longest wait for the lights controller's answer (discovery included)."""
_RESPONSE = re.compile(r"SetLEDAnimation_Response\(success=(True|False), message=(['\"])(.*)\2\)\s*$", re.M)


def service_call_argv(ros: RosInterfaces, namespace: str, anim_id: int, param: str, repeating: bool) -> list[str]:
    """The manual's `ros2 service call .../lights/set_animation ...` as an argv (no shell)."""
    request = "{animation: {id: %d, param: %s}, repeating: %s}" % (  # noqa: UP031 - YAML, not Python
        anim_id, json.dumps(param), "true" if repeating else "false")
    return ["ros2", "service", "call", ros.service_path("lights/set_animation", namespace),
            ros.set_led_animation_type, request]


def robot_namespace(ctx: RobotContext, cfg: RobotConfig) -> str:
    """The ROS namespace the robot's driver runs under ("" = none): the inventory's, else the
    one its compose file and config give (`panther_ops.core.robot.namespace.driver_namespace`)."""
    return ctx.robot.namespace or read_and_plan(ctx, lambda reads: driver_namespace(reads, cfg))[0]


def set_animation(ctx: RobotContext, anim_id: int, param: str, repeating: bool) -> RobotResult:
    cfg = read_config(ctx)
    client = ctx.transport.docker()
    if client is None:
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, "no docker engine on this robot (demo robot)")
    containers = running_containers(client, cfg.service, posixpath.dirname(cfg.compose_path))
    if not containers:
        raise RemoteStateError(f"the driver ({cfg.service}) is not running", hint="panther-ops driver status")
    ros = interfaces_for(cfg.stack.version)
    argv = service_call_argv(ros, robot_namespace(ctx, cfg), anim_id, param, repeating)
    return call_in(ctx.robot.name, containers[0], argv, anim_id, ros.stack)


def call_in(robot: str, container: Any, argv: list[str], anim_id: int, stack: str) -> RobotResult:
    """Run the service call in the driver container (through the image's entrypoint, which
    sources ROS; ``timeout`` bounds it) and judge the controller's answer."""
    code, output = container.exec_run(["/ros_entrypoint.sh", "timeout", str(CALL_TIMEOUT_S), *argv], demux=False)
    text = (output or b"").decode(errors="replace").strip()
    data = {"argv": argv, "response": text[-500:]}
    found = _RESPONSE.findall(text)
    if code == 124 or (not found and "waiting for service" in text):
        return RobotResult(robot, Outcome.FAILED, f"no answer from {argv[3]} ({argv[4]}) within {CALL_TIMEOUT_S} s: "
                           f"is the lights controller running, and under that name ({stack})?", data=data)
    if not found:
        return RobotResult(robot, Outcome.FAILED, f"service call failed (exit {code}): {text[-300:]}", data=data)
    success, _, message = found[-1]
    if success != "True":
        return RobotResult(robot, Outcome.FAILED, f"{argv[3]} refused animation {anim_id}: {message or 'no reason'}",
                           data=data)
    return RobotResult(robot, Outcome.CHANGED, f"animation {anim_id} requested on {argv[3]}", data=data)
