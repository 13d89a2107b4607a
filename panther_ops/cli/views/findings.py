"""Human and JSON output of file checks (`bt validate`, `lights validate`)."""

from __future__ import annotations

from typing import Any

from panther_ops.cli.render import _console, emit_json, esc
from panther_ops.errors import ExitCode


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
        where = f" [dim]{esc(f.where)}[/]" if f.where else ""
        out.print(f"[{colour}]{sev}[/] {esc(f.message)} [dim]({f.code})[/]{where}")
    verdict = f"{path}: {what} " + ("refused" if errors else "valid") + (
        f" ({len(errors)} errors, {len(findings) - len(errors)} warnings)" if findings else "")
    _console(stderr=True).print(esc(verdict))
    return int(code)
