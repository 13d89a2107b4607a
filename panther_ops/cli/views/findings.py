"""Human and JSON output of file checks (`bt validate`, `lights validate`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from panther_ops.cli.render import _console, counted, emit_json, esc
from panther_ops.errors import ExitCode


def _place(where: str, path: str) -> str:
    """Where in the file a finding is; nothing when it is the file itself (the verdict line
    names the file)."""
    file = Path(path)
    return "" if where in (path, file.name, str(file.resolve())) else where


def report_findings(path: str, findings: list[Any], *, json_out: bool, what: str) -> int:
    """Print the findings; exit 2 when any is an error (the file would be refused)."""
    errors = [f for f in findings if str(getattr(f.severity, "value", f.severity)) == "error"]
    code = ExitCode.USAGE if errors else ExitCode.OK
    if json_out:
        emit_json({
            "schema": 1,
            "file": path,
            "valid": not errors,
            "exit_code": int(code),
            "findings": [
                {"severity": str(getattr(f.severity, "value", f.severity)), "code": f.code, "message": f.message,
                 "where": f.where}
                for f in findings
            ],
        })
        return int(code)
    out = _console()
    for f in findings:
        sev = str(getattr(f.severity, "value", f.severity))
        colour = "red" if sev == "error" else "yellow"
        place = _place(str(f.where or ""), path)
        where = f" [dim]{esc(place)}[/]" if place else ""
        out.print(f"[{colour}]{sev}[/] {esc(f.message)} [dim]({f.code})[/]{where}")
    verdict = f"{path}: {what} " + ("refused" if errors else "valid") + (
        f" ({counted(len(errors), 'error')}, {counted(len(findings) - len(errors), 'warning')})" if findings else "")
    _console(stderr=True).print(esc(verdict))
    return int(code)
