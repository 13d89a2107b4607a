"""`panther-ops gps ...`: NMEA from the RUTX11's GNSS (listen), the nmea-gps service (enable/disable)."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Annotated, Optional

import typer

from panther_ops.cli.options import Json

if TYPE_CHECKING:
    from panther_ops.core.gps.nmea import Fix

app = typer.Typer(
    help="GPS (ANT02 / the RUTX11's GNSS): decode NMEA, enable or disable the NMEA driver on robots.",
    no_args_is_help=True,
)


def _fix_line(fix: Fix) -> str:
    where = "no position" if fix.lat is None else f"{fix.lat:.8f} {fix.lon:.8f}"
    extra = [f"sats {fix.satellites}" if fix.satellites is not None else "sats -",
             f"hdop {fix.hdop}" if fix.hdop is not None else "hdop -"]
    if fix.altitude_m is not None:
        extra.append(f"alt {fix.altitude_m} m")
    return f"{fix.time or '-'}  {fix.talker}  {where}  quality {fix.fix_quality}  " + "  ".join(extra)


@app.command("listen")
def listen(
    udp: Annotated[str, typer.Option("--udp", help="HOST:PORT of this machine to receive NMEA on, e.g. 0.0.0.0:5000.")],
    count: Annotated[
        Optional[int],  # noqa: UP045
        typer.Option("--count", "-n", min=1, help="Stop after N fixes (GGA sentences)."),
    ] = None,
    timeout: Annotated[
        Optional[float],  # noqa: UP045
        typer.Option("--timeout", min=0.1, help="Stop after SECONDS (default: none; Ctrl-C stops)."),
    ] = None,
    json_out: Json = False,
) -> int:
    """Decode NMEA arriving at a UDP address of this machine (an operator on the robot's
    network, the router forwarding to this machine): one line per fix (GGA) as it arrives.

    With --json, one document at the end holding the list of fixes (lat, lon, fix_quality,
    satellites, hdop, ...) and the counts of sentences by type, malformed ones and bad
    checksums. Exit 0 when --count fixes arrived (or Ctrl-C/--timeout without --count),
    3 when --timeout passed before --count fixes.

    Example: panther-ops gps listen --udp 0.0.0.0:5000 --count 3 --json
    """
    from panther_ops.core.gps.listen import listen as run_listen

    def show(fix: Fix) -> None:
        sys.stdout.write(_fix_line(fix) + "\n")
        sys.stdout.flush()

    result = run_listen(udp, count=count, timeout_s=timeout, on_fix=None if json_out else show)
    short = count is not None and len(result.fixes) < count
    code = 3 if short and result.timed_out else 0
    stats = result.decoder.stats
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "command": "gps listen", "address": result.address, "exit_code": code,
                   "fixes": [f.to_json() for f in result.fixes], "counts": stats.to_json()})
    else:
        from panther_ops.cli.render import _console

        types = ", ".join(f"{k} {v}" for k, v in sorted(stats.by_type.items())) or "none"
        _console(stderr=True).print(
            f"{len(result.fixes)} fixes; {stats.sentences} sentences ({types}); malformed {stats.malformed}, "
            f"bad checksum {stats.bad_checksum}, unknown type {stats.unknown_type}"
            + (f"; --timeout passed before {count} fixes" if code else ""), highlight=False, markup=False)
    return code
