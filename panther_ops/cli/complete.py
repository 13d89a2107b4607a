"""Shell completion of the names a command line takes (docs/getting-started.md): robots after
``-r``, groups after ``-g``, config keys after ``config get|set|unset``, file kinds after
``--as`` (and ``config pull``), shipped scenarios after ``--scenario``.

Each is typer's ``autocompletion=`` of the parameter. Robots and groups come from the inventory
in use, found as a run finds it: the ``-i`` given on the command line so far, else
``$PANTHER_OPS_INVENTORY``, else ``./inventory``. Completing reads that file and nothing else
(no robot is contacted) and never prints: an inventory that cannot be read completes nothing,
and the shell falls back to its own (file names).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import typer

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Inventory

Completion = list[tuple[str, str]]
"""(value, help): zsh and fish show the help beside the value; bash shows the values."""


def _quiet(complete: Callable[[typer.Context], Completion]) -> Callable[[typer.Context, str], Completion]:
    """A completion that never fails: any error completes nothing (the shell shows no message)."""

    def run(ctx: typer.Context, incomplete: str) -> Completion:
        try:
            return [(v, h) for v, h in complete(ctx) if v.startswith(incomplete)]
        except Exception:  # a completion that fails completes nothing; it never prints
            return []

    run.__name__ = run.__qualname__ = complete.__name__
    run.__doc__ = complete.__doc__
    return run


def given(ctx: typer.Context, name: str) -> Any:
    """The value of parameter ``name`` on the command line so far: the nearest command that has
    one (a global option on the root, or an option of the command itself)."""
    c: Any = ctx
    while c is not None:
        value = c.params.get(name)
        if value is not None:
            return value
        c = c.parent
    return None


def inventory(ctx: typer.Context) -> Inventory:
    """The inventory a run of this command line would use (read, not a robot contacted)."""
    from panther_ops.core.fleet.inventory_file import load_inventory

    return load_inventory(given(ctx, "inventory"))


def _robots(ctx: typer.Context) -> Completion:
    """The inventory's robot names, but those already given with -r."""
    chosen = set(given(ctx, "robot") or ())
    return [(name, where) for name, where in _robot(ctx) if name not in chosen]


def _robot(ctx: typer.Context) -> Completion:
    """The inventory's robot names (a command's ROBOT argument), each with where it is."""
    return [(name, "demo robot" if robot.transport == "local" else robot.host)
            for name, robot in inventory(ctx).robots.items()]


def _groups(ctx: typer.Context) -> Completion:
    """The inventory's groups, but those already given with -g."""
    chosen = set(given(ctx, "group") or ())
    inv = inventory(ctx)
    return [(name, str(group.get("description") or ", ".join(r.name for r in inv.robots.values() if name in r.groups)))
            for name, group in inv.groups.items() if name not in chosen]


def _config_keys(ctx: typer.Context) -> Completion:
    """Launch arguments of the catalogue (every supported stack's) and controller limit keys."""
    from panther_ops.core.kinds.arg_catalogue import CATALOGUE
    from panther_ops.core.kinds.controller_limits import all_limit_keys

    return [*((s.key, s.description) for s in CATALOGUE), *((k, "controller limit") for k in all_limit_keys("WH02"))]


def _kinds(ctx: typer.Context) -> Completion:
    """The config file kinds `config push --as` and `config pull` take."""
    from panther_ops.core.kinds import PUSHABLE

    return [(k.value, "config file kind") for k in PUSHABLE]


def _scenarios(ctx: typer.Context) -> Completion:
    """The scenarios panther-ops ships (a file path completes as the shell's file names)."""
    from panther_ops.core.fleet.inventory_desired import shipped_scenarios

    return [(name, "shipped scenario") for name in shipped_scenarios()]


robots = _quiet(_robots)
robot = _quiet(_robot)
groups = _quiet(_groups)
config_keys = _quiet(_config_keys)
kinds = _quiet(_kinds)
scenarios = _quiet(_scenarios)
