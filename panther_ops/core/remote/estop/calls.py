"""Asking the driver about its E-stop: one command per robot, run inside the driver container.

The driver's ROS API (panther_ros ROS_API.md; the same names from 2.0 to husarion_ugv 2.2):
the topic ``<ns>/hardware/e_stop`` (std_msgs/Bool, true = triggered), the services
``<ns>/hardware/e_stop_trigger`` and ``<ns>/hardware/e_stop_reset`` (std_srvs/Trigger), and
``<ns>/cmd_vel`` (its publishers are named; the driver refuses a reset while the last velocity
command is not zero, `plan`'s docstring gives each release's rule and source). On
husarion_ugv 2.3.2 cmd_vel is one input of the twist mux (its subscriber), beside ``manual/cmd_vel``
and ``autonomous/cmd_vel``: their publishers are asked for too (sections ``publishers_manual``,
``publishers_autonomous``). On every release the driver alone judges a reset (`plan.plan_reset`).

Per stack version only the way in differs: the driver's container (``panther_ros`` up to
2.1, ``husarion_ugv_ros`` from 2.2; found among the running containers by compose service,
name or image, as compose.yaml's driver service is) and where its namespace comes from (the
inventory's ``namespace``, else the launch argument ``namespace:=`` of the container's main
process (2.0), else its ``ROBOT_NAMESPACE``: compose.yaml's environment (2.1), the env_file
(2.2)). Nothing is read before: one command per robot, so a trigger costs one round trip.
Every ROS 2 command the robot runs is bounded by ``timeout``.

The way in (the robot script, the exec in the driver container, its sections) is the shared
engine's (:mod:`panther_ops.core.containers.driver_exec`); the E-stop's own part is
:data:`CONTAINER_SCRIPT`.

A demo robot (a directory) has no driver: it answers from a recording in its directory
(:data:`DEMO_RECORDING`), the same ROS 2 CLI texts a robot prints; trigger and reset are
not called there.
"""

from __future__ import annotations

import json
from typing import Any

from panther_ops.core.containers import driver_exec
from panther_ops.core.containers.driver_exec import NAMESPACE_SH
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.remote.estop import answers
from panther_ops.core.remote.estop.plan import (
    E_STOP_TOPIC,
    RESET_SERVICE,
    ROS_TIMEOUT_S,
    TRIGGER_SERVICE,
    answer_tail,
    nonzero_hint,
    plan_reset,
    refused_for_velocity,
    state_of,
    state_text,
)
from panther_ops.errors import RemoteStateError, TransportError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command

DEMO_RECORDING = "/var/lib/panther-ops-demo/ros.json"
"""Where a demo robot keeps the recorded answers of its driver (inside its directory)."""

#: In the driver container (after the image's entrypoint sourced ROS): $1 timeout, $2 the
#: namespace ('' = the launch's `namespace:=` argument of the container's main process, else
#: ROBOT_NAMESPACE), then the actions in order.
CONTAINER_SCRIPT = r"""t=$1 ns=$2; shift 2
""" + NAMESPACE_SH + r"""for a in "$@"; do
    echo "@@$a"
    case $a in
        status) timeout "$t" ros2 topic echo --once "$p/hardware/e_stop" std_msgs/msg/Bool 2>&1 ;;
        publishers)
            out=$(timeout "$t" ros2 topic info -v "$p/cmd_vel" 2>&1); s=$?
            printf '%s\n' "$out"
            case $out in *"Node name: twist_mux_controller"*)  # 2.3.2: the mux's other inputs too
                for i in manual autonomous; do
                    echo "@@exit $s"
                    echo "@@publishers_$i"
                    timeout "$t" ros2 topic info -v "$p/$i/cmd_vel" 2>&1; s=$?
                done ;;
            esac
            (exit $s) ;;
        trigger) timeout "$t" ros2 service call "$p/hardware/e_stop_trigger" std_srvs/srv/Trigger 2>&1 ;;
        reset) timeout "$t" ros2 service call "$p/hardware/e_stop_reset" std_srvs/srv/Trigger 2>&1 ;;
        keyboard) timeout "$t" python3 -c 'import rclpy, geometry_msgs.msg, termios' 2>&1 ;;
        *) echo "unknown action $a"; false ;;
    esac
    echo "@@exit $?"
done
"""

ACTIONS = ("status", "publishers", "trigger", "reset", "keyboard")
"""``keyboard``: whether the container's python3 has what `teleop`'s program imports
(`panther_ops.core.remote.teleop.program.CHECK`)."""


def command(namespace: str, actions: tuple[str, ...], timeout: int = ROS_TIMEOUT_S) -> Command:
    """The one command the robot runs for ``actions`` (each a name of :data:`ACTIONS`);
    ``namespace`` '' lets the driver container tell its own."""
    unknown = [a for a in actions if a not in ACTIONS]
    if unknown:
        raise ValueError(f"unknown E-stop actions {unknown}")
    return driver_exec.command(CONTAINER_SCRIPT, [str(timeout), namespace, *actions])


def is_demo(ctx: RobotContext) -> bool:
    return ctx.robot.transport == "local"


def ask(ctx: RobotContext, actions: tuple[str, ...]) -> answers.Answers:
    """Run ``actions`` in the robot's driver container (one command, nothing read before it);
    a demo robot answers from its recording (only ``status`` and ``publishers`` are recorded)."""
    if is_demo(ctx):
        return recorded(ctx, actions)
    return driver_exec.ask(ctx, command(ctx.robot.namespace or "", actions), ROS_TIMEOUT_S * len(actions) + 30)


def recorded(ctx: RobotContext, actions: tuple[str, ...]) -> answers.Answers:
    """A demo robot's recorded answers, in the format a robot's answers come in."""
    try:
        raw = json.loads(ctx.transport.read_file(DEMO_RECORDING).decode())
    except FileNotFoundError:
        raise RemoteStateError(f"no recorded driver answers ({DEMO_RECORDING})",
                               hint="recreate the demo fleet: panther-ops demo init --force") from None
    except ValueError as exc:
        raise TransportError(ctx.robot.name, f"{DEMO_RECORDING}: not JSON ({exc})") from None
    asked = [k for k in raw if k in actions or (k.split("_")[0] == "publishers" and "publishers" in actions)]
    sections = {a: answers.Section(a, str(raw[a]), 0) for a in asked}
    return answers.Answers(str(raw.get("namespace", "/")), sections)


def status_task(ctx: RobotContext) -> RobotResult:
    """`estop status`: the E-stop and who publishes on cmd_vel."""
    state = state_of(ask(ctx, ("status", "publishers")))
    data = {**state.to_json(), "recorded": is_demo(ctx)}
    if state.problems:
        return RobotResult(ctx.robot.name, Outcome.FAILED, "; ".join(state.problems), data=data)
    note = " (recorded answer: demo robot)" if is_demo(ctx) else ""
    return RobotResult(ctx.robot.name, Outcome.OK, state_text(state) + note, data=data)


def trigger_task(ctx: RobotContext) -> RobotResult:
    """`estop trigger`: the trigger service, answered by the driver."""
    if is_demo(ctx):
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, "demo robot: no driver to call")
    got = ask(ctx, ("trigger",))
    return _service_result(ctx, got, "trigger", TRIGGER_SERVICE, "E-stop triggered")


def read_and_plan_reset(ctx: RobotContext) -> RobotPlan:
    """`estop reset`'s read (the E-stop and cmd_vel's publishers, one command), then its plan."""
    return plan_reset(ctx.robot.name, state_of(ask(ctx, ("status", "publishers"))))


def reset_task(ctx: RobotContext, planned: dict[str, Any] | None = None) -> RobotResult:
    """`estop reset`, second phase: the reset service, then the E-stop read back. ``planned``:
    the plan's reading (`State.to_json`), whose velocity publishers a refusal names."""
    if is_demo(ctx):
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, "demo robot: no driver to call")
    got = ask(ctx, ("reset", "status"))
    result = _service_result(ctx, got, "reset", RESET_SERVICE, "E-stop reset")
    if result.outcome is Outcome.FAILED and refused_for_velocity(str(result.data.get("response", ""))):
        result.message += "; " + nonzero_hint(planned or {"namespace": got.namespace})
    if result.outcome is Outcome.CHANGED:
        state = state_of(got)
        result.data.update(state.to_json())
        if state.triggered is not False:
            result.outcome = Outcome.FAILED
            result.message += f"; but {state.topic(E_STOP_TOPIC)} still says " + (
                "triggered" if state.triggered else "nothing")
    return result


def _service_result(ctx: RobotContext, got: answers.Answers, action: str, service: str, done: str) -> RobotResult:
    name = f"{got.namespace.rstrip('/')}/{service}"
    section = got.get(action)
    response = answers.trigger_response(section.text) if section is not None else None
    data: dict[str, Any] = {"namespace": got.namespace, "service": name}
    if response is None:
        text = section.text if section is not None else ""
        return RobotResult(ctx.robot.name, Outcome.FAILED,
                           f"no answer from {name} within {ROS_TIMEOUT_S} s{answer_tail(text)}", data=data)
    success, message = response
    data.update(success=success, response=message)
    if not success:
        return RobotResult(ctx.robot.name, Outcome.FAILED, f"{name} refused: {message}", data=data)
    # the drivers answer a reset with an empty message (panther_ros@2.1.1:panther_hardware_interfaces/src/
    # panther_system/panther_system_ros_interface.cpp, husarion_ugv_ros@2.3.2:.../system_ros_interface.cpp
    # CallbackWrapper: only a refusal sets it)
    return RobotResult(ctx.robot.name, Outcome.CHANGED, f"{done} ({message})" if message else done, data=data)
