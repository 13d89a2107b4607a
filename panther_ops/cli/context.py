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


def _preload(modules: tuple[str, ...]) -> None:
    """Import paramiko in the background while the inventory loads (it takes ~0.05 s), then
    ``modules`` (what the command's robot tasks need, e.g. the planners and their YAML
    editor: ~0.04 s) and what the output needs (rich: ~0.03 s), all while the fleet's
    handshakes run: a task then finds them loaded instead of importing them itself while
    the other robots' tasks wait on the import lock."""
    import importlib
    import threading

    def load() -> None:
        from panther_ops.transport.paramiko_import import import_paramiko

        import_paramiko()
        for name in (*modules, "rich.console", "rich.table", "rich.text"):
            importlib.import_module(name)

    threading.Thread(target=load, name="preload", daemon=True).start()


def load(ctx: typer.Context, preload: tuple[str, ...] = (), start: bool = True) -> Inventory:
    """The inventory; ``start``: begin the background imports first (else the caller does)."""
    from panther_ops.core.fleet.inventory import load_inventory

    if start:
        _preload(preload)
    inv = load_inventory(settings(ctx).inventory)
    info(f"inventory: {inv.path} (from {inv.origin})")
    return inv


def targets(
    ctx: typer.Context, robots: list[str] | None, groups: list[str] | None, all_: bool,
    preload: tuple[str, ...] = (), connect: bool = True, read_only: bool = False,
) -> tuple[Inventory, list[Robot]]:
    """The inventory and the robots chosen; ``preload``: modules the robots' tasks will import.

    Every caller goes on to connect to every robot chosen, its own input already checked, so
    the robots' TCP connections start now, in the background (``connect=False``: not yet).
    ``read_only``: a command that only reads answers, when no robot is chosen, for the
    inventory's ``settings.default_group``, else for every robot.
    """
    inv = load(ctx, preload, start=not connect)
    if read_only and not (robots or groups or all_) and len(inv.robots) > 1:
        if inv.default_group is not None:
            info(f"no robot chosen: group {inv.default_group} (settings.default_group)")
            groups = [inv.default_group]
        else:
            info(f"no robot chosen: reading all {len(inv.robots)} (choose with -r, -g)")
            all_ = True
    chosen = inv.select(robots or [], groups or [], all_)
    if connect:  # the robots first: their sshd then start while paramiko loads
        from panther_ops.core.fleet.connect_ahead import connect_ahead

        connect_ahead(inv, chosen)
        _preload(preload)
    return inv, chosen


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


