"""Human view of `config history`."""

from __future__ import annotations

from panther_ops.cli.render import _console, esc, print_summary, print_warnings, result_cell
from panther_ops.results import FleetResult, Outcome


def print_history(fleet: FleetResult) -> None:
    from rich.table import Table

    table = Table(title="panther-ops config history")
    for col in (fleet.subject, "backup id", "created", "command", "changed", "ended"):
        table.add_column(col, overflow="fold")
    for r in fleet.results:
        if r.outcome is not Outcome.OK:
            table.add_row(r.robot, result_cell(r), esc(r.message), "", "", "")
            continue
        entries = r.data.get("history", [])
        if not entries:
            table.add_row(r.robot, "-", "", "no backups yet", "", "")
        for i, e in enumerate(entries):
            files = ", ".join(str(f.get("path")) for f in e.get("files", []))
            status = str(e.get("status", ""))
            colour = "green" if status.startswith("applied") else ("magenta" if "rolled" in status else "yellow")
            table.add_row(r.robot if i == 0 else "", str(e.get("id")), str(e.get("created", "")),
                          esc(e.get("command", "")), esc(f"{e.get('summary', '')} ({files})"),
                          f"[{colour}]{esc(status)}[/]")
    _console().print(table)
    print_warnings(fleet)
    print_summary(fleet)
