"""What a planner plans from: the files and facts read from one robot, as data.

Planners are pure functions of a :class:`Reads` (plus what the user asked): they never
touch a transport. A planner that needs a file or fact that was not read yet raises
:class:`NotRead` naming it; the reader (`reading.py`) reads it over the robot's one
connection and plans again. So the reads are exactly those the planner asks for, in the
order it asks for them, and a golden test hands a planner a complete `Reads` and gets the
plan with no robot at all.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class Need:
    """One read a planner asks for: ``kind`` ``file`` (``key``: its robot path) or a fact's name."""

    kind: str
    key: str


class NotRead(Exception):
    """The planner needs this read before it can plan (the reader reads it, then plans again)."""

    def __init__(self, need: Need) -> None:
        super().__init__(f"not read: {need.kind} {need.key}")
        self.need = need


@dataclass
class Reads:
    """What was read from one robot (besides its compose.yaml, which planners take as such)."""

    robot: str
    """The robot's inventory name."""
    stack: str = "auto"
    """The inventory's ``stack:`` setting."""
    namespace: str | None = None
    """The inventory's ``namespace:`` for the robot."""
    files: dict[str, bytes | None] = field(default_factory=dict)
    """File content by robot path (None: the file does not exist)."""
    facts: dict[Need, Any] = field(default_factory=dict)
    """Other facts (an image's presence, running containers), by what was asked."""

    def file(self, path: str) -> bytes | None:
        """The file's content as read (None: it does not exist)."""
        if path not in self.files:
            raise NotRead(Need("file", path))
        return self.files[path]

    def fact(self, kind: str, key: str = "") -> Any:
        """A fact of this ``kind`` about ``key`` as read."""
        need = Need(kind, key)
        if need not in self.facts:
            raise NotRead(need)
        return self.facts[need]
