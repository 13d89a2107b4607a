"""`status` and `doctor`: read-only views of the fleet."""

from __future__ import annotations

from typing import Annotated

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.options import READ, shared


@shared(*READ)
def status(fleet: Fleet) -> int:
    """Each robot: reachable, hostname, OS build, model/serial, stack and version, containers
    (state, restart count), free disk, clock offset from this machine.

    One SSH connection per robot (docker state rides the same connection).

    \b
    Example:
      panther-ops -i fleet.yaml status --all --json
    """
    from panther_ops.cli.views.status import print_status
    from panther_ops.core.health.status import status_task

    return fleet.run("status", status_task, print_status, read_only=True)


@shared(*READ, "canary", "max_fail")
def doctor(
    fleet: Fleet,
    password_check: Annotated[
        bool, typer.Option("--password-check/--no-password-check",
                           help="Try the default password 'husarion' once per robot (a second connection).")
    ] = True,
) -> int:
    """Check the fleet before changing it: time sync (warn above 1 s, per robot and across
    the fleet), key authentication, docker and compose v2, free disk, supported stack, and
    whether the default password is still accepted. Every finding comes with its fix.

    \b
    Example:
      panther-ops doctor --all
    """
    from panther_ops.cli.views.status import print_doctor
    from panther_ops.core.health.doctor import fleet_findings, make_doctor_task, unreached_findings

    result = fleet.results("doctor", make_doctor_task(password_check=password_check), read_only=True)
    unreached_findings(result)
    result.data["fleet_findings"] = fleet_findings(result)
    return fleet.show(result, print_doctor)


def register(app: typer.Typer) -> None:
    app.command("status")(status)
    app.command("doctor")(doctor)
