"""Human views of the gps commands: a fix line (`gps listen`), the status table (`gps
status`, each refresh of `gps watch`), the router's forwarding (`gps router show`)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from panther_ops.cli.output import console
from panther_ops.cli.render import esc, new_table, print_table, result_cell
from panther_ops.cli.tables import Column

if TYPE_CHECKING:
    from panther_ops.core.gps.listen import ListenResult
    from panther_ops.core.gps.nmea import Fix
    from panther_ops.results import FleetResult


def fix_line(fix: Fix) -> str:
    where = "no position" if fix.lat is None else f"{fix.lat:.8f} {fix.lon:.8f}"
    extra = [f"sats {fix.satellites}" if fix.satellites is not None else "sats -",
             f"hdop {fix.hdop}" if fix.hdop is not None else "hdop -"]
    if fix.altitude_m is not None:
        extra.append(f"alt {fix.altitude_m} m")
    return f"{fix.time or '-'}  {fix.talker}  {where}  quality {fix.fix_quality}  " + "  ".join(extra)


def print_listened(result: ListenResult, count: int | None, short: bool) -> None:
    """What `gps listen` received, counted, on stderr."""
    stats = result.decoder.stats
    types = ", ".join(f"{k} {v}" for k, v in sorted(stats.by_type.items())) or "none"
    console(stderr=True).print(
        f"{len(result.fixes)} fixes; {stats.sentences} sentences ({types}); malformed {stats.malformed}, "
        f"bad checksum {stats.bad_checksum}, unknown type {stats.unknown_type}"
        + (f"; --timeout passed before {count} fixes" if short else ""), highlight=False, markup=False)


def print_status(fleet: FleetResult) -> None:
    print_table(status_table(fleet, "panther-ops gps status"), fleet)


def status_table(fleet: FleetResult, title: str) -> Any:
    table = new_table(title, (
        Column("robot", "name"), Column("result"), Column("verdict"), Column("sentences/s", drop=3),
        Column("position", "id"), Column("sats", drop=2), Column("hdop", drop=4),
        Column("age", drop=1), Column("driver", drop=5), Column("detail", "message")))
    for r in fleet.results:
        d = r.data
        fix = d.get("fix") or {}
        pos = f"{fix['lat']:.7f} {fix['lon']:.7f}" if fix.get("lat") is not None else "-"
        rate = d.get("sentences_per_s")
        age = d.get("age_s")
        table.add_row(
            esc(r.robot), result_cell(r), esc(d.get("verdict", "")),
            "-" if rate is None else f"{rate:g}" + (" (recorded)" if d.get("recorded") else ""), pos,
            str(fix.get("satellites", "-")), str(fix.get("hdop", "-")), "-" if age is None else f"{age:.1f} s",
            esc((d.get("driver") or {}).get("mode", "")), esc(d.get("detail", r.message)),
        )
    return table


def print_router(fleet: FleetResult) -> None:
    table = new_table("panther-ops gps router show", (
        Column("robot", "name"), Column("result"), Column("gps"), Column("forwarding"),
        Column("to", "name"), Column("sentences"), Column("message", "message")))
    for r in fleet.results:
        d = r.data
        if "forwarding" not in d:
            table.add_row(esc(r.robot), result_cell(r), "", "", "", "", esc(r.message))
            continue
        table.add_row(esc(r.robot), result_cell(r), "on" if d["gps_enabled"] else "off",
                      "on" if d["forwarding"] else "off", esc(f"{d['hostname']}:{d['port']}/{d['proto']}"),
                      esc(",".join(d["sentences"])), "")
    print_table(table, fleet)


@contextmanager
def watch_display(json_out: bool) -> Iterator[Callable[[FleetResult, str], None]]:
    """How `gps watch` shows each refresh: one live table on a terminal, a table per refresh
    in a pipe, nothing with --json (one document at the end)."""
    import sys

    live = None
    if not json_out and sys.stdout.isatty():
        from rich.live import Live

        live = Live(console=console(), auto_refresh=False)
        live.start()

    def show(fleet: FleetResult, title: str) -> None:
        if live is not None:
            live.update(status_table(fleet, title), refresh=True)
        elif not json_out:
            console().print(status_table(fleet, title), crop=False)

    try:
        yield show
    finally:
        if live is not None:
            live.stop()
