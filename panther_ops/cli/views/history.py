"""Human view of `config history`."""

from __future__ import annotations

from panther_ops.cli.render import esc, new_table, print_summary, print_warnings, result_cell, show
from panther_ops.cli.tables import Column, FitTable
from panther_ops.results import FleetResult, Outcome


def history_table(fleet: FleetResult) -> FitTable:
    """One row per backup; the backup id (what ``rollback --to`` takes) is never broken."""
    table = new_table("panther-ops config history", (
        Column(fleet.subject, "name"), Column("backup id", "id"), Column("created", "id", drop=2),
        Column("command", drop=1), Column("changed", drop=3), Column("ended")))
    for r in fleet.results:
        if r.outcome is not Outcome.OK:
            table.add_row(esc(r.robot), "", "", "", "", result_cell(r), note=esc(r.message))
            continue
        entries = r.data.get("history", [])
        if not entries:
            table.add_row(esc(r.robot), "-", "", "", "no backups yet", "")
        for i, e in enumerate(entries):
            files = ", ".join(str(f.get("path")) for f in e.get("files", []))
            status = str(e.get("status", ""))
            colour = "green" if status.startswith("applied") else ("magenta" if "rolled" in status else "yellow")
            table.add_row(esc(r.robot) if i == 0 else "", esc(e.get("id")), esc(_when(str(e.get("created", "")))),
                          esc(e.get("command", "")), esc(f"{e.get('summary', '')} ({files})"),
                          f"[{colour}]{esc(status)}[/]")
    return table


def _when(created: str) -> str:
    """``2025-01-02T10:00:01.671+00:00`` as ``2025-01-02 10:00:01 UTC`` (other zones as written)."""
    if len(created) >= 19 and created[10] == "T" and created.endswith("+00:00"):
        return f"{created[:10]} {created[11:19]} UTC"
    return created


def print_history(fleet: FleetResult) -> None:
    show(history_table(fleet))
    print_warnings(fleet)
    print_summary(fleet)
