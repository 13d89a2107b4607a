"""Live per-robot progress of fleet work, on stderr, and the recap after it.

Shown only when stderr is a terminal and neither ``--json`` nor ``--quiet`` was given:
each robot that is being worked on with its phase (connect, plan, write, recreate,
verify, roll back) and how long it has been in it, and a count of the robots done. When
the work is over the live view goes away and a recap (one line per robot: its result
and the time each phase took, like Ansible's) stays on stderr. In a pipe nothing is
printed: stdout carries only the table (or the JSON), stderr only the messages.

Interrupted (Ctrl-C: the core raises ``FleetInterrupted`` at once), the live view goes
and the partial recap stays: each robot finished, planned, interrupted in its phase, or
not started; the error funnel then says the same in words (cli/app.py).

The core reports phases through its ``Progress`` callback (``core/runner.py``): this
object is that callback.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Iterator
from typing import Any

from panther_ops.cli.output import console, is_terminal, quiet
from panther_ops.cli.render import counted, outcome_counts, outcome_word, result_cell
from panther_ops.core.fleet.interrupt import FleetInterrupted, Interruption
from panther_ops.results import RobotResult

PHASE_STYLE = {"connect": "cyan", "plan": "blue", "write": "yellow", "recreate": "magenta", "verify": "green",
               "roll back": "red"}


def progress_wanted(json_out: bool) -> bool:
    return not json_out and not quiet() and is_terminal(stderr=True)


class FleetProgress:
    """The ``Progress`` of a fleet command: phases as they come, results as they end."""

    def __init__(self, robots: list[str], *, enabled: bool, printing: bool = True) -> None:
        self.robots = list(robots)
        self.enabled = enabled
        self.printing = printing
        """The run's end prints with rich (not ``--json``)."""
        self._lock = threading.Lock()
        self._current: dict[str, tuple[str, float]] = {}
        self._times: dict[str, dict[str, float]] = {r: {} for r in self.robots}
        self._done: dict[str, RobotResult] = {}
        self._live: Any = None

    # -- the core's callbacks (worker threads) -----------------------------------------------
    def phase(self, robot: str, name: str) -> None:
        now = time.monotonic()
        with self._lock:
            self._close_phase(robot, now)
            self._current[robot] = (name, now)
            self._done.pop(robot, None)  # at work again (the plan's result came first)
        self._refresh()

    def __call__(self, result: RobotResult) -> None:
        with self._lock:
            self._close_phase(result.robot, time.monotonic())
            self._current.pop(result.robot, None)
            self._done[result.robot] = result
        self._refresh()

    def _close_phase(self, robot: str, now: float) -> None:
        if robot in self._current:
            name, since = self._current[robot]
            times = self._times.setdefault(robot, {})
            times[name] = times.get(name, 0.0) + now - since  # a phase met again (write: staged, then committed)

    # -- the view -------------------------------------------------------------------------------
    @contextlib.contextmanager
    def live(self) -> Iterator[None]:
        """Show the live view while the block runs (nothing when not enabled)."""
        if not self.enabled:
            if self.printing:  # made now, as the run's end needs it: a Ctrl-C's report then imports
                console(stderr=True)  # nothing while the workers hold the CPU, and answers at once
            yield
            return
        from rich.live import Live

        out = console(stderr=True)
        try:
            with Live(self._render(out.size.height), console=out, transient=True, refresh_per_second=8,
                      get_renderable=lambda: self._render(out.size.height)) as view:
                self._live = view
                try:
                    yield
                finally:
                    self._live = None
        except FleetInterrupted as exc:  # the live view is gone: what was done stays
            self.recap(exc.where)
            raise

    def _refresh(self) -> None:
        view = self._live
        if view is not None:
            view.refresh()

    def _render(self, height: int) -> Any:
        from rich.table import Table
        from rich.text import Text

        now = time.monotonic()
        with self._lock:
            current = [(r, *self._current[r]) for r in self.robots if r in self._current]
            done = dict(self._done)
        grid = Table.grid(padding=(0, 2))
        grid.add_column(no_wrap=True)
        grid.add_column(no_wrap=True)
        grid.add_column(no_wrap=True, justify="right")
        room = max(1, height - 3)
        for robot, name, since in current[:room]:
            grid.add_row(robot, Text(name, style=PHASE_STYLE.get(name, "")), f"{now - since:4.1f} s")
        if len(current) > room:
            grid.add_row(f"... {len(current) - room} more", "", "")
        summary = Text(f"{len(done)}/{counted(len(self.robots), 'robot')} done")
        for n, word, style in outcome_counts(done.values()):  # a dry run's change: "would change"
            summary.append(f"  {n} {word}", style=style)
        from rich.console import Group

        return Group(grid, summary)

    def recap(self, interrupted: Interruption | None = None) -> None:
        """One line per robot: its result and the time of each phase (on a terminal only).
        ``interrupted``: the partial recap of an interrupted run, every robot where it was."""
        if not self.enabled or not (self._done or interrupted):
            return
        from rich.markup import escape

        with self._lock:
            now = time.monotonic()
            for robot in list(self._current):  # the phases cut short, up to now
                self._close_phase(robot, now)
                self._current[robot] = (self._current[robot][0], now)
            times = {r: dict(t) for r, t in self._times.items()}
            done = dict(self._done)
        cells = {r: (result_cell(res), outcome_word(res)) for r, res in done.items()}
        if interrupted is not None:
            cells = {r.robot: (result_cell(r), outcome_word(r)) for r in interrupted.finished}
            cells.update({r: ("[cyan]planned[/]", "planned") for r in interrupted.planned})
            cells.update({r: ("[yellow]interrupted[/]", "interrupted") for r in interrupted.running})
            cells.update({r: ("[dim]not started[/]", "not started") for r in interrupted.not_started})
        err = console(stderr=True)
        err.print("[bold]recap[/]" + (" (interrupted)" if interrupted is not None else ""))
        width = max(len(r) for r in self.robots)
        for robot in self.robots:
            if robot not in cells:
                continue
            cell, word = cells[robot]
            phases = "  ".join(f"{name} {seconds:.1f} s" for name, seconds in times.get(robot, {}).items())
            err.print(f"{escape(robot):<{width}}  {cell}{' ' * max(0, 12 - len(word))} {phases}".rstrip(),
                      soft_wrap=True)
