"""What a command will do to one robot: file edits with exact diffs, services to recreate,
what must hold afterwards. Planners build these from what they read; the pipeline
(`pipeline.py`) carries them out."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from typing import Any, ClassVar

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


_SECRET_LINE = re.compile(r"^(\s*(?:-\s+)?secret\s*:\s*)(?![{\s]|$)([^#\n]*?)(\s*(?:#.*)?)$", re.MULTILINE)


def mask_secrets(text: str) -> str:
    """`secret: value` lines with the value replaced by ****, for diffs and logs."""
    return _SECRET_LINE.sub(lambda m: f"{m.group(1)}****{m.group(3)}", text)


@dataclass(frozen=True)
class MaskedFileEdit(FileEdit):
    """A FileEdit whose diff shows ``secret: ****`` (the file itself keeps the value: a
    shutdown hosts file's HMAC secret). When a value gives way to another, each is marked
    ``**** (old value)`` / ``**** (new value)``, so a changed secret still shows as a changed
    line (a rollback may change nothing else)."""

    def diff(self) -> Diff:
        plain = super().diff()
        before = (self.before or b"").decode(errors="replace")
        after = (self.after or b"").decode(errors="replace")
        old_values = {m.group(2) for m in _SECRET_LINE.finditer(before)}
        new_values = {m.group(2) for m in _SECRET_LINE.finditer(after)}
        replaced = bool(old_values - new_values) and bool(new_values - old_values)
        kept = old_values & new_values if replaced else old_values | new_values

        def mask(text: str, note: str) -> str:
            return _SECRET_LINE.sub(lambda m: f"{m.group(1)}****{'' if m.group(2) in kept else note}{m.group(3)}", text)

        old, new = mask(before, " (old value)"), mask(after, " (new value)")
        return Diff(plain.path, unified_diff(None if self.before is None else old,
                                             None if self.after is None else new, self.path))


@functools.lru_cache(maxsize=256)
def _diff(path: str, before: bytes | None, after: bytes | None) -> Diff:
    """The edit's diff; robots with the same file and change share one (a Diff is immutable)."""
    old = None if before is None else before.decode(errors="replace")
    return Diff(path, unified_diff(old, None if after is None else after.decode(errors="replace"), path))


@dataclass(frozen=True)
class Verify:
    """What must hold after the services are recreated."""

    service: str
    cmd_contains: tuple[str, ...] = ()
    cmd_lacks: tuple[str, ...] = ()


@dataclass(frozen=True)
class Step:
    """One order of a plan beyond its file edits (restart a container, PUT to the router, reset
    the E-stop, ...). A feature defines its step types (frozen dataclasses holding everything
    the order needs) in its ``plan.py`` and registers their executors in its ``apply.py``
    (`fleet.steps`); the pipeline carries them out. ``RobotPlan.data`` only shows a plan (the
    table, ``--json``): no executor reads it."""

    action: ClassVar[bool] = True
    """The step is the change itself (a plan holding one does something even without file
    edits, its summary starts with its verb: ``would reset the E-stop``); False: a step that
    only accompanies the file edits (a dropped service's container removed after the write)."""


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
    skipped: str | None = None
    """Why this robot is skipped (a demo robot where the change needs a real one): nothing to do,
    reported ``skipped`` (exit 0), as read-only siblings report it."""
    steps: list[Step] = field(default_factory=list)
    """What the plan orders beyond its file edits, carried out in order by their executors
    (each wraps the ones after it and, innermost, the pipeline's write of ``edits``)."""

    @property
    def action(self) -> bool:
        """The plan holds a step that is the change itself (see :attr:`Step.action`)."""
        return any(s.action for s in self.steps)

    @property
    def diffs(self) -> list[Diff]:
        return [e.diff() for e in self.edits]
