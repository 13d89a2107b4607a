"""`status`, `doctor` and `describe`: read-only views of the fleet and of one robot."""

from __future__ import annotations

from typing import Annotated

import typer

from panther_ops.cli import complete
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


@shared("json_out")
def describe(
    fleet: Fleet,
    name: Annotated[str, typer.Argument(metavar="ROBOT", help="The robot's name in the inventory.",
                                        autocompletion=complete.robot)],
) -> int:
    """One robot, part by part: how it is reached, hostname, model, OS build, stack and image,
    containers, disk, clock, the WebUI's URL, GPS, E-stop, the last change and its backup,
    and doctor's findings (each with its fix).

    One SSH connection (the WebUI is read through it); the readers are those of status,
    gps status, estop status, config history and doctor (without --password-check, which
    needs a second connection). Exit 0 when the robot was read, 4 when it is unreachable.

    \b
    Examples:
      panther-ops describe panther-01
      panther-ops describe panther-01 --json | jq .robots[0].data.status.containers
    """
    from panther_ops.cli.context import check_keys, load
    from panther_ops.cli.views.describe import print_describe
    from panther_ops.core.health.describe import describe_task
    from panther_ops.errors import UsageError

    inv = load(fleet.ctx, robots_next=True)
    chosen = inv.select([name], [], False)
    if len(chosen) != 1:
        raise UsageError(f"describe shows one robot; {name!r} names {len(chosen)}: "
                         + ", ".join(r.name for r in chosen),
                         hint=f"give one name, e.g. panther-ops describe {chosen[0].name}")
    check_keys(inv, chosen)
    return fleet.run("describe", describe_task, print_describe, on=(inv, chosen))


def register(app: typer.Typer) -> None:
    app.command("status")(status)
    app.command("doctor")(doctor)
    app.command("describe")(describe)
