"""`teleop`: the manual's keyboard teleoperation, run in the robot's driver container.

Before anything moves: the E-stop is asked (refused while triggered, with the way to reset
it) and the publishers of ``cmd_vel`` (a warning: "do not try controlling the robot from
different sources at the same time"). Then ``teleop_twist_keyboard`` runs in the driver
container (``docker exec -it``) on a pseudo-terminal of the robot's connection, with
``repeat_rate`` 10.0 (the manual's value: the robot stops when no command arrived for 1 s;
10 Hz is the recommended minimum) publishing on the robot's ``cmd_vel``.
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.remote.estop.calls import CMD_VEL, ask, is_demo, read_state
from panther_ops.errors import RemoteStateError, UsageError
from panther_ops.transport.base import Command

MIN_RATE_HZ = 10.0


@dataclass(frozen=True)
class TeleopPlan:
    container: str
    namespace: str
    command: Command
    warnings: tuple[str, ...]


def teleop_command(container: str, namespace: str, rate: float) -> Command:
    """``docker exec -it`` of teleop_twist_keyboard with repeat_rate, on <ns>/cmd_vel."""
    topic = f"{namespace.rstrip('/')}/{CMD_VEL}"
    return Command.of("docker", "exec", "-it", container, "/ros_entrypoint.sh", "ros2", "run",
                      "teleop_twist_keyboard", "teleop_twist_keyboard", "--ros-args", "-p", f"repeat_rate:={rate:g}",
                      "-r", f"cmd_vel:={topic}")


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
    got = ask(ctx, ("status", "publishers"))
    state = read_state(got)
    if state.problems:
        raise RemoteStateError("; ".join(state.problems), hint="panther-ops driver status")
    if state.triggered:
        raise RemoteStateError("the E-stop is triggered: the robot ignores cmd_vel",
                               hint=f"panther-ops estop reset -r {ctx.robot.name} --yes (after checking the "
                               "robot's surroundings)")
    warnings: tuple[str, ...] = ()
    if state.publishers:
        warnings = (f"{', '.join(state.publishers)} already publishes on {state.topic(CMD_VEL)}: do not control "
                    "the robot from different sources at the same time",)
    if not got.container:
        raise RemoteStateError("the driver container did not say its name")
    return TeleopPlan(got.container, got.namespace, teleop_command(got.container, got.namespace, rate), warnings)
