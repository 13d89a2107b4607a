"""What a fleet run says when the operator interrupts it (Ctrl-C).

The runner (``runner.py``) stops starting work at once and does not wait for the robots
it is working on: it raises :class:`FleetInterrupted`, which names every targeted robot
once: finished (with its result), planned (a change known, nothing written), being
written, cut short in another phase, or not started. A robot being written is safe to
leave: every file is staged beside its target and renamed into place (``scripts_apply``),
so each file holds either its old or its new content; a write that already had its
go-ahead completes on the robot, one that had not is dropped when the connection ends.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from panther_ops.errors import ExitCode, OpsError
from panther_ops.results import RobotResult

WRITING = ("write", "roll back")
"""The phases in which a robot's files are being replaced."""

ATOMIC = ("each file is staged beside its target and renamed into place: it holds either its old or its new "
          "content, never part of one")


@dataclass
class Interruption:
    """Where each targeted robot was when the run was interrupted."""

    finished: list[RobotResult] = field(default_factory=list)
    planned: list[str] = field(default_factory=list)
    """A change planned (and maybe staged), nothing written."""
    running: dict[str, str] = field(default_factory=dict)
    """Robot -> the phase it was in."""
    not_started: list[str] = field(default_factory=list)

    def lines(self) -> list[str]:
        out = ["interrupted (Ctrl-C): no new work was started"]
        if self.finished:
            out.append("  finished: " + ", ".join(f"{r.robot} {_word(r)}" for r in self.finished))
        if self.planned:
            out.append("  planned, nothing written: " + ", ".join(self.planned))
        writing = [r for r, p in self.running.items() if p in WRITING]
        if writing:
            out.append(f"  being written: {', '.join(writing)} ({ATOMIC})")
        cut = [f"{r} ({p})" for r, p in self.running.items() if p not in WRITING]
        if cut:
            out.append("  cut short: " + ", ".join(cut))
        if self.not_started:
            out.append("  not started: " + ", ".join(self.not_started))
        return out


def _word(r: RobotResult) -> str:
    return "would change" if r.data.get("dry_run") else r.outcome.value


class FleetInterrupted(OpsError):
    """The operator interrupted a fleet run: nothing more is started; exit code 130."""

    exit_code = ExitCode.INTERRUPTED

    def __init__(self, command: str, where: Interruption) -> None:
        super().__init__("\n".join(where.lines()))
        self.command = command
        self.where = where

    def regrouped(self, robots: Iterable[str], finished: Mapping[str, RobotResult],
                  planned: Iterable[str] = ()) -> FleetInterrupted:
        """The same interruption over a wider run (``robots``, in their order): ``finished`` (the
        caller's answers) first, then ``planned``, then this run's own results."""
        mine = {r.robot: r for r in self.where.finished}
        plans = set(planned) | set(self.where.planned)
        where = Interruption(running={r: self.where.running[r] for r in robots if r in self.where.running})
        for name in robots:
            if name in where.running:
                continue
            if name in finished:
                where.finished.append(finished[name])
            elif name in plans:
                where.planned.append(name)
            elif name in mine:
                where.finished.append(mine[name])
            else:
                where.not_started.append(name)
        return FleetInterrupted(self.command, where)
