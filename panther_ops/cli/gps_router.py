"""`panther-ops gps router show|set`: the RUTX11's NMEA forwarding (registered under `gps`)."""

from __future__ import annotations

import sys
from typing import Annotated, Any

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.options import READ, TARGETS, OptBool, OptInt, OptStr, port_number, shared

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


@router_app.command("show")
@shared(*READ)
def router_show(fleet: Fleet, address: Address = "10.15.20.1") -> int:
    """The router's GNSS switch, NMEA forwarding (enabled, hostname, port, protocol) and the
    sentences it forwards, per robot. The router's certificate is pinned on first use.

    \b
    Example:
      PANTHER_OPS_ROUTER_PASSWORD=... panther-ops gps router show --all
    """
    from panther_ops.cli.views.gps import print_router
    from panther_ops.core.gps.router.plan import check_address
    from panther_ops.core.gps.router.read import show_task

    check_address(address)
    return fleet.run("gps router show", show_task(address, credentials()), print_router, read_only=True)


@router_app.command("set")
@shared(*TARGETS, "yes", "dry_run", "json_out", "forks")
def router_set(
    fleet: Fleet,
    address: Address = "10.15.20.1",
    enable: Annotated[OptBool, typer.Option("--enable/--disable",
                                            help="Turn NMEA forwarding on (and the GNSS with it) or off.")] = None,
    hostname: Annotated[OptStr, typer.Option(
        "--hostname", help="Where the router sends NMEA (the Built-in Computer: 10.15.20.2).")] = None,
    port: Annotated[OptInt, typer.Option("--port", parser=port_number(),
                                                  help="UDP port the router sends NMEA to, 1-65535 (5000).")] = None,
    sentences: Annotated[OptStr, typer.Option(
        "--sentences", help="Forward exactly these sentence ids (e.g. GPGGA,GPRMC), the others not.")] = None,
) -> int:
    """Set the router's NMEA forwarding; only what differs is sent (PUT, values as strings),
    then read back. Shows the change and asks first (--yes: without asking).

    \b
    Example:
      panther-ops gps router set -r panther-01 --enable --hostname 10.15.20.2 --port 5000 --yes
    """
    from panther_ops.core.gps.router.apply import apply_router
    from panther_ops.core.gps.router.plan import RouterRequest, check_address, parse_sentences
    from panther_ops.core.gps.router.read import read_and_plan_router
    from panther_ops.errors import UsageError

    req = RouterRequest(enabled=enable, hostname=hostname, port=port, sentences=parse_sentences(sentences))
    if req.empty:
        raise UsageError("nothing to set", hint="--enable/--disable, --hostname, --port or --sentences")
    check_address(address)
    creds = credentials()
    return fleet.change("gps router set", lambda c: read_and_plan_router(c, address, creds, req),
                        applier=apply_router(address, creds, req), verb="Change the router of")
