"""`driver logs` and `manager logs`: one container's log per robot, or one followed live."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from panther_ops.cli import context

if TYPE_CHECKING:
    from panther_ops.core.containers.logs import LogOptions
    from panther_ops.core.fleet.inventory import Inventory, Robot

OpenLogs = Callable[[Any, "LogOptions"], tuple[str, Any]]


def show_logs(command: str, inv: Inventory, chosen: list[Robot], open_logs: OpenLogs, *, lines: int | None,
              since_s: float | None, timestamps: bool, follow: bool, json_out: bool,
              skip: tuple[type[Exception], ...] = ()) -> int:
    """Print each robot's log (prefixed ``robot | `` when several), or follow one robot's.

    A robot without a docker engine (a demo robot) is ``skipped``, whichever container is asked for.
    """
    from panther_ops.cli.render import error, finish, print_warnings
    from panther_ops.core.containers.engine import NoEngineError
    from panther_ops.core.containers.logs import LogOptions, prefix_lines

    skip = (NoEngineError, *skip)
    from panther_ops.errors import UsageError
    from panther_ops.results import Outcome, RobotResult

    if follow:
        if len(chosen) != 1:
            raise UsageError(f"--follow works on one robot; {len(chosen)} chosen", hint="pick one with -r NAME")
        if json_out:
            raise UsageError("--follow prints the log as it comes; --json is for a finished answer")
        opts = LogOptions(tail=0 if lines is None else lines, since_s=since_s, follow=True, timestamps=timestamps)
        return _follow(command, inv, chosen[0], open_logs, opts, skip)
    opts = LogOptions(tail=100 if lines is None else lines, since_s=since_s, timestamps=timestamps)
    got: dict[str, bytes] = {}

    def task(c: Any) -> RobotResult:
        try:
            name, data = open_logs(c, opts)
        except skip as exc:
            return RobotResult(c.robot.name, Outcome.SKIPPED, str(exc))
        got[c.robot.name] = bytes(data)
        count = data.count(b"\n")
        return RobotResult(c.robot.name, Outcome.OK, f"{count} lines from container {name}",
                           data={"container": name, "log": data.decode(errors="replace")} if json_out else
                           {"container": name})

    fleet = context.run(command, inv, chosen, task, json_out=True)
    if json_out:
        return finish(fleet, True, lambda f: None)
    several = len(chosen) > 1
    for r in fleet.results:
        data = got.get(r.robot)
        if data is None:
            (context.info if r.outcome is Outcome.SKIPPED else error)(f"{r.robot}: {r.outcome.value}: {r.message}")
            continue
        sys.stdout.buffer.write(prefix_lines(r.robot, data) if several else data)
    sys.stdout.flush()
    print_warnings(fleet)
    return int(fleet.exit_code)


def _follow(command: str, inv: Inventory, robot: Robot, open_logs: OpenLogs, opts: LogOptions,
            skip: tuple[type[Exception], ...]) -> int:
    """Stream one robot's log in this thread until it ends or Ctrl-C (a robot without a docker
    engine is skipped, as without --follow)."""
    from panther_ops.cli.render import error
    from panther_ops.core.containers.logs import iter_chunks
    from panther_ops.core.fleet.runner import Connections, RobotContext, run_one
    from panther_ops.results import FleetResult, Outcome, RobotResult

    out = sys.stdout.buffer

    def task(c: RobotContext) -> RobotResult:
        try:
            name, stream = open_logs(c, opts)
        except skip as exc:
            return RobotResult(c.robot.name, Outcome.SKIPPED, str(exc))
        context.info(f"{c.robot.name}: following {name} (Ctrl-C to stop)")
        try:
            for chunk in iter_chunks(stream):
                out.write(chunk)
                out.flush()
        finally:
            with contextlib.suppress(Exception):  # closing a cancelled stream must not hide the interrupt
                stream.close()
        return RobotResult(c.robot.name, Outcome.OK, f"{name}: the log ended (container stopped or recreated)")

    with Connections(inv) as conns:
        try:
            result = run_one(conns, robot, task)
        except KeyboardInterrupt:
            return 0
    if result.outcome is Outcome.SKIPPED:
        context.info(f"{result.robot}: skipped: {result.message}")
    elif result.outcome is not Outcome.OK:
        error(f"{result.robot}: {result.outcome.value}: {result.message}")
    else:
        context.info(f"{result.robot}: {result.message}")
    return int(FleetResult(command, [result]).exit_code)
