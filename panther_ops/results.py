"""Result vocabulary shared by every command: one outcome per robot, then the fleet's.

Every command reports each targeted robot with exactly one :class:`Outcome`, a one-line
message (also when nothing changed: the reason), optional diffs and command-specific data.
The fleet result turns those into the documented exit code.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from panther_ops.errors import ExitCode

JSON_SCHEMA_VERSION = 1


class Outcome(str, Enum):
    """What happened on one robot."""

    OK = "ok"
    """Reached; nothing to change (the message says why)."""
    CHANGED = "changed"
    """Reached and changed as planned (and verified)."""
    FAILED = "failed"
    """Reached, but the step failed; nothing was rolled back or nothing needed to be."""
    ROLLED_BACK = "rolled-back"
    """The change failed verification and the previous state was restored."""
    UNREACHABLE = "unreachable"
    """Could not connect (network, host key, authentication)."""
    SKIPPED = "skipped"
    """Deliberately not done (the message says why)."""

    @property
    def is_failure(self) -> bool:
        return self in (Outcome.FAILED, Outcome.ROLLED_BACK, Outcome.UNREACHABLE)


@dataclass(frozen=True)
class Diff:
    """A file change on a robot: the exact unified diff of one file."""

    path: str
    unified: str

    def to_json(self) -> dict[str, str]:
        return {"path": self.path, "unified": self.unified}


@dataclass
class RobotResult:
    """The outcome of one command on one robot."""

    robot: str
    outcome: Outcome
    message: str
    diffs: list[Diff] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    duration_s: float = 0.0

    def to_json(self) -> dict[str, Any]:
        return {
            "robot": self.robot,
            "outcome": self.outcome.value,
            "message": self.message,
            "diffs": [d.to_json() for d in self.diffs],
            "warnings": list(self.warnings),
            "duration_s": round(self.duration_s, 3),
            "data": self.data,
        }


@dataclass
class FleetResult:
    """Every targeted robot's result, in inventory order, plus fleet-wide notes."""

    command: str
    results: list[RobotResult] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)
    duration_s: float = 0.0
    subject: str = "robot"
    """What each result is of, as the tables and the summary name it: ``robot``, or ``file`` for a
    local file given to a command (``shutdown hosts add FILE``, ``config history --file``)."""
    drift_exit: bool = False
    """A comparison asked for its answer in the exit code (``config diff --exit-code``): a robot
    that would change makes it DRIFT (6) when every robot was read."""

    def add(self, result: RobotResult) -> None:
        self.results.append(result)

    def by_outcome(self, *outcomes: Outcome) -> list[RobotResult]:
        return [r for r in self.results if r.outcome in outcomes]

    @property
    def exit_code(self) -> ExitCode:
        code = exit_code_for(r.outcome for r in self.results)
        if self.drift_exit and code is ExitCode.OK and self.by_outcome(Outcome.CHANGED):
            return ExitCode.DRIFT
        return code

    def to_json(self) -> dict[str, Any]:
        counts: dict[str, int] = {o.value: 0 for o in Outcome}
        for r in self.results:
            counts[r.outcome.value] += 1
        return {
            "schema": JSON_SCHEMA_VERSION,
            "command": self.command,
            "exit_code": int(self.exit_code),
            "summary": counts,
            "duration_s": round(self.duration_s, 3),
            "notes": list(self.notes),
            "robots": [r.to_json() for r in self.results],
            **({"data": self.data} if self.data else {}),
        }


def exit_code_for(outcomes: Iterable[Outcome]) -> ExitCode:
    """The documented exit code for a set of robot outcomes.

    0 when every robot is ok/changed/skipped (or none was targeted); 4 when every robot was
    unreachable; 3 when at least one failed, was rolled back or unreachable and others were
    reached.
    """
    seen = list(outcomes)
    if not seen:
        return ExitCode.OK
    if all(o is Outcome.UNREACHABLE for o in seen):
        return ExitCode.UNREACHABLE
    if any(o.is_failure for o in seen):
        return ExitCode.PARTIAL
    return ExitCode.OK
