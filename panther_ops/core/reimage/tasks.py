"""The per-robot tasks of `reimage plan` and `reimage backup` (run by the fleet runner)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from panther_ops.core.fleet.runner import RobotContext, Task
from panther_ops.core.reimage.archive import write_archive
from panther_ops.core.reimage.backup import Carried, collect
from panther_ops.core.reimage.device import human_size
from panther_ops.results import Outcome, RobotResult


def _summary(c: Carried) -> str:
    secrets = sum(f.secret for f in c.files)
    n = len(c.files)
    text = f"{n} file{'' if n == 1 else 's'}, {human_size(c.total_bytes)} ({secrets} secret)"
    if c.missing:
        home = c.identity.get("home") or ""
        short = ["~" + m[len(home):] if home and m.startswith(home + "/") else m for m in c.missing]
        text += f"; not on the robot: {', '.join(short)}"
    return text


def _data(c: Carried) -> dict[str, Any]:
    return {"robot": c.identity, "files": [f.to_json() for f in c.files], "missing": c.missing,
            "unreadable": c.unreadable, "desired": c.desired}


def plan_task(ctx: RobotContext) -> RobotResult:
    """What a backup of this robot would carry."""
    c = collect(ctx)
    return RobotResult(ctx.robot.name, Outcome.OK, _summary(c), data=_data(c),
                       warnings=[f"unreadable: {u}" for u in c.unreadable])


def backup_task(directory: Path) -> Task:
    """Read the robot and write its archive into ``directory``."""

    def task(ctx: RobotContext) -> RobotResult:
        c = collect(ctx)
        path = write_archive(c, directory, ctx.robot.name)
        return RobotResult(ctx.robot.name, Outcome.OK, f"{path}: {_summary(c)}",
                           data={"archive": str(path), **_data(c)}, warnings=[f"unreadable: {u}" for u in c.unreadable])

    return task
