"""`status` and `doctor`: read-only views of the fleet."""

from __future__ import annotations

from typing import Annotated

import typer

from panther_ops.cli import context
from panther_ops.cli.options import All, Canary, Forks, Groups, Json, MaxFail, Robots


def status(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Each robot: reachable, hostname, OS build, model/serial, stack and version, containers
    (state, restart count), free disk, clock offset from this machine.

    One SSH connection per robot (docker state rides the same connection).

    Example: panther-ops -i fleet.yaml status --all --json
    """
    from panther_ops.cli.render import finish
    from panther_ops.cli.status_view import print_status
    from panther_ops.core.health.status import status_task

    inv, chosen = context.targets(ctx, robot, group, all_, read_only=True)
    fleet = context.run("status", inv, chosen, status_task, forks=forks, json_out=json_out)
    return finish(fleet, json_out, print_status)


def doctor(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    json_out: Json = False,
    forks: Forks = None,
    canary: Canary = 0,
    max_fail: MaxFail = None,
    password_check: Annotated[
        bool, typer.Option("--password-check/--no-password-check",
                           help="Try the default password 'husarion' once per robot (a second connection).")
    ] = True,
) -> int:
    """Check the fleet before changing it: time sync (warn above 1 s, per robot and across
    the fleet), key authentication, docker and compose v2, free disk, supported stack, and
    whether the default password is still accepted. Every finding comes with its fix.

    Example: panther-ops doctor --all
    """
    from panther_ops.cli.render import finish
    from panther_ops.cli.status_view import print_doctor
    from panther_ops.core.health.doctor import fleet_findings, make_doctor_task

    inv, chosen = context.targets(ctx, robot, group, all_, read_only=True)
    fleet = context.run("doctor", inv, chosen, make_doctor_task(password_check=password_check),
                        forks=forks, canary=canary, max_fail=max_fail, json_out=json_out)
    fleet.data["fleet_findings"] = fleet_findings(fleet)
    return finish(fleet, json_out, print_doctor)


def register(app: typer.Typer) -> None:
    app.command("status")(status)
    app.command("doctor")(doctor)
