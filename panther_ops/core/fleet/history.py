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
from typing import Any

from panther_ops.core.fleet import plan_rollback as planner
from panther_ops.core.fleet.confine import backup_of_file
from panther_ops.core.fleet.pipeline import BACKUP_ROOT
from panther_ops.core.fleet.plan import MaskedFileEdit, RobotPlan
from panther_ops.core.fleet.reading import FactReader, read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import RemoteStateError, TransportError
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


def read_backup(ctx: RobotContext, key: str) -> bytes:
    """A file of a backup (``key``: ``<id>/<name in the backup>``) as it was saved."""
    backup_id, _, name = key.partition("/")
    res = ctx.transport.run(Command.sh(scripts_backup.READ_BACKUP, f"{BACKUP_ROOT}/{backup_id}", name))
    if not res.ok:
        raise RemoteStateError(f"backup {backup_id} is incomplete: {name} missing")
    return res.raw_stdout


ROLLBACK_FACTS: dict[str, FactReader] = {planner.HISTORY: lambda c, _key: list_history(c),
                                         planner.BACKUP: read_backup}
"""How the facts the rollback planner asks for are read."""


def read_and_plan_rollback(ctx: RobotContext, to: str | None, *, only: str | None = None,
                           edit: planner.MakeEdit = MaskedFileEdit) -> RobotPlan:
    """Restore the files of backup ``to`` (default: the newest): read the backups the planner
    (`plan_rollback.py`, pure; ``only`` and ``edit`` are its) asks for, and the files as they are now."""
    return read_and_plan(ctx, lambda reads: planner.plan_rollback(reads, to, only=only, edit=edit), ROLLBACK_FACTS)
