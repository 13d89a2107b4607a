"""Human view of `manager status`."""

from __future__ import annotations

from panther_ops.cli.render import esc, new_table, print_table, result_cell
from panther_ops.cli.tables import Column
from panther_ops.results import FleetResult


def print_status(fleet: FleetResult) -> None:
    from panther_ops.core.containers.times import human_duration

    table = new_table("panther-ops manager status", (
        Column("robot", "name"), Column("result"), Column("version"), Column("mode"),
        Column("state"), Column("uptime"), Column("restarts", drop=1),
        Column("disable_manager", drop=2), Column("message", "message")))
    for r in fleet.results:
        d = r.data
        uptime = human_duration(d["uptime_s"]) if d.get("uptime_s") is not None else "-"
        table.add_row(esc(r.robot), result_cell(r), esc(d.get("version") or "-"),
                      esc(d.get("mode") or "-"), esc(d.get("state") or "-"), uptime,
                      str(d.get("restart_count", "-")), esc(d.get("disable_manager") or "not set"), esc(r.message))
    print_table(table, fleet)
