"""The readers of `reimage restore`: the backup archive (checked before any robot is
contacted) and the robot's files as a backup reads them, then the pure planner (`plan.py`)."""

from __future__ import annotations

import posixpath

from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.reimage.archive import read_archive
from panther_ops.core.reimage.backup import collect
from panther_ops.core.reimage.plan import Backup, BackupFile, plan_restore


def load_backup(path: str) -> Backup:
    """The archive's manifest and files, every member checked against the manifest
    (``archive.read_archive``); UsageError naming what is wrong (nothing is done)."""
    contents = read_archive(path)
    files = [BackupFile(e.path, e.mode, contents.data[e.path], e.secret) for e in contents.entries if e.kind == "file"]
    links = [e.path for e in contents.entries if e.kind == "symlink"]
    return Backup(path, contents.manifest, files, links)


def read_and_plan_restore(ctx: RobotContext, backup: Backup) -> RobotPlan:
    """Read the robot's files as a backup would (those the backup holds), then plan writing the
    backup's back where they differ."""
    now = collect(ctx, tuple(f.path for f in backup.files))
    home = str(now.identity.get("home") or ctx.transport.home())
    compose = posixpath.join(home, ctx.robot.compose_file[2:]) if ctx.robot.compose_file.startswith("~/") \
        else ctx.robot.compose_file
    current = {f.path: (f.data, f.mode) for f in now.files}
    return plan_restore(backup, ctx.robot.name, home, compose, now.identity, current)
