"""Human view of `describe`: one robot, one part a line (or a few), label on the left.

Laid out at the console's width: labels never wrap, values wrap at words under their own
column; a backup id (what ``rollback --to`` takes) and the URL are words and are never broken.
"""

from __future__ import annotations

from typing import Any

from panther_ops.cli.render import _console, esc, human_bytes, print_summary, print_warnings, result_cell
from panther_ops.cli.views.history import _when
from panther_ops.cli.views.status import COLOUR
from panther_ops.core.fleet.facts import signed_seconds
from panther_ops.results import FleetResult, Outcome, RobotResult

LABEL = 12
"""Columns of the labels (the longest, ``last change``, and a space)."""
GAP = 2


def print_describe(fleet: FleetResult) -> None:
    console = _console()
    for r in fleet.results:
        for label, value, hang in describe_rows(r):
            _print_row(console, label, value, hang)
    print_warnings(fleet)
    print_summary(fleet)


def _print_row(console: Any, label: str, value: str, hang: int) -> None:
    """``label`` in bold, then ``value`` (markup; its lines apart by newlines) wrapped at words
    to the console's width; a line that wraps goes on ``hang`` columns further in."""
    from rich.text import Text

    indent = LABEL + GAP
    width = max(console.width - indent, 20 + hang)
    head = Text(label + " " * max(GAP, indent - len(label)), style="bold")  # a long name: the value after it
    for part in value.split("\n"):
        text = Text.from_markup(part)
        first = text.wrap(console, max(console.width - len(head), 20), overflow="fold")[0]
        rest = text[len(first.plain):]
        rest = rest[len(rest.plain) - len(rest.plain.lstrip(" ")):]
        lines = [first, *rest.wrap(console, width - hang, overflow="fold")]
        for i, line in enumerate(lines):
            if i and not line.plain.strip():
                continue
            line.rstrip()
            console.print(Text.assemble(head, " " * (hang if i else 0), line), crop=False, soft_wrap=True)
            head = Text(" " * indent)


def describe_rows(r: RobotResult) -> list[tuple[str, str, int]]:
    """(label, value in markup, hang) of each line of the description: the robot's name and
    result, then each part; a value's own lines are separated by newlines."""
    rows: list[tuple[str, str, int]] = [(r.robot, f"{result_cell(r)}  {esc(r.message)}", 0)]
    if r.outcome is Outcome.UNREACHABLE or "status" not in r.data:
        return rows
    d, s = r.data, r.data["status"]
    model = " ".join(str(x) for x in (s.get("robot_model"), s.get("robot_version")) if x) or "-"
    disk = human_bytes(s.get("disk_free_bytes"))
    if s.get("disk_total_bytes"):
        disk += f" free of {human_bytes(s['disk_total_bytes'])}"
    offset = s.get("clock_offset_s")
    last, backup = _history(r.robot, d.get("history") or {})
    rows += [
        ("reached", esc(d.get("where", "-")), 0),
        ("hostname", esc(" · ".join(str(x) for x in (s.get("hostname"), s.get("os")) if x) or "-"), 0),
        ("model", esc(model + (f" / serial {s['robot_serial']}" if s.get("robot_serial") else "")), 0),
        ("OS build", esc(s.get("system_build_version") or "-"), 0),
        ("stack", esc(f"{s.get('stack') or '?'} {s.get('stack_version') or ''}".strip()), 0),
        ("image", esc(s.get("driver_image") or "-"), 0),
        ("containers", _containers(s), 2),
        ("disk", disk, 0),
        ("clock", "-" if offset is None else f"{signed_seconds(offset)} from this machine", 0),
        ("WebUI", _webui(s.get("webui")), 0),
        ("GPS", _gps(d.get("gps") or {}), 0),
        ("E-stop", _estop(d.get("estop") or {}), 0),
        ("last change", last, 0),
        ("backup", backup, 0),
        ("doctor", *_doctor(d.get("doctor") or {})),
    ]
    return rows


def _failed(part: dict[str, Any]) -> str | None:
    """A part that could not be read: why (and the hint), in red; None when it was read."""
    if "error" not in part:
        return None
    return f"[red]not read[/]: {esc(part['error'])}" + (f" (hint: {esc(part['hint'])})" if part.get("hint") else "")


def _containers(s: dict[str, Any]) -> str:
    ctrs = s.get("containers")
    if ctrs is None:
        return f"[dim]not read: {esc(s.get('docker_skipped') or '-')}[/]"
    if not ctrs:
        return "none"
    lines = []
    for c in ctrs:
        colour = "green" if c["state"] == "running" else "yellow"
        driver = " (driver)" if s.get("driver_service") in (c.get("service"), c["name"]) else ""
        restarts = f", {c['restart_count']} restarts" if c.get("restart_count") else ""
        lines.append(f"{esc(c['name'])}{driver}: [{colour}]{esc(c['state'])}[/]{restarts} · {esc(c['image'])}")
    return "\n".join(lines)


def _webui(w: dict[str, Any] | None) -> str:
    if not w:
        return "- (no user_computer: in the inventory)"
    if "error" in w:
        return f"[red]not read[/]: {esc(w['error'])}"
    if not w.get("installed"):
        return "not installed (panther-ops webui install)"
    state = "[green]running[/]" if w.get("running") else "[yellow]stopped[/]"
    return f"{state} {esc(w.get('url') or '')}".rstrip()


def _gps(part: dict[str, Any]) -> str:
    failed = _failed(part)
    if failed:
        return failed
    g = part.get("data", {})
    verdict = str(g.get("verdict", part.get("message", "?")))
    colour = "green" if verdict == "fix" else "yellow"
    recorded = " (recorded: demo robot)" if g.get("recorded") else ""
    driver = (g.get("driver") or {}).get("mode")
    tail = "; no NMEA driver in compose.yaml" if driver == "off" else ""
    return f"[{colour}]{esc(verdict)}[/]: {esc(g.get('detail', ''))}{recorded}{esc(tail)}"


def _estop(part: dict[str, Any]) -> str:
    failed = _failed(part)
    if failed:
        return failed
    e = part.get("data", {})
    shown = {True: "[red]triggered[/]", False: "[green]released[/]"}.get(e.get("e_stop"), "[yellow]unknown[/]")
    pubs = e.get("cmd_vel_publishers")
    who = ", ".join(pubs) if pubs else ("none" if pubs == [] else "-")
    recorded = " (recorded: demo robot)" if e.get("recorded") else ""
    return f"{shown}; cmd_vel publishers: {esc(who)}{recorded}"


def _history(robot: str, part: dict[str, Any]) -> tuple[str, str]:
    """(last change, backup): the newest backup's change and how it ended; its id and how to go back."""
    failed = _failed(part)
    if failed:
        return failed, failed
    h = part.get("data", {})
    last = h.get("last")
    if not last:
        return "none recorded", "no backups yet"
    status = str(last.get("status", ""))
    colour = "green" if status.startswith("applied") else ("magenta" if "rolled" in status else "yellow")
    change = (f"{esc(last.get('command', '?'))} ({esc(last.get('summary', ''))}), [{colour}]{esc(status)}[/], "
              f"{esc(_when(str(last.get('created', ''))))}")
    backup = (f"{esc(last['id'])} ({h.get('backups')} in all); undo the change: "
              f"panther-ops config rollback -r {esc(robot)} --to {esc(last['id'])}")
    return change, backup


def _doctor(part: dict[str, Any]) -> tuple[str, int]:
    """One line a finding: state, check, detail, then its fix on a line of its own; and the
    hang of a line that wraps (under the details)."""
    failed = _failed(part)
    if failed:
        return failed, 0
    findings = part.get("data", {}).get("findings", [])
    width = max((len(f["check"]) for f in findings), default=0)
    lines = []
    for f in findings:
        state = f"[{COLOUR[f['state']]}]{f['state']:<4}[/]"
        lines.append(f"{state} {esc(f['check'].ljust(width))}  {esc(f['detail'])}")
        if f.get("fix"):
            lines.append(f"{' ' * (width + 7)}[dim]fix:[/] {esc(f['fix'])}")
    return "\n".join(lines) or "no findings", width + 7
