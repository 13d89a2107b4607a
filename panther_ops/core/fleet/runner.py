"""The fleet runner: bounded parallelism, canaries, a failure budget, one connection per robot.

A task is a function ``(RobotContext) -> RobotResult``. The runner opens the robot's
transport (one connection), hands it to the task, closes it, and turns every error into
the shared result vocabulary; one robot's failure never stops the others.

The robots are worked on in worker threads; the calling (main) thread only starts them and
collects their results, waiting a short time at once, so a Ctrl-C (KeyboardInterrupt, which
Python raises in the main thread) is acted on at once: nothing more is started, the workers
are not waited for (a robot hanging in connect may take its whole connect timeout), each
worker stops at its next phase, and :class:`~panther_ops.core.fleet.interrupt.FleetInterrupted`
says where every robot was (``interrupt.py``).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from panther_ops.core.fleet.interrupt import FleetInterrupted, Interruption
from panther_ops.core.fleet.inventory import DEFAULT_FORKS, Inventory, Robot
from panther_ops.errors import OpsError, UnreachableError
from panther_ops.results import FleetResult, Outcome, RobotResult
from panther_ops.transport.base import Transport

if TYPE_CHECKING:
    from panther_ops.transport.session import Session

log = logging.getLogger("panther_ops")


@dataclass
class RobotContext:
    """What a task gets: the robot, its open transport, and the inventory."""

    robot: Robot
    transport: Transport
    inventory: Inventory
    warnings: list[str] = field(default_factory=list)
    on_phase: Callable[[str], None] | None = None
    """Told each phase the task enters (see :meth:`phase`)."""
    session: Session | None = None
    """The robot's write session, made while its plan is made (``changes.plan_fleet`` under
    ``--yes``): it reads the compose file first, for the plan (`core/robot/read.py`)."""

    def phase(self, name: str) -> None:
        """Report the phase this robot's work has reached (one of :data:`PHASES`)."""
        if self.on_phase is not None:
            self.on_phase(name)


Task = Callable[[RobotContext], RobotResult]
Progress = Callable[[RobotResult], None]
"""Told each robot's result as it ends. A progress object that also has a method
``phase(robot, phase)`` is told each phase a robot enters (connect, plan, write,
recreate, verify, roll back), as it happens, from the robot's worker thread."""

PHASES = ("connect", "plan", "write", "recreate", "verify", "roll back")

WAIT_S = 0.1
"""How long the main thread waits for a result at a time (a Ctrl-C is acted on between waits
too, where the platform does not interrupt a wait)."""


def phase_reporter(progress: Progress | None, robot: str) -> Callable[[str], None] | None:
    """``progress.phase`` bound to ``robot``, when the progress object takes phases."""
    phase = getattr(progress, "phase", None)
    if phase is None:
        return None
    return lambda name: phase(robot, name)


@dataclass(frozen=True)
class RunOptions:
    forks: int = DEFAULT_FORKS
    canary: int = 0
    """Run this many robots first; if any of them fails, do not start the rest."""
    max_fail_pct: float | None = None
    """Stop starting robots once failures exceed this share (0-100) of the targeted robots."""


def open_transport(inventory: Inventory, robot: Robot) -> Transport:
    """The transport for a robot (not yet connected)."""
    if robot.transport == "local":
        from panther_ops.transport.local import LocalTransport

        assert robot.root is not None
        return LocalTransport(robot.name, robot.root, robot.user, robot.home)
    from panther_ops.transport.ssh import SshTransport

    return SshTransport(inventory.endpoint(robot))


class Connections:
    """One open transport per robot, kept across the phases of a command (plan, then apply).

    A robot that could not be reached is remembered and not tried again in a later phase.
    """

    def __init__(self, inventory: Inventory) -> None:
        self.inventory = inventory
        self._open: dict[str, Transport] = {}
        self._failed: dict[str, UnreachableError] = {}
        self._lock = threading.Lock()

    def get(self, robot: Robot) -> Transport:
        with self._lock:
            if robot.name in self._failed:
                raise self._failed[robot.name]
            existing = self._open.get(robot.name)
        if existing is not None:
            return existing
        transport = open_transport(self.inventory, robot)
        try:
            transport.connect()
        except UnreachableError as exc:
            with self._lock:
                self._failed[robot.name] = exc
            raise
        with self._lock:
            self._open[robot.name] = transport
        return transport

    def close(self) -> None:
        with self._lock:
            opened = list(self._open.values())
            self._open.clear()
        for t in opened:
            try:
                t.close()
            except Exception:  # closing must never hide a result
                log.debug("close failed on %s", t.name, exc_info=True)

    def __enter__(self) -> Connections:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, *exc: object) -> None:
        if exc_type is not None and issubclass(exc_type, (FleetInterrupted, KeyboardInterrupt)):
            # interrupted: the workers still use their connections and closing one mid-write
            # waits for the write; they are closed in the background (or end with the process)
            threading.Thread(target=self.close, name="close-connections", daemon=True).start()
            return
        self.close()


class Stopped(OpsError):
    """A robot's work reached its next phase after the run was interrupted: it goes no further."""


def run_one(connections: Connections, robot: Robot, task: Task,
            on_phase: Callable[[str], None] | None = None) -> RobotResult:
    """Run the task on the robot's (shared) connection; every error becomes a result."""
    start = time.monotonic()
    try:
        if on_phase is not None:
            on_phase("connect")
        ctx = RobotContext(robot, connections.get(robot), connections.inventory, on_phase=on_phase)
        result = task(ctx)
        result.warnings[:0] = ctx.warnings
    except UnreachableError as exc:
        result = RobotResult(robot.name, Outcome.UNREACHABLE, _strip(exc, robot.name))
        if exc.hint:
            result.data["hint"] = exc.hint
    except OpsError as exc:
        result = RobotResult(robot.name, Outcome.FAILED, _strip(exc, robot.name))
        if exc.hint:
            result.data["hint"] = exc.hint
    except Exception as exc:
        log.exception("internal error on %s", robot.name)
        result = RobotResult(robot.name, Outcome.FAILED, f"internal error: {exc!r} (a bug: see --debug)")
    result.duration_s = time.monotonic() - start
    return result


def _strip(exc: OpsError, robot: str) -> str:
    msg = exc.message
    return msg[len(robot) + 2 :] if msg.startswith(f"{robot}: ") else msg


class _Fleet:
    """One run: schedules robots ``forks`` at a time and records every result."""

    def __init__(self, connections: Connections, task: Task, opts: RunOptions, progress: Progress | None) -> None:
        self.connections = connections
        self.task = task
        self.opts = opts
        self.progress = progress
        self.results: dict[str, RobotResult] = {}
        self.lock = threading.Lock()
        self.stop_reason: str | None = None
        self.failures = 0
        self.running: dict[str, str] = {}
        """Robot -> the phase it is in, while a worker has it."""
        self.stop = threading.Event()

    def note(self, res: RobotResult) -> None:
        with self.lock:
            self.results[res.robot] = res
            self.running.pop(res.robot, None)
        if self.progress:
            self.progress(res)

    def on_phase(self, robot: str) -> Callable[[str], None]:
        """The phase callback of one robot's worker: recorded, passed on to the progress, and
        the point where an interrupted run's workers stop (a rollback under way goes on)."""
        forward = phase_reporter(self.progress, robot)

        def phase(name: str) -> None:
            if self.stop.is_set() and name != "roll back":
                raise Stopped(f"{robot}: interrupted: not continued")
            with self.lock:
                self.running[robot] = name
            if forward is not None:
                forward(name)

        return phase

    def interrupted(self, command: str, robots: list[Robot]) -> FleetInterrupted:
        """Stop the run's workers at their next phase; where each robot is now."""
        self.stop.set()
        with self.lock:
            where = Interruption(running={r.name: self.running[r.name] for r in robots if r.name in self.running})
            where.finished = [self.results[r.name] for r in robots
                              if r.name in self.results and r.name not in where.running]
        done = set(where.running) | {r.robot for r in where.finished}
        where.not_started = [r.name for r in robots if r.name not in done]
        return FleetInterrupted(command, where)

    def skip(self, robots: list[Robot]) -> None:
        for r in robots:
            self.note(RobotResult(r.name, Outcome.SKIPPED, f"not started: {self.stop_reason}"))

    def batch(self, todo: list[Robot], budget: int | None) -> None:
        """Run ``todo``, ``forks`` at a time. Interrupted (KeyboardInterrupt), the pool is shut
        down without waiting for its workers and the interrupt goes on to the caller."""
        queue = list(todo)
        pending: set[Future[RobotResult]] = set()
        pool = ThreadPoolExecutor(max_workers=max(1, min(self.opts.forks, len(todo))))
        try:
            while queue or pending:
                while queue and len(pending) < self.opts.forks and self.stop_reason is None:
                    robot = queue.pop(0)
                    pending.add(pool.submit(run_one, self.connections, robot, self.task, self.on_phase(robot.name)))
                if not pending:
                    break
                done, pending = wait(pending, timeout=WAIT_S, return_when=FIRST_COMPLETED)
                for fut in done:
                    res = fut.result()
                    self.note(res)
                    if res.outcome.is_failure:
                        self.failures += 1
                        if budget is not None and self.failures > budget and self.stop_reason is None:
                            self.stop_reason = f"max-fail reached ({self.failures} failed)"
        except BaseException:
            self.stop.set()
            pool.shutdown(wait=False, cancel_futures=True)
            raise
        pool.shutdown(wait=True)  # every worker is done: this returns at once
        self.skip(queue)


def run_fleet(
    command: str,
    inventory: Inventory,
    robots: list[Robot],
    task: Task,
    options: RunOptions | None = None,
    progress: Progress | None = None,
    connections: Connections | None = None,
) -> FleetResult:
    """Run ``task`` on every robot, ``forks`` at a time; results in inventory order.

    With ``connections`` the robots' transports stay open for a later phase (the caller
    closes them); otherwise they are closed when this returns.
    Raises :class:`FleetInterrupted` on a Ctrl-C, at once (see the module's text).
    """
    if connections is None:
        with Connections(inventory) as own:
            return run_fleet(command, inventory, robots, task, options, progress, own)
    run = _Fleet(connections, task, options or RunOptions(forks=inventory.forks), progress)
    try:
        return _run(run, command, inventory, robots)
    except KeyboardInterrupt:
        raise run.interrupted(command, robots) from None


def _run(run: _Fleet, command: str, inventory: Inventory, robots: list[Robot]) -> FleetResult:
    opts = run.opts
    start = time.monotonic()
    fleet = FleetResult(command, subject=inventory.subject)
    budget = None if opts.max_fail_pct is None else int(len(robots) * opts.max_fail_pct / 100.0)
    canaries = robots[: opts.canary] if opts.canary > 0 else []
    rest = robots[len(canaries):]
    if canaries:
        run.batch(canaries, budget)
        failed = [run.results[r.name] for r in canaries if run.results[r.name].outcome.is_failure]
        if failed:
            run.stop_reason = f"canary {failed[0].robot} {failed[0].outcome.value}"
            fleet.notes.append(f"stopped after the canary: {failed[0].robot} {failed[0].outcome.value}")
    if rest:
        if run.stop_reason:
            run.skip(rest)
        else:
            run.batch(rest, budget)
    if run.stop_reason and not fleet.notes:
        fleet.notes.append(f"stopped early: {run.stop_reason}")
    fleet.results = [run.results[r.name] for r in robots]
    fleet.duration_s = time.monotonic() - start
    return fleet
