"""Human views of `status` and `doctor`."""

from __future__ import annotations

from panther_ops.cli.render import (
    _console,
    esc,
    human_bytes,
    print_summary,
    print_warnings,
    result_cell,
)
from panther_ops.results import FleetResult, Outcome


def print_status(fleet: FleetResult) -> None:
    from rich.table import Table

    table = Table(title="panther-ops status")
    for col in ("robot", "result", "hostname", "model / serial", "OS build", "stack", "driver",
                "containers", "disk free", "clock", "webui"):
        table.add_column(col, overflow="fold")
    for r in fleet.results:
        d = r.data
        if r.outcome is not Outcome.OK:
            table.add_row(r.robot, result_cell(r), esc(r.message), *[""] * 8)
            continue
        ctrs = d.get("containers")
        if ctrs is None:
            ctr_text = f"[dim]skipped ({esc(d.get('docker_skipped'))})[/]"
        else:
            ctr_text = "\n".join(
                f"{c['name']} {c['state']}" + (f" ({c['restart_count']} restarts)" if c["restart_count"] else "")
                for c in ctrs
            ) or "none"
        model = " ".join(str(x) for x in (d.get("robot_model"), d.get("robot_version")) if x) or "-"
        if d.get("robot_serial"):
            model += f" / {d['robot_serial']}"
        offset = d.get("clock_offset_s")
        clock = "-" if offset is None else f"{offset:+.2f} s"
        if offset is not None and abs(offset) > 1.0:
            clock = f"[red]{clock}[/]"
        stack = f"{d.get('stack') or '?'} {d.get('stack_version') or ''}".strip()
        table.add_row(
            r.robot, result_cell(r), d.get("hostname") or "-", model,
            d.get("system_build_version") or "-", stack, d.get("driver_state") or "-", ctr_text,
            human_bytes(d.get("disk_free_bytes")), clock, _webui(d.get("webui")),
        )
    _console().print(table)
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


def print_doctor(fleet: FleetResult) -> None:
    from rich.table import Table

    table = Table(title="panther-ops doctor")
    for col in ("robot", "check", "state", "detail", "fix"):
        table.add_column(col, overflow="fold")
    colour = {"ok": "green", "warn": "yellow", "fail": "red"}
    for r in fleet.results:
        findings = r.data.get("findings")
        if not findings:
            table.add_row(r.robot, "-", result_cell(r), esc(r.message), "")
            continue
        for i, f in enumerate(findings):
            table.add_row(r.robot if i == 0 else "", f["check"], f"[{colour[f['state']]}]{f['state']}[/]",
                          esc(f["detail"]), esc(f.get("fix") or ""))
    _console().print(table)
    for note in fleet.data.get("fleet_findings", []):
        _console(stderr=True).print(f"[{colour[note['state']]}]{note['state']}[/] fleet {note['check']}: "
                                    f"{note['detail']}" + (f" — fix: {note['fix']}" if note.get("fix") else ""))
    print_warnings(fleet)
    print_summary(fleet)
