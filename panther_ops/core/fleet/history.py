"""`config history` and `config rollback`: the backups every change leaves on the robot.

Each change writes ``~/.panther-ops/backups/<id>/`` before touching anything: the files as
they were (``files/N``), a ``manifest.json`` (command, summary, per-file diff and hashes)
and, once the attempt ended, a ``status`` line (``applied`` or ``rolled-back: why``).
A rollback restores one backup through the same pipeline, so it is itself backed up.
"""

from __future__ import annotations

import json
from typing import Any

from panther_ops.core.fleet.pipeline import BACKUP_ROOT
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import RemoteStateError, TransportError, UsageError
from panther_ops.transport import scripts_backup
from panther_ops.transport.base import Command


def list_history(ctx: RobotContext) -> list[dict[str, Any]]:
    """Every backup on the robot, oldest first (ids sort by time)."""
    res = ctx.transport.run(Command.sh(scripts_backup.LIST, BACKUP_ROOT))
    if not res.ok:
        raise TransportError(ctx.robot.name, f"cannot list backups: {res.stderr.strip()}")
    entries: list[dict[str, Any]] = []
    for record in res.stdout.split("@@@\n"):
        if not record.strip():
            continue
        manifest, _, status = record.partition("@@status\n")
        try:
            doc = json.loads(manifest)
        except ValueError:
            continue
        doc["status"] = status.strip() or "interrupted (no status recorded)"
        entries.append(doc)
    entries.sort(key=lambda d: str(d.get("id", "")))
    return entries


def plan_rollback(ctx: RobotContext, to: str | None) -> RobotPlan:
    """Restore the files of backup ``to`` (default: the newest) as they were before that change."""
    from panther_ops.core.fleet.confine import backup_entry_ok, backup_ref

    backup_ref(to)
    entries = [e for e in list_history(ctx) if backup_entry_ok(e.get("id"), e.get("files", []))]
    if not entries:
        raise RemoteStateError("no backups on this robot: nothing to roll back to")
    if to is None:
        entry = entries[-1]
    else:
        hits = [e for e in entries if str(e.get("id", "")).startswith(to)]
        if len(hits) != 1:
            known = ", ".join(str(e.get("id")) for e in entries[-5:])
            raise UsageError(f"backup {to!r} {'is ambiguous' if hits else 'not found'} on {ctx.robot.name}",
                             hint=f"newest backups: {known} (panther-ops config history)")
        entry = hits[0]
    bdir = f"{BACKUP_ROOT}/{entry['id']}"
    edits: list[FileEdit] = []
    for f in entry.get("files", []):
        path = str(f["path"])
        try:
            now: bytes | None = ctx.transport.read_file(path)
        except FileNotFoundError:
            now = None
        if f.get("backup"):
            res = ctx.transport.run(Command.sh(scripts_backup.READ_BACKUP, bdir, str(f["backup"])))
            if not res.ok:
                raise RemoteStateError(f"backup {entry['id']} is incomplete: {f['backup']} missing")
            old: bytes | None = res.raw_stdout
        else:
            old = None
        if now != old:
            edits.append(FileEdit(path, now, old))
    services = tuple(entry.get("recreate", ()))
    plan = RobotPlan(ctx.robot.name, f"restore backup {entry['id']} (before: {entry.get('command') or '?'})",
                     edits, services, str(entry.get("compose_file", "~/compose.yaml")),
                     [Verify(s) for s in services],
                     noop=f"already as before {entry['id']}")
    plan.data["backup_restored"] = entry["id"]
    return plan
