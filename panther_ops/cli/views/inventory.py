"""Human view of `inventory list`."""

from __future__ import annotations

from typing import TYPE_CHECKING

from panther_ops.cli.output import console

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Inventory, Robot


def print_robots(inv: Inventory, robots: list[Robot]) -> None:
    """The robots with how each is reached."""
    from rich.table import Table

    table = Table(title=f"inventory {inv.path}")
    for col in ("robot", "reached as", "via", "groups", "stack"):
        table.add_column(col)
    for r in robots:
        if r.transport == "local":
            where = f"local dir {r.root}"
        else:
            where = f"{r.user}@{r.host}" + (f":{r.port}" if r.port else "")
        table.add_row(r.name, where, r.jump or "", ", ".join(r.groups), r.stack)
    console().print(table)
