"""Human view of `estop status`."""

from __future__ import annotations

from panther_ops.cli.render import esc, new_table, print_table, result_cell
from panther_ops.cli.tables import Column
from panther_ops.results import FleetResult


def print_state(fleet: FleetResult) -> None:
    table = new_table(None, (Column("robot", "name"), Column("e-stop"), Column("cmd_vel publishers"),
                             Column("namespace", drop=1), Column("note", "message")))
    for r in fleet.results:
        e_stop = r.data.get("e_stop")
        shown = ("[red]triggered[/]" if e_stop is True else "[green]released[/]" if e_stop is False
                 else result_cell(r))
        pubs = r.data.get("cmd_vel_publishers")
        mux = r.data.get("twist_mux_publishers")  # husarion_ugv 2.3.2: each input of the twist mux
        if isinstance(mux, dict):
            ns = str(r.data.get("namespace", "/")).rstrip("/")
            pubs = [f"{node} ({topic.removeprefix(ns + '/')})" for topic, nodes in mux.items() for node in nodes]
        note = "recorded (demo robot)" if r.data.get("recorded") else ("" if e_stop is not None else r.message)
        table.add_row(esc(r.robot), shown, esc(", ".join(pubs) if pubs else ("none" if pubs == [] else "-")),
                      esc(r.data.get("namespace", "-")), esc(note))
    print_table(table, fleet)
