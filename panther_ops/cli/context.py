"""Per-invocation state of the CLI: global options, consoles, and fleet plumbing."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING

import typer

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Inventory, Robot
    from panther_ops.core.fleet.runner import Task
    from panther_ops.results import FleetResult


@dataclass
class Settings:
    inventory: str | None = None
    verbose: int = 0
    debug: bool = False
    yes: bool = False


def settings(ctx: typer.Context) -> Settings:
    obj = ctx.find_root().obj
    return obj if isinstance(obj, Settings) else Settings()


def info(message: str) -> None:
    """A human message on stderr (stdout is for data)."""
    sys.stderr.write(message + "\n")


RICH = ("rich.console", "rich.table", "rich.text")
"""What a table on the terminal needs (``--json`` needs none of it)."""


def _preload(modules: tuple[str, ...]) -> None:
    """Import paramiko in the background while the inventory loads (it takes ~0.1 s), then
    ``modules`` (what the command's robot tasks need, e.g. the planners and their YAML
    editor: ~0.04 s; what the output needs, :data:`RICH`: ~0.03 s), all while the fleet's
    handshakes run: a task then finds them loaded instead of importing them itself while
    the other robots' tasks wait on the import lock. Only what the run will use: on a busy
    machine the imports take the interpreter from the handshakes."""
    import importlib
    import threading

    def load() -> None:
        for name in ("paramiko", *modules):
            importlib.import_module(name)

    # not a daemon: an interpreter that exits normally (main() called in-process, then
    # sys.exit) waits for the imports to end instead of tearing down a thread that is inside
    # one (glibc: "FATAL: exception not rethrown", SIGABRT); the console script leaves with
    # os._exit once its output is flushed, so it never waits for them
    threading.Thread(target=load, name="preload", daemon=False).start()


def load(ctx: typer.Context, preload: tuple[str, ...] = (), tables: bool = True) -> Inventory:
    """The inventory, the background imports started first (see :func:`_preload`);
    ``tables``: the output will be rich tables (not ``--json``)."""
    from panther_ops.core.fleet.inventory_file import load_inventory

    _preload(preload + RICH if tables else preload)
    inv = load_inventory(settings(ctx).inventory)
    info(f"inventory: {inv.path} (from {inv.origin})")
    return inv


def targets(
    ctx: typer.Context, robots: list[str] | None, groups: list[str] | None, all_: bool,
    preload: tuple[str, ...] = (), read_only: bool = False, tables: bool = True,
) -> tuple[Inventory, list[Robot]]:
    """The inventory and the robots chosen; ``preload``: modules the robots' tasks will import;
    ``tables``: the output will be rich tables (False with ``--json``: rich is not preloaded).

    ``read_only``: a command that only reads answers, when no robot is chosen, for the
    inventory's ``settings.default_group``, else for every robot.
    """
    inv = load(ctx, preload, tables)
    if read_only and not (robots or groups or all_) and len(inv.robots) > 1:
        if inv.default_group is not None:
            info(f"no robot chosen: group {inv.default_group} (settings.default_group)")
            groups = [inv.default_group]
        else:
            info(f"no robot chosen: reading all {len(inv.robots)} (choose with -r, -g)")
            all_ = True
    return inv, inv.select(robots or [], groups or [], all_)


def run(
    command: str,
    inv: Inventory,
    chosen: list[Robot],
    task: Task,
    *,
    forks: int | None = None,
    canary: int = 0,
    max_fail: float | None = None,
    json_out: bool = False,
) -> FleetResult:
    from panther_ops.cli.progress import FleetProgress, progress_wanted
    from panther_ops.core.fleet.runner import RunOptions, run_fleet

    opts = RunOptions(forks=forks or inv.forks, canary=canary, max_fail_pct=max_fail)
    progress = FleetProgress([r.name for r in chosen], enabled=progress_wanted(json_out) and len(chosen) > 1)
    with progress.live():
        return run_fleet(command, inv, chosen, task, opts, progress)


