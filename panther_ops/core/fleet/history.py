"""`config history` and `config rollback`: the backups every change leaves on the robot.

Each change writes ``~/.panther-ops/backups/<id>/`` before touching anything: the files as
they were (``files/N``), a ``manifest.json`` (command, summary, per-file diff and hashes)
and, once the attempt ended, a ``status`` line (``applied`` or ``rolled-back: why``).
A rollback restores one backup through the same pipeline, so it is itself backed up.

A local file (``shutdown hosts add|remove FILE``) keeps its backups the same way in its own
directory (the local target's home, ``<dir>/.panther-ops/backups/``): ``only`` narrows the
history and the rollback to the backups of that one file, which is all such a rollback
writes (see :func:`confine.backup_of_file`); it recreates nothing.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from panther_ops.core.fleet.confine import backup_entry_ok, backup_of_file, backup_ref
from panther_ops.core.fleet.pipeline import BACKUP_ROOT
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import RemoteStateError, TransportError, UsageError
from panther_ops.transport import scripts_backup
from panther_ops.transport.base import Command


def list_history(ctx: RobotContext, only: str | None = None) -> list[dict[str, Any]]:
    """Every backup on the robot, oldest first; ``only``: the backups of
    that one (absolute) file and of nothing else."""
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
        if only is None or backup_of_file(doc, only):
            entries.append(doc)
    # ids sort by time to the second; within one, the time of creation (to the millisecond) orders them
    entries.sort(key=lambda d: (str(d.get("id", ""))[:16], str(d.get("created", "")), str(d.get("id", ""))))
    return entries


def plan_rollback(ctx: RobotContext, to: str | None, *, only: str | None = None,
                  edit: Callable[[str, bytes | None, bytes | None], FileEdit] = FileEdit) -> RobotPlan:
    """Restore the files of backup ``to`` (default: the newest) as they were before that change.

    ``only``: a local file's backups (see the module's text); ``edit`` makes each file's edit
    from its path, its content now and the one to restore (e.g. one whose diff masks secrets).
    """
    backup_ref(to)
    entries = [e for e in list_history(ctx) if backup_entry_ok(e.get("id"), e.get("files", []))]
    others = entries
    if only is not None:
        entries = [e for e in entries if backup_of_file(e, only)]
    if to is not None:
        entry = _pick(ctx, entries, others, to, only)
    elif entries:
        entry = entries[-1]
    elif only is not None:
        raise UsageError(f"no backups of {ctx.robot.name}: nothing to roll back to",
                         hint="`shutdown hosts add|remove FILE` keep the file's backups beside it, in "
                         ".panther-ops/backups/")
    else:
        raise RemoteStateError("no backups on this robot: nothing to roll back to")
    bdir = f"{BACKUP_ROOT}/{entry['id']}"
    edits: list[FileEdit] = []
    for f in entry.get("files", []):
        path = str(f["path"]) if only is None else only
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
            edits.append(edit(path, now, old))
    services = tuple(entry.get("recreate", ())) if only is None else ()
    compose = str(entry.get("compose_file", "~/compose.yaml")) if only is None else "~/compose.yaml"
    plan = RobotPlan(ctx.robot.name, f"restore backup {entry['id']} (before: {entry.get('command') or '?'})",
                     edits, services, compose,
                     [Verify(s) for s in services],
                     noop=f"already as before {entry['id']}")
    plan.data["backup_restored"] = entry["id"]
    return plan


def _pick(ctx: RobotContext, entries: list[dict[str, Any]], others: list[dict[str, Any]], to: str,
          only: str | None) -> dict[str, Any]:
    """The one backup whose id starts with ``to`` (UsageError naming the ids there are)."""
    hits = [e for e in entries if str(e.get("id", "")).startswith(to)]
    if len(hits) == 1:
        return hits[0]
    known = ", ".join(str(e.get("id")) for e in entries[-5:]) or "none"
    elsewhere = [e for e in others if e not in entries and str(e.get("id", "")).startswith(to)]
    if not hits and elsewhere:
        files = ", ".join(str(f.get("path")) for f in elsewhere[0].get("files", []))
        raise UsageError(f"backup {elsewhere[0]['id']} is not a backup of {ctx.robot.name} (it holds {files})",
                         hint=f"backups of {ctx.robot.name}: {known} (panther-ops config history --file "
                         f"{ctx.robot.name})")
    listed = f"config history --file {ctx.robot.name}" if only is not None else "config history"
    raise UsageError(f"backup {to!r} {'is ambiguous' if hits else 'not found'} "
                     f"{'for' if only is not None else 'on'} {ctx.robot.name}",
                     hint=f"newest backups: {known} (panther-ops {listed})")
