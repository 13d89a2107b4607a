"""Per-invocation state of the CLI: global options, consoles, and fleet plumbing."""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import typer

if TYPE_CHECKING:
    import threading

    from panther_ops.cli.mutate import Asking
    from panther_ops.core.fleet.changes import Planner
    from panther_ops.core.fleet.inventory import Inventory, Robot
    from panther_ops.core.fleet.runner import Task
    from panther_ops.results import FleetResult
    from panther_ops.secret import Secret


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


def _import_paramiko() -> threading.Thread:
    """Import paramiko (~0.1 s) in a background thread while this one reads the inventory.

    Made safe by design: two threads importing modules of one package at the same time can
    meet a half-initialised module (CPython breaks the lock cycle of a package and a
    submodule imported from two threads by handing one of them the unfinished module: a
    NameError inside PyYAML was seen). So the thread imports paramiko alone, a third-party
    package that imports nothing of ours; the inventory's parser, PyYAML, which paramiko
    also reaches (through invoke's vendored yaml), is imported here first; while the thread
    runs, reading the inventory imports only single standard-library modules (held by
    tests/cli/test_background_import.py); and the thread is joined before any robot's task
    starts, so no task ever imports while it does. The robots' tasks import what else they
    need themselves, all along the same path."""
    import importlib
    import threading

    import yaml  # noqa: F401  # the inventory's parser, before the thread starts (see above)

    # not a daemon: an interpreter that exits normally (main() called in-process, then
    # sys.exit) waits for the import to end instead of tearing down a thread that is inside
    # one (glibc: "FATAL: exception not rethrown", SIGABRT)
    thread = threading.Thread(target=importlib.import_module, args=("paramiko",), name="import-paramiko",
                              daemon=False)
    thread.start()
    return thread


def load(ctx: typer.Context, robots_next: bool = False) -> Inventory:
    """The inventory; ``robots_next``: the command contacts robots next, so paramiko is
    imported meanwhile (see :func:`_import_paramiko`)."""
    from panther_ops.core.fleet.inventory_file import load_inventory

    importing = _import_paramiko() if robots_next else None
    try:
        inv = load_inventory(settings(ctx).inventory)
    finally:
        if importing is not None:
            importing.join()
    info(f"inventory: {inv.path} (from {inv.origin})")
    return inv


def targets(
    ctx: typer.Context, robots: list[str] | None, groups: list[str] | None, all_: bool,
    read_only: bool = False,
) -> tuple[Inventory, list[Robot]]:
    """The inventory and the robots chosen.

    ``read_only``: a command that only reads answers, when no robot is chosen, for the
    inventory's ``settings.default_group``, else for every robot.
    """
    inv = load(ctx, robots_next=True)
    if read_only and not (robots or groups or all_) and len(inv.robots) > 1:
        if inv.default_group is not None:
            info(f"no robot chosen: group {inv.default_group} (settings.default_group)")
            groups = [inv.default_group]
        else:
            info(f"no robot chosen: reading all {len(inv.robots)} (choose with -r, -g)")
            all_ = True
    chosen = inv.select(robots or [], groups or [], all_)
    check_keys(inv, chosen)
    return inv, chosen


def check_keys(inv: Inventory, chosen: list[Robot]) -> None:
    """A key file of the chosen robots that is missing or unreadable: exit 2 before any robot is
    contacted (``Inventory.key_problems``), each named with its file, key and fix."""
    problems = inv.key_problems(chosen)
    if len(problems) == 1:
        raise problems[0]
    if problems:
        from panther_ops.errors import InventoryError

        raise InventoryError(f"{len(problems)} identity files cannot be used:\n  " +
                             "\n  ".join(p.message for p in problems),
                             path=str(inv.path), hint=problems[0].hint)


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
    progress = FleetProgress([r.name for r in chosen], enabled=progress_wanted(json_out) and len(chosen) > 1,
                             printing=not json_out)
    with progress.live():
        return run_fleet(command, inv, chosen, task, opts, progress)


_ROBOTS_ONLY = {
    "no_restart": ("--no-restart", "no container is recreated for a local file"),
    "settle": ("--settle", "no container is recreated, so none settles"),
    "forks": ("--forks", "one local file, no robots worked on at once"),
}
"""The shared options a local file (``--file``, a FILE argument) gives no meaning: option, why."""


@dataclass
class Fleet:
    """What a fleet command was given of the shared options (cli/options.py), and the one way
    its body goes: select the robots, run the task (or plan and apply a change), render,
    return the exit code."""

    ctx: typer.Context
    robot: list[str] | None = None
    group: list[str] | None = None
    all_: bool = False
    yes: bool = False
    dry_run: bool = False
    no_restart: bool = False
    settle: float = 5.0
    json_out: bool = False
    forks: int | None = None
    canary: int = 0
    max_fail: float | None = None

    def robots_only(self, what: str) -> None:
        """``what`` (a local file) instead of robots: the shared options that mean something only
        for robots, given on the command line, are a usage error naming each and why (exit 2)."""
        given = [(option, why) for name, (option, why) in _ROBOTS_ONLY.items()
                 if getattr(self.ctx.get_parameter_source(name), "name", "DEFAULT") in ("COMMANDLINE", "ENVIRONMENT")]
        if given:
            from panther_ops.errors import UsageError

            one = len(given) == 1
            raise UsageError(f"{', '.join(o for o, _ in given)} {'means' if one else 'mean'} nothing for {what} ("
                             + "; ".join(f"{o}: {why}" for o, why in given) + ")",
                             hint=f"leave {'it' if one else 'them'} out: {'it is' if one else 'they are'} for robots "
                                  "(-r/-g/--all)")

    def targets(self, read_only: bool = False) -> tuple[Inventory, list[Robot]]:
        """The inventory and the robots chosen (see :func:`targets`)."""
        return targets(self.ctx, self.robot, self.group, self.all_, read_only=read_only)

    def results(self, command: str, task: Task, *, read_only: bool = False,
                at_once: bool = False, progress: bool = True,
                on: tuple[Inventory, list[Robot]] | None = None) -> FleetResult:
        """``task`` run on the robots chosen (or ``on`` the targets given); ``at_once``: every
        robot at the same time (no fork limit); ``progress``: the live progress when it is wanted."""
        inv, chosen = on or self.targets(read_only)
        forks = (len(chosen) or None) if at_once else self.forks
        return run(command, inv, chosen, task, forks=forks, canary=self.canary, max_fail=self.max_fail,
                   json_out=self.json_out or not progress)

    def show(self, fleet: FleetResult, view: Callable[[FleetResult], None] | None = None) -> int:
        """The result as one JSON document, else through ``view`` (default: the generic table)."""
        from panther_ops.cli.render import finish, print_results

        return finish(fleet, self.json_out, view or print_results)

    def run(self, command: str, task: Task, view: Callable[[FleetResult], None] | None = None, *,
            read_only: bool = False, at_once: bool = False,
            on: tuple[Inventory, list[Robot]] | None = None) -> int:
        """Select, run ``task``, render: a read or an action on each robot."""
        return self.show(self.results(command, task, read_only=read_only, at_once=at_once, on=on),
                         view)

    def change(self, command: str, planner: Planner, *, verb: str = "Apply to", asking: Asking | None = None,
               read_only: bool = False, on: tuple[Inventory, list[Robot]] | None = None,
               restart: bool | None = None, drift_exit: bool = False, sudo_password: Secret | None = None,
               view: Callable[[FleetResult], None] | None = None) -> int:
        """A change through the pipeline (cli/mutate.py) on the robots chosen, or ``on`` the
        targets given; ``read_only``: only compare (a dry run that does not call itself one);
        ``verb`` (or all of ``asking``), ``drift_exit``, ``view``: see
        :class:`~panther_ops.cli.mutate.Change`; ``restart``: when the command decides it (else
        not ``--no-restart``); ``sudo_password``: for steps that run sudo beside the robot."""
        from panther_ops.cli.mutate import Asking, Change, mutate

        inv, chosen = on or self.targets(read_only)
        return mutate(Change(command, planner, asking or Asking(verb), read_only, drift_exit, view,
                             restart=not self.no_restart if restart is None else restart,
                             sudo_password=sudo_password), inv, chosen, self)
