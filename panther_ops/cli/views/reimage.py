"""Progress and results of `reimage flash`/`verify`: a rich bar on a terminal, plain lines otherwise."""

from __future__ import annotations

import contextlib
import sys
import threading
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

from panther_ops.cli.render import human_bytes

if TYPE_CHECKING:
    from panther_ops.cli.tables import FitTable
    from panther_ops.results import FleetResult, RobotResult

ProgressFn = Callable[[str, int, "int | None"], None]
PHASES = {"size": "measuring", "checksum": "checksum", "write": "writing", "verify": "verifying",
          "compare": "comparing", "mapping": "mapping", "image": "image"}


def _rate(done: int, seconds: float) -> str:
    return f"{done / (1 << 20) / seconds:.1f} MiB/s" if seconds > 0 else "-"


@contextlib.contextmanager
def progress(json_out: bool, *, plain_every: float = 2.0) -> Iterator[ProgressFn]:
    """A progress callback for the core: bytes, throughput and ETA of each phase, on stderr (a
    bar on a terminal, plain lines otherwise); nothing with ``--json`` or ``--quiet``."""
    from panther_ops.cli.output import quiet

    if json_out or quiet():
        yield lambda _phase, _done, _total: None
        return
    if sys.stderr.isatty():
        with _bar() as fn:
            yield fn
        return
    state: dict[str, float] = {}
    lock = threading.Lock()

    def plain(phase: str, done: int, total: int | None) -> None:
        now = time.monotonic()
        with lock:
            started = state.setdefault(phase + ":start", now)
            last = state.get(phase + ":last", started)
            finished = total is not None and done >= total
            if not finished and now - last < plain_every:
                return
            state[phase + ":last"] = now
        took = now - started
        line = f"{PHASES.get(phase, phase)}: {human_bytes(done)}"
        if total:
            line += f" of {human_bytes(total)} ({100 * done / total:.0f}%)"
        if took >= 0.01:
            line += f", {_rate(done, took)}"
        if total and done < total and done > 0 and took > 0:
            line += f", ETA {(total - done) * took / done:.0f} s"
        elif finished:
            line += f", done in {took:.1f} s"
        sys.stderr.write(line + "\n")

    yield plain


@contextlib.contextmanager
def _bar() -> Iterator[ProgressFn]:
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        DownloadColumn,
        Progress,
        TextColumn,
        TimeRemainingColumn,
        TransferSpeedColumn,
    )

    tasks: dict[str, object] = {}
    lock = threading.Lock()
    columns = (TextColumn("{task.description:<10}"), BarColumn(), DownloadColumn(binary_units=True),
               TransferSpeedColumn(), TimeRemainingColumn())
    with Progress(*columns, console=Console(stderr=True)) as bar:

        def step(phase: str, done: int, total: int | None) -> None:
            with lock:
                if phase not in tasks:
                    tasks[phase] = bar.add_task(PHASES.get(phase, phase), total=total)
                bar.update(tasks[phase], completed=done, total=total)  # type: ignore[arg-type]

        yield step


def print_carried(fleet: FleetResult, *, title: str) -> None:
    """The per-robot results, then each robot's files (path, role, size, mode, owner, secret)."""
    from panther_ops.cli.render import print_results, show

    print_results(fleet, title=title)
    for r in fleet.results:
        table = files_table(r)
        if table is not None:
            show(table)


def files_table(r: RobotResult) -> FitTable | None:
    """A robot's carried files; the paths shortened from the left (never two alike)."""
    from panther_ops.cli.render import esc, new_table
    from panther_ops.cli.tables import Column

    files = r.data.get("files") or []
    if not files:
        return None
    ident = r.data.get("robot") or {}
    head = ", ".join(f"{k} {ident[k]}" for k in ("model", "serial", "stack", "os_build", "host_key") if ident.get(k))
    table = new_table(esc(f"{r.robot}: {head}" if head else r.robot), (
        Column("path", "path"), Column("role", drop=1), Column("size", justify="right"),
        Column("mode", drop=3), Column("owner", drop=2), Column("secret")),
        title_justify="left")
    for f in files:
        table.add_row(esc(f["path"] + (f" -> {f['link']}" if f.get("link") else "")), esc(f["role"]),
                      human_bytes(f["size"]), esc(f["mode"]), esc(f["owner"]), "yes" if f["secret"] else "")
    return table
