"""The planner of `config rollback`: a pure function of the robot's backups as listed
(fact ``history``), the saved files it restores (fact ``backup``, ``<id>/<name>``) and the
files as they are now; the reads are `history.py`'s.

``only``: a local file's backups (``config rollback --file FILE``, see `history.py`): the
history narrowed to that one file's, and the rollback writes that file and nothing else.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from panther_ops.core.fleet.confine import (
    SERVICE_NAME,
    backup_entry_ok,
    backup_of_file,
    backup_ref,
    compose_path_problem,
)
from panther_ops.core.fleet.plan import FileEdit, MaskedFileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.errors import RemoteStateError, UsageError

HISTORY = "history"
"""Fact: every backup's manifest on the robot, oldest first (`history.list_history`)."""
BACKUP = "backup"
"""Fact: a saved file of a backup, by ``<id>/<name in the backup>``."""

MakeEdit = Callable[[str, bytes | None, bytes | None], FileEdit]


def plan_rollback(reads: Reads, to: str | None, *, only: str | None = None,
                  edit: MakeEdit = MaskedFileEdit) -> RobotPlan:
    """Restore the files of backup ``to`` (default: the newest) as they were before that change.

    ``only``: a local file's backups (see the module's text); ``edit`` makes each file's edit
    from its path, its content now and the one to restore; by default one whose diff masks
    ``secret:`` values (a restored shutdown hosts file may hold the HMAC secret).
    """
    backup_ref(to)
    entries = [e for e in reads.fact(HISTORY) if backup_entry_ok(e.get("id"), e.get("files", []))]
    others = entries
    if only is not None:
        entries = [e for e in entries if backup_of_file(e, only)]
    if to is not None:
        entry = _pick(reads.robot, entries, others, to, only)
    elif entries:
        entry = entries[-1]
    elif only is not None:
        raise UsageError(f"no backups of {reads.robot}: nothing to roll back to",
                         hint="`shutdown hosts add|remove FILE` keep the file's backups beside it, in "
                         ".panther-ops/backups/")
    else:
        raise RemoteStateError("no backups on this robot: nothing to roll back to")
    edits: list[FileEdit] = []
    for f in entry.get("files", []):
        path = str(f["path"]) if only is None else only
        now = reads.file(path)
        old: bytes | None = reads.fact(BACKUP, f"{entry['id']}/{f['backup']}") if f.get("backup") else None
        if now != old:
            edits.append(edit(path, now, old))
    services = tuple(str(s) for s in entry.get("recreate", ())) if only is None else ()
    compose = str(entry.get("compose_file", "~/compose.yaml")) if only is None else "~/compose.yaml"
    bad = next((s for s in services if not SERVICE_NAME.match(s)), None)
    problem = compose_path_problem(compose) or ((f"service {bad!r} is not a compose service name", "") if bad else None)
    if problem is not None:  # the manifest was changed on the robot: nothing is recreated from it
        raise RemoteStateError(f"backup {entry['id']}: its manifest is damaged: {problem[0]}; refused, nothing "
                               "was changed")
    plan = RobotPlan(reads.robot, f"restore backup {entry['id']} (before: {entry.get('command') or '?'})",
                     edits, services, compose,
                     [Verify(s) for s in services],
                     noop=f"already as before {entry['id']}")
    plan.data["backup_restored"] = entry["id"]
    return plan


def _pick(robot: str, entries: list[dict[str, Any]], others: list[dict[str, Any]], to: str,
          only: str | None) -> dict[str, Any]:
    """The one backup whose id starts with ``to`` (UsageError naming the ids there are)."""
    hits = [e for e in entries if str(e.get("id", "")).startswith(to)]
    if len(hits) == 1:
        return hits[0]
    known = ", ".join(str(e.get("id")) for e in entries[-5:]) or "none"
    elsewhere = [e for e in others if e not in entries and str(e.get("id", "")).startswith(to)]
    if not hits and elsewhere:
        files = ", ".join(str(f.get("path")) for f in elsewhere[0].get("files", []))
        raise UsageError(f"backup {elsewhere[0]['id']} is not a backup of {robot} (it holds {files})",
                         hint=f"backups of {robot}: {known} (panther-ops config history --file {robot})")
    listed = f"config history --file {robot}" if only is not None else "config history"
    raise UsageError(f"backup {to!r} {'is ambiguous' if hits else 'not found'} "
                     f"{'for' if only is not None else 'on'} {robot}",
                     hint=f"newest backups: {known} (panther-ops {listed})")
