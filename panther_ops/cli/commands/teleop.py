"""`panther-ops teleop -r ROBOT`: drive one robot from this terminal's keyboard."""

from __future__ import annotations

from typing import Annotated

import typer

from panther_ops.cli import context
from panther_ops.cli.options import Robots, real_number

MIN_RATE_HZ = 10.0
"""The manual's minimum frequency (the robot stops when no command arrived for 1 s)."""


def _rate(value: float) -> float:
    """--rate: at least the manual's 10 Hz (checked before anything is contacted)."""
    if value < MIN_RATE_HZ:
        raise typer.BadParameter(f"{value:g} Hz is below {MIN_RATE_HZ:g} Hz (the manual's minimum repeat_rate)")
    return value


def teleop(
    ctx: typer.Context,
    robot: Robots = None,
    rate: Annotated[float, typer.Option("--rate", parser=real_number(), callback=_rate,
                                        help="publishing rate in Hz, the manual's repeat_rate (at least 10).")] = 10.0,
) -> int:
    """The manual's keyboard teleoperation, on this terminal, over the robot's connection: a
    small rclpy publisher in the robot's driver container (the images have no
    teleop_twist_keyboard; they have python3 and rclpy, checked first) sending cmd_vel every
    1/rate s. Refused while the E-stop is triggered or when the container lacks what it
    needs; warns when another node publishes on cmd_vel. Exactly one robot. Keys as
    teleop_twist_keyboard's: u i o j l m , . move, k stops, q/z w/x e/c speeds, Ctrl-C ends.

    \b
    Example:
      panther-ops teleop -r panther-01
    """
    from panther_ops.cli.render import error
    from panther_ops.core.fleet.runner import Connections, RobotContext
    from panther_ops.core.remote.teleop.keyboard import prepare, skipped
    from panther_ops.core.remote.teleop.session import drive
    from panther_ops.errors import ExitCode, RemoteStateError, UnreachableError, UsageError

    inv, chosen = context.targets(ctx, robot, None, False)
    if len(chosen) != 1:
        raise UsageError(f"teleop drives exactly one robot, {len(chosen)} chosen", hint="-r NAME")
    with Connections(inv) as conns:
        try:
            rctx = RobotContext(chosen[0], conns.get(chosen[0]), inv)
            why = skipped(rctx)
            if why is not None:
                context.info(f"{chosen[0].name}: skipped: {why}")
                return 0
            plan = prepare(rctx, rate)
        except UnreachableError as exc:
            error(str(exc))
            return int(ExitCode.UNREACHABLE)
        except RemoteStateError as exc:  # the robot's state refuses it: that robot failed
            error(f"{chosen[0].name}: {exc}")
            return int(ExitCode.PARTIAL)
        for w in plan.warnings:
            context.info(f"warning {chosen[0].name}: {w}")
        context.info(f"{chosen[0].name}: keyboard teleop (rclpy) in {plan.container} on "
                     f"{plan.namespace.rstrip('/')}/cmd_vel at {rate:g} Hz; Ctrl-C ends")
        return drive(rctx, plan)


def register(app: typer.Typer) -> None:
    app.command("teleop")(teleop)
