"""Human views of `status` and `doctor`."""

from __future__ import annotations

from panther_ops.cli.render import (
    _console,
    esc,
    human_bytes,
    new_table,
    print_summary,
    print_warnings,
    result_cell,
    show,
)
from panther_ops.cli.tables import Column, FitTable
from panther_ops.core.fleet.facts import signed_seconds
from panther_ops.results import FleetResult, Outcome

STATUS_COLUMNS = (
    Column("robot", "name"), Column("result"), Column("hostname", "name", drop=3),
    Column("model / serial", drop=5), Column("OS build", drop=4), Column("stack"), Column("driver"),
    Column("containers", drop=1), Column("disk free", drop=2), Column("clock"), Column("webui"),
)
"""Hidden first when the terminal is narrow: containers, disk free, hostname, OS build, model."""


def status_table(fleet: FleetResult) -> FitTable:
    table = new_table("panther-ops status", STATUS_COLUMNS)
    for r in fleet.results:
        d = r.data
        if r.outcome is not Outcome.OK:  # why, on its own line under the row
            table.add_row(esc(r.robot), result_cell(r), *[""] * 9, note=esc(r.message))
            continue
        ctrs = d.get("containers")
        if ctrs is None:
            ctr_text = f"[dim]skipped ({esc(d.get('docker_skipped'))})[/]"
        else:
            ctr_text = "\n".join(
                esc(f"{c['name']} {c['state']}" + (f" ({c['restart_count']} restarts)" if c["restart_count"] else ""))
                for c in ctrs
            ) or "none"
        model = " ".join(str(x) for x in (d.get("robot_model"), d.get("robot_version")) if x) or "-"
        if d.get("robot_serial"):
            model += f" / {d['robot_serial']}"
        offset = d.get("clock_offset_s")
        clock = "-" if offset is None else signed_seconds(offset)
        if offset is not None and abs(offset) > 1.0:
            clock = f"[red]{clock}[/]"
        stack = f"{d.get('stack') or '?'} {d.get('stack_version') or ''}".strip()
        table.add_row(
            esc(r.robot), result_cell(r), esc(d.get("hostname") or "-"), esc(model),
            esc(d.get("system_build_version") or "-"), esc(stack), esc(d.get("driver_state") or "-"), ctr_text,
            human_bytes(d.get("disk_free_bytes")), clock, _webui(d.get("webui")),
        )
    return table


def print_status(fleet: FleetResult) -> None:
    show(status_table(fleet))
    print_warnings(fleet)
    print_summary(fleet)


def _webui(w: dict[str, object] | None) -> str:
    """The WebUI column: running :PORT, stopped, not installed, an error, or - (no User Computer)."""
    if not w:
        return "-"
    if "error" in w:
        return "[red]?[/]"
    if not w.get("installed"):
        return "not installed"
    return f"[green]running :{w.get('port')}[/]" if w.get("running") else "stopped"


def doctor_table(fleet: FleetResult) -> FitTable:
    table = new_table("panther-ops doctor", (Column("robot", "name"), Column("check"), Column("state"),
                                             Column("detail"), Column("fix")))
    for r in fleet.results:
        findings = r.data.get("findings")
        if not findings:
            table.add_row(esc(r.robot), "-", result_cell(r), "", "", note=esc(r.message))
            continue
        for i, f in enumerate(findings):
            table.add_row(esc(r.robot) if i == 0 else "", esc(f["check"]), f"[{COLOUR[f['state']]}]{f['state']}[/]",
                          esc(f["detail"]), esc(f.get("fix") or ""))
    return table


COLOUR = {"ok": "green", "warn": "yellow", "fail": "red"}


def print_doctor(fleet: FleetResult) -> None:
    show(doctor_table(fleet))
    for note in fleet.data.get("fleet_findings", []):
        _console(stderr=True).print(f"[{COLOUR[note['state']]}]{note['state']}[/] fleet {note['check']}: "
                                    f"{note['detail']}" + (f" — fix: {note['fix']}" if note.get("fix") else ""))
    print_warnings(fleet)
    print_summary(fleet)
