"""`panther-ops gps router show|set`: the RUTX11's NMEA forwarding (registered under `gps`)."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Annotated, Any, Optional

import typer

from panther_ops.cli import context
from panther_ops.cli.mutate import DryRun, Yes, mutate
from panther_ops.cli.options import All, Forks, Groups, Json, Robots

if TYPE_CHECKING:
    from panther_ops.results import FleetResult


router_app = typer.Typer(
    help="The RUTX11 router's NMEA forwarding (REST API, through the robot's SSH connection).",
    no_args_is_help=True,
)

Address = Annotated[
    str, typer.Option("--address", help="The router's address on the robot's LAN (default 10.15.20.1).")
]


def credentials() -> Any:
    from panther_ops.core.gps.credentials import load_credentials

    def ask() -> tuple[str, str]:
        user = typer.prompt("router user", default="admin", err=True)
        return user, typer.prompt("router password", hide_input=True, err=True)

    return load_credentials(ask if sys.stdin.isatty() else None)


def _print_router(fleet: FleetResult) -> None:
    from rich.table import Table

    from panther_ops.cli.render import STYLE, _console, esc, print_summary, print_warnings

    table = Table(title="panther-ops gps router show")
    for col in ("robot", "result", "gps", "forwarding", "to", "sentences", "message"):
        table.add_column(col, overflow="fold")
    for r in fleet.results:
        d = r.data
        if "forwarding" not in d:
            table.add_row(r.robot, f"[{STYLE[r.outcome]}]{r.outcome.value}[/]", "", "", "", "", esc(r.message))
            continue
        table.add_row(r.robot, f"[{STYLE[r.outcome]}]{r.outcome.value}[/]", "on" if d["gps_enabled"] else "off",
                      "on" if d["forwarding"] else "off", esc(f"{d['hostname']}:{d['port']}/{d['proto']}"),
                      esc(",".join(d["sentences"])), "")
    _console().print(table)
    print_warnings(fleet)
    print_summary(fleet)


@router_app.command("show")
def router_show(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    address: Address = "10.15.20.1",
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """The router's GNSS switch, NMEA forwarding (enabled, hostname, port, protocol) and the
    sentences it forwards, per robot. The router's certificate is pinned on first use.

    Example: PANTHER_OPS_ROUTER_PASSWORD=... panther-ops gps router show --all
    """
    from panther_ops.cli.render import finish
    from panther_ops.core.gps.router import show_task
    from panther_ops.core.gps.router_plan import check_address

    check_address(address)
    creds = credentials()
    inv, chosen = context.targets(ctx, robot, group, all_)
    return finish(context.run("gps router show", inv, chosen, show_task(address, creds), forks=forks,
                              json_out=json_out), json_out, _print_router)


@router_app.command("set")
def router_set(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    address: Address = "10.15.20.1",
    enable: Annotated[
        Optional[bool],  # noqa: UP045
        typer.Option("--enable/--disable", help="Turn NMEA forwarding on (and the GNSS with it) or off."),
    ] = None,
    hostname: Annotated[
        Optional[str],  # noqa: UP045
        typer.Option("--hostname", help="Where the router sends NMEA (the Built-in Computer: 10.15.20.2)."),
    ] = None,
    port: Annotated[
        Optional[int],  # noqa: UP045
        typer.Option("--port", help="UDP port the router sends NMEA to (5000)."),
    ] = None,
    sentences: Annotated[
        Optional[str],  # noqa: UP045
        typer.Option("--sentences", help="Forward exactly these sentence ids (e.g. GPGGA,GPRMC), the others not."),
    ] = None,
    yes: Yes = False,
    dry_run: DryRun = False,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Set the router's NMEA forwarding; only what differs is sent (PUT, values as strings),
    then read back. Shows the change and asks first (--yes: without asking).

    Example: panther-ops gps router set -r panther-01 --enable --hostname 10.15.20.2 --port 5000 --yes
    """
    from panther_ops.core.gps.router import apply_router, plan_router
    from panther_ops.core.gps.router_plan import RouterRequest, check_address, parse_sentences
    from panther_ops.errors import UsageError

    req = RouterRequest(enabled=enable, hostname=hostname, port=port, sentences=parse_sentences(sentences))
    if req.empty:
        raise UsageError("nothing to set", hint="--enable/--disable, --hostname, --port or --sentences")
    check_address(address)
    creds = credentials()
    inv, chosen = context.targets(ctx, robot, group, all_)
    return mutate("gps router set", inv, chosen, lambda c: plan_router(c, address, creds, req),
                  applier=apply_router(address, creds, req), yes=yes, dry_run=dry_run, json_out=json_out,
                  forks=forks, verb="Change the router of")
