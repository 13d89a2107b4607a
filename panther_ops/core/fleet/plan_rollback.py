"""The planner of `config rollback`: a pure function of the robot's backups as listed
(fact ``history``), the saved files it restores (fact ``backup``, ``<id>/<name>``) and the
files as they are now; the reads are `history.py`'s."""

from __future__ import annotations

from panther_ops.core.fleet.confine import backup_entry_ok, backup_ref
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.errors import RemoteStateError, UsageError

HISTORY = "history"
"""Fact: every backup's manifest on the robot, oldest first (`history.list_history`)."""
BACKUP = "backup"
"""Fact: a saved file of a backup, by ``<id>/<name in the backup>``."""


def plan_rollback(reads: Reads, to: str | None) -> RobotPlan:
    """Restore the files of backup ``to`` (default: the newest) as they were before that change."""
    backup_ref(to)
    entries = [e for e in reads.fact(HISTORY) if backup_entry_ok(e.get("id"), e.get("files", []))]
    if not entries:
        raise RemoteStateError("no backups on this robot: nothing to roll back to")
    if to is None:
        entry = entries[-1]
    else:
        hits = [e for e in entries if str(e.get("id", "")).startswith(to)]
        if len(hits) != 1:
            known = ", ".join(str(e.get("id")) for e in entries[-5:])
            raise UsageError(f"backup {to!r} {'is ambiguous' if hits else 'not found'} on {reads.robot}",
                             hint=f"newest backups: {known} (panther-ops config history)")
        entry = hits[0]
    edits: list[FileEdit] = []
    for f in entry.get("files", []):
        path = str(f["path"])
        now = reads.file(path)
        old: bytes | None = reads.fact(BACKUP, f"{entry['id']}/{f['backup']}") if f.get("backup") else None
        if now != old:
            edits.append(FileEdit(path, now, old))
    services = tuple(entry.get("recreate", ()))
    plan = RobotPlan(reads.robot, f"restore backup {entry['id']} (before: {entry.get('command') or '?'})",
                     edits, services, str(entry.get("compose_file", "~/compose.yaml")),
                     [Verify(s) for s in services],
                     noop=f"already as before {entry['id']}")
    plan.data["backup_restored"] = entry["id"]
    return plan
