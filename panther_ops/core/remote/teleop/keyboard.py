"""`teleop`: the manual's keyboard teleoperation, run in the robot's driver container.

Before anything moves, in one command in the driver container: the E-stop (refused while
triggered, with the way to reset it), the publishers of ``cmd_vel`` (a warning: "do not try
controlling the robot from different sources at the same time") and whether the container's
python3 imports rclpy and geometry_msgs (refused, naming what is missing). Then the keyboard
program of `program` (what ``teleop_twist_keyboard`` does; the images do not have that
package) runs in the driver container (``docker exec -it``) on a pseudo-terminal of the
robot's connection, publishing on the robot's ``cmd_vel`` every ``1/rate`` s (the manual's
repeat_rate 10.0: the robot stops when no command arrived for 1 s; 10 Hz is the minimum); on
husarion_ugv 2.3.2 (its twist mux subscribes cmd_vel) stamped twists on ``manual/cmd_vel``.
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.remote.estop.answers import Section
from panther_ops.core.remote.estop.calls import ask, is_demo
from panther_ops.core.remote.estop.plan import CMD_VEL, state_of
from panther_ops.core.remote.teleop.program import CHECK, PROGRAM
from panther_ops.errors import RemoteStateError, UsageError
from panther_ops.transport.base import Command

MIN_RATE_HZ = 10.0


@dataclass(frozen=True)
class TeleopPlan:
    container: str
    namespace: str
    command: Command
    warnings: tuple[str, ...]


MANUAL = "manual/cmd_vel"
"""husarion_ugv 2.3.2: the twist mux's manual input (priority 100, as the gamepad's joy2twist:
husarion_ugv_ros@2.3.2:husarion_ugv_controller/config/WH01_controller.yaml), TwistStamped."""


def teleop_command(container: str, namespace: str, rate: float, mux: bool = False) -> Command:
    """``docker exec -it`` of the keyboard program (`program.PROGRAM`) through the image's
    entrypoint (which sources ROS), publishing on <ns>/cmd_vel every 1/rate s; with the twist
    mux (``mux``: 2.3.2), stamped twists on <ns>/manual/cmd_vel."""
    topic = f"{namespace.rstrip('/')}/{MANUAL if mux else CMD_VEL}"
    return Command.of("docker", "exec", "-it", container, "/ros_entrypoint.sh", "python3", "-c", PROGRAM,
                      topic, f"{rate:g}", "stamped" if mux else "plain")


def missing_for_keyboard(section: Section | None) -> str | None:
    """What the driver container lacks to run the keyboard program (None: nothing), from the
    ``keyboard`` check's answer (``python3 -c '<CHECK>'``)."""
    if section is None or section.status == 0:
        return None
    text = section.text.strip()
    if section.status in (126, 127) or ("python3" in text and ("not found" in text or "No such file" in text)):
        return "python3"  # the shell's or timeout's "cannot run it"
    for line in reversed(text.splitlines()):
        if "No module named" in line:
            return line.split("No module named", 1)[1].strip(" '\"")
    last = text.splitlines()[-1][-200:] if text else f"exit {section.status}"
    return f"working `python3 -c \"{CHECK}\"` ({last})"


DEMO_SKIP = "demo robot: no driver to drive (teleop needs a real robot)"
"""Why a demo robot is skipped (exit 0), as `estop trigger` and `driver logs` skip it."""


def skipped(ctx: RobotContext) -> str | None:
    """Why teleop skips this robot (a demo robot), else None."""
    return DEMO_SKIP if is_demo(ctx) else None


def prepare(ctx: RobotContext, rate: float) -> TeleopPlan:
    """Check the robot (E-stop, other publishers) and build the command (raises when refused)."""
    if rate < MIN_RATE_HZ:
        raise UsageError(f"--rate {rate:g} is below {MIN_RATE_HZ:g} Hz",
                         hint="the robot stops when no velocity command arrived for 1 s; 10 Hz is the minimum")
    if is_demo(ctx):
        raise RemoteStateError(DEMO_SKIP)
    got = ask(ctx, ("status", "publishers", "keyboard"))
    state = state_of(got)
    if state.problems:
        raise RemoteStateError("; ".join(state.problems), hint="panther-ops driver status")
    if state.triggered:
        raise RemoteStateError("the E-stop is triggered: the robot ignores cmd_vel",
                               hint=f"panther-ops estop reset -r {ctx.robot.name} --yes (after checking the "
                               "robot's surroundings)")
    warnings: tuple[str, ...] = ()
    if state.mux is not None and state.velocity_publishers():
        warnings = (f"{', '.join(state.velocity_publishers())} already publish velocity: do not control the robot "
                    "from different sources at the same time (the twist mux obeys manual/cmd_vel first)",)
    elif state.publishers:
        warnings = (f"{', '.join(state.publishers)} already publishes on {state.topic(CMD_VEL)}: do not control "
                    "the robot from different sources at the same time",)
    if not got.container:
        raise RemoteStateError("the driver container did not say its name")
    missing = missing_for_keyboard(got.get("keyboard"))
    if missing is not None:
        raise RemoteStateError(
            f"the driver container {got.container} has no {missing}: teleop runs a small rclpy publisher "
            "there (python3 with rclpy and geometry_msgs, as every ROS 2 image has; the images have no "
            "teleop_twist_keyboard); nothing was started",
            hint="is the driver running the robot's own image? panther-ops driver status")
    command = teleop_command(got.container, got.namespace, rate, mux=state.mux is not None)
    return TeleopPlan(got.container, got.namespace, command, warnings)
