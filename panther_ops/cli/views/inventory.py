"""Human view of `inventory list`."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Inventory, Robot


def print_robots(inv: Inventory, robots: list[Robot]) -> None:
    """The robots with how each is reached."""
    from panther_ops.cli.render import esc, new_table, show
    from panther_ops.cli.tables import Column

    table = new_table(esc(f"inventory {inv.path}"), (Column("robot", "name"), Column("reached as", "path"),
                                                     Column("via"), Column("groups"), Column("stack", drop=1)))
    for r in robots:
        where = str(r.root) if r.transport == "local" else f"{r.user}@{r.host}" + (f":{r.port}" if r.port else "")
        table.add_row(esc(r.name), esc(where), esc(r.jump or ""), esc(", ".join(r.groups)), esc(r.stack))
    show(table)
