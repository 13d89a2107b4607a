"""What a command will do to one robot: file edits with exact diffs, services to recreate,
what must hold afterwards. Planners build these from what they read; the pipeline
(`pipeline.py`) carries them out."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.yaml.diff import unified_diff
from panther_ops.results import Diff


@dataclass(frozen=True)
class FileEdit:
    """One file to write on the robot."""

    path: str
    before: bytes | None
    """What the plan read (None: the file does not exist yet)."""
    after: bytes | None
    """What to write (None: remove the file)."""
    mode: int | None = None

    def diff(self) -> Diff:
        return _diff(self.path, self.before, self.after)


@functools.lru_cache(maxsize=256)
def _diff(path: str, before: bytes | None, after: bytes | None) -> Diff:
    """The edit's diff; robots with the same file and change share one (a Diff is immutable)."""
    old = (before or b"").decode(errors="replace")
    return Diff(path, unified_diff(old, (after or b"").decode(errors="replace"), path))


@dataclass(frozen=True)
class Verify:
    """What must hold after the services are recreated."""

    service: str
    cmd_contains: tuple[str, ...] = ()
    cmd_lacks: tuple[str, ...] = ()


@dataclass
class RobotPlan:
    """What a command will do to one robot."""

    robot: str
    summary: str
    edits: list[FileEdit] = field(default_factory=list)
    recreate: tuple[str, ...] = ()
    compose_file: str = "~/compose.yaml"
    verify: list[Verify] = field(default_factory=list)
    noop: str | None = None
    """Why nothing needs to change (then ``edits`` is empty)."""
    warnings: list[str] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)
    home: str | None = None
    """The robot user's home, when the plan read it (``~/`` paths resolve against it)."""

    @property
    def diffs(self) -> list[Diff]:
        return [e.diff() for e in self.edits]
