"""Per-invocation state of the CLI: global options, consoles, and fleet plumbing."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING

import typer

if TYPE_CHECKING:
    from panther_ops.core.inventory import Inventory, Robot
    from panther_ops.core.runner import Task
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


def _preload_ssh() -> None:
    """Import paramiko in the background while the inventory loads (it takes ~0.05 s), then
    what the output needs (rich: ~0.03 s), which the fleet's handshakes leave time for."""
    import threading

    def load() -> None:
        from panther_ops.transport.paramiko_import import import_paramiko

        import_paramiko()
        import rich.console
        import rich.table
        import rich.text  # noqa: F401

    threading.Thread(target=load, name="preload-paramiko", daemon=True).start()


def load(ctx: typer.Context) -> Inventory:
    from panther_ops.core.inventory import load_inventory

    _preload_ssh()
    inv = load_inventory(settings(ctx).inventory)
    info(f"inventory: {inv.path} (from {inv.origin})")
    return inv


def targets(
    ctx: typer.Context, robots: list[str] | None, groups: list[str] | None, all_: bool
) -> tuple[Inventory, list[Robot]]:
    inv = load(ctx)
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
    from panther_ops.cli.render import progress_printer
    from panther_ops.core.runner import RunOptions, run_fleet

    opts = RunOptions(forks=forks or inv.forks, canary=canary, max_fail_pct=max_fail)
    with progress_printer(len(chosen), enabled=not json_out) as progress:
        return run_fleet(command, inv, chosen, task, opts, progress)


