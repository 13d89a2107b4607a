"""`panther-ops gps ...`: NMEA from the RUTX11's GNSS (listen), the nmea-gps service (enable/disable)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Optional

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.gps_router import Address, router_app
from panther_ops.cli.gps_router import credentials as _credentials
from panther_ops.cli.options import (
    GATED,
    READ,
    TARGETS,
    Json,
    OptFloat,
    OptInt,
    port_number,
    real_number,
    shared,
    whole_number,
)

if TYPE_CHECKING:
    from panther_ops.core.gps.nmea import Fix
    from panther_ops.core.gps.status import StatusOptions

app = typer.Typer(
    help="GPS (ANT02 on the RUTX11): the NMEA driver on robots, the router's forwarding, fix status, NMEA decoding.",
    no_args_is_help=True,
)
app.add_typer(router_app, name="router")


@app.command("listen")
def listen(
    udp: Annotated[str, typer.Option("--udp", help="HOST:PORT of this machine to receive NMEA on, e.g. 0.0.0.0:5000.")],
    count: Annotated[OptInt, typer.Option("--count", "-n", parser=whole_number(1),
                                                         help="Stop after N fixes (GGA sentences).")] = None,
    timeout: Annotated[OptFloat, typer.Option("--timeout", parser=real_number(0.1),
                                              help="Stop after SECONDS (default: none; Ctrl-C stops).")] = None,
    json_out: Json = False,
) -> int:
    """Decode NMEA arriving at a UDP address of this machine (an operator on the robot's
    network, the router forwarding to this machine): one line per fix (GGA) as it arrives.

    With --json, one document at the end holding the list of fixes (lat, lon, fix_quality,
    satellites, hdop, ...) and the counts of sentences by type, malformed ones and bad
    checksums. Exit 0 when --count fixes arrived (or Ctrl-C/--timeout without --count),
    3 when --timeout passed before --count fixes.

    \b
    Example:
      panther-ops gps listen --udp 0.0.0.0:5000 --count 3 --json
    """
    from panther_ops.cli.views.gps import fix_line, print_listened
    from panther_ops.core.gps.listen import listen as run_listen

    def show(fix: Fix) -> None:
        typer.echo(fix_line(fix))

    result = run_listen(udp, count=count, timeout_s=timeout, on_fix=None if json_out else show)
    short = count is not None and len(result.fixes) < count
    code = 3 if short and result.timed_out else 0
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "command": "gps listen", "address": result.address, "exit_code": code,
                   "fixes": [f.to_json() for f in result.fixes], "counts": result.decoder.stats.to_json()})
    else:
        print_listened(result, count, short=bool(code))
    return code


Port = Annotated[int, typer.Option("--port", parser=port_number(),
                                   help="UDP port the router forwards NMEA to, 1-65535 (default 5000).")]
Ip = Annotated[str, typer.Option("--ip", help="Built-in Computer address the driver listens on (default 10.15.20.2).")]
Namespace = Annotated[
    Optional[str],  # noqa: UP045
    typer.Option("--namespace", help="ROS namespace of the fix topic (default: the robot's, else panther)."),
]
Container = Annotated[
    bool, typer.Option("--container", help="Run the nmea-gps service also on 2.1.1+ (instead of launch_nmea_gps).")
]


@app.command("enable")
@shared(*GATED)
def enable(
    fleet: Fleet,
    port: Port = 5000,
    ip: Ip = "10.15.20.2",
    namespace: Namespace = None,
    container: Container = False,
    router: Annotated[
        bool, typer.Option("--router", help="Also set the router's NMEA forwarding to --ip:--port (same plan).")
    ] = False,
    address: Annotated[
        str, typer.Option("--address", help="The router's address on the robot's LAN (with --router).")
    ] = "10.15.20.1",
) -> int:
    """Run the NMEA GPS driver (ANT02 via the router's NMEA forwarding) on each robot, the way
    its stack does it:

    \b
      panther_ros 2.0.x-2.1.0: the manual's nmea-gps service added to ~/compose.yaml
        (husarion/nmea-gps:humble-2.0.1-20240617, network_mode host, restart always,
        ros2 launch /husarion_utils/nmea_navsat.launch.py robot_namespace:=<ns>);
        only that service is recreated and checked;
      panther_ros 2.1.1+ / husarion_ugv 2.2: launch_nmea_gps:=True on the driver; a port
        or ip other than 5000 / 10.15.20.2 also writes the NMEA parameters file
        (2.1.1: ~/config/panther_localization/config/nmea_navsat_params.yaml, mounted,
        params_file; 2.2: ~/config/husarion_ugv_localization/config/nmea_navsat.yaml,
        nmea_params_path).

    Plan, diff, confirm, backup, atomic write, recreate, verify, roll back: like config set.
    A robot already set up reports ok. The fix topic: /<ns>/gps/fix. With --router the
    router's forwarding (GNSS and forwarding on, --ip:--port, udp) is part of the same plan,
    applied after the driver (credentials as for `gps router`). Then `gps status` confirms
    the fix from the robot's fix topic.

    \b
    Examples:
      panther-ops gps enable --all --dry-run
      panther-ops gps enable -r panther-01 --yes
      panther-ops gps enable -r panther-01 --router --yes
    """
    from panther_ops.core.gps.plan import GpsOptions
    from panther_ops.core.gps.read import read_and_plan_enable
    from panther_ops.core.gps.router.plan import check_address

    check_address(address)  # refused even without --router: a bad value is never silently ignored
    opts = GpsOptions(port=port, ip=ip, namespace=namespace, container=container)
    if router:
        from panther_ops.core.gps.combined import plan_enable_with_router

        creds = _credentials()
        return fleet.change("gps enable", lambda c: plan_enable_with_router(c, opts, address, creds))
    return fleet.change("gps enable", lambda c: read_and_plan_enable(c, opts))


@app.command("disable")
@shared(*GATED)
def disable(fleet: Fleet) -> int:
    """Take back what `gps enable` adds: the nmea-gps service (its container stopped and
    removed), or launch_nmea_gps, params_file (2.2: nmea_params_path) and the parameters file
    panther-ops wrote.
    After an enable, compose.yaml is restored byte for byte.

    \b
    Example:
      panther-ops gps disable -r panther-01 --yes
    """
    from panther_ops.core.gps.read import read_and_plan_disable

    return fleet.change("gps disable", read_and_plan_disable)


NmeaPort = Annotated[int, typer.Option("--port", parser=port_number(), help="The robot's NMEA port, 1-65535 (5000).")]


def _status_options(port: int, window: float, router: bool, address: str) -> StatusOptions:
    """`gps status` and `gps watch`: their options checked, then (--router) the router's
    credentials asked for: bad input is refused before anyone is asked for a password."""
    from panther_ops.core.gps.router.plan import check_address
    from panther_ops.core.gps.status import StatusOptions

    check_address(address)
    StatusOptions(port=port, window_s=window)
    creds = _credentials() if router else None
    return StatusOptions(port=port, window_s=window, router=address if router else None, credentials=creds)


@app.command("status")
@shared(*READ)
def status(
    fleet: Fleet,
    port: NmeaPort = 5000,
    window: Annotated[float, typer.Option("--window", parser=real_number(0.5, 60),
                                          help="Seconds to listen, 0.5-60 (3).")] = 3.0,
    router: Annotated[
        bool, typer.Option("--router", help="Also read the router's forwarding (credentials as for gps router).")
    ] = False,
    address: Address = "10.15.20.1",
) -> int:
    """Per robot: is NMEA arriving at its UDP port (listened to on the robot for --window
    seconds, decoded here with pynmea2: sentences per second, fix quality, satellites, HDOP,
    position, age), and a verdict: fix, data but no fix, router not forwarding, forwarding to
    wrong host/port (with --router), no data, or port busy. Once the NMEA driver of
    compose.yaml holds the port (after gps enable), the robot's own fix topic decides
    (/<ns>/gps/fix echoed once in the driver container, --window + 5 s): fix with its
    position, data but no fix (status -1), or no fix message; where gpsd holds it, gpsd's
    view. `ok` only with a fix; `failed` (exit 3) otherwise. Demo robots answer with a
    recorded NMEA file.

    \b
    Examples:
      panther-ops gps status --all
      panther-ops gps status -r panther-01 --router --json
    """
    from panther_ops.cli.views.gps import print_status
    from panther_ops.core.gps.status import status_task

    opts = _status_options(port, window, router, address)
    return fleet.run("gps status", status_task(opts), print_status, read_only=True)


@app.command("watch")
@shared(*TARGETS, "json_out")
def watch(
    fleet: Fleet,
    port: NmeaPort = 5000,
    window: Annotated[float, typer.Option("--window", parser=real_number(0.5, 60),
                                          help="Seconds per refresh, 0.5-60 (2).")] = 2.0,
    count: Annotated[OptInt, typer.Option("--count", "-n", parser=whole_number(1),
                                          help="Stop after N refreshes (needed with --json).")] = None,
    router: Annotated[bool, typer.Option("--router", help="Also read the router's forwarding each time.")] = False,
    address: Address = "10.15.20.1",
) -> int:
    """`gps status` again and again over the same connections: a live table on a terminal
    (one table per refresh when piped), until Ctrl-C or --count refreshes. With --json (and
    --count) one document: every refresh's robots.

    \b
    Example:
      panther-ops gps watch -r panther-01 --router
    """
    import time

    from panther_ops.cli.progress import FleetProgress, progress_wanted
    from panther_ops.cli.render import emit_json
    from panther_ops.cli.views.gps import watch_display
    from panther_ops.core.fleet.interrupt import FleetInterrupted, Interruption
    from panther_ops.core.fleet.runner import Connections, RunOptions, run_fleet
    from panther_ops.core.gps.status import status_task
    from panther_ops.errors import ExitCode, UsageError
    from panther_ops.results import RobotResult

    if fleet.json_out and count is None:  # every input checked before the first refresh
        raise UsageError("gps watch --json needs --count N (one JSON document at the end)")
    opts = _status_options(port, window, router, address)
    inv, chosen = fleet.targets(read_only=True)
    rounds: list[dict[str, Any]] = []
    code = 0
    names = [r.name for r in chosen]
    progress = FleetProgress(names, enabled=False)
    last: list[RobotResult] = []
    try:
        with watch_display(fleet.json_out) as show, Connections(inv) as conns:
            started = time.monotonic()
            while count is None or len(rounds) < count:
                if rounds:  # a refresh every --window seconds at most (demo robots answer at once)
                    time.sleep(max(0.0, window - (time.monotonic() - started)))
                started, stamp = time.monotonic(), time.time()  # a round is stamped when it starts
                progress = FleetProgress(names, enabled=progress_wanted(fleet.json_out))  # this round's phases
                result = run_fleet("gps watch", inv, chosen, status_task(opts), RunOptions(forks=inv.forks), progress,
                                   conns)
                code, last = int(result.exit_code), list(result.results)
                rounds.append({"time": round(stamp, 3), **result.to_json()})
                show(result, f"panther-ops gps watch ({time.strftime('%H:%M:%S')}, refresh {len(rounds)})")
    except (FleetInterrupted, KeyboardInterrupt) as exc:  # Ctrl-C: in a round, or between two
        where = exc.where if isinstance(exc, FleetInterrupted) else Interruption(finished=last)
        progress.recap(where)  # each robot as the last refresh left it, on a terminal
        if not fleet.json_out:
            raise FleetInterrupted("gps watch", where) from None
        code = int(ExitCode.INTERRUPTED)
    if fleet.json_out:
        emit_json({"schema": 1, "command": "gps watch", "exit_code": code, "rounds": rounds})
    return code
