"""Human views of `driver status` and `driver versions`."""

from __future__ import annotations

from panther_ops.cli.output import console
from panther_ops.cli.render import (
    esc,
    human_bytes,
    new_table,
    print_summary,
    print_table,
    print_warnings,
    result_cell,
    show,
)
from panther_ops.cli.tables import Column
from panther_ops.results import FleetResult


def print_status(fleet: FleetResult) -> None:
    from panther_ops.core.containers.times import human_duration

    table = new_table("panther-ops driver status", (
        Column("robot", "name"), Column("result"), Column("service", drop=4), Column("image", "path"),
        Column("state"), Column("uptime"), Column("restarts", drop=2),
        Column("exit", drop=3), Column("health", drop=1), Column("command", drop=5)))
    for r in fleet.results:
        d = r.data
        if "state" not in d or d.get("state") == "missing":
            table.add_row(esc(r.robot), result_cell(r), esc(d.get("service", "")),
                          esc(d.get("compose_image") or ""), "", "", "", "", "", "", note=esc(r.message))
            continue
        drift = d.get("command_drift")
        table.add_row(
            esc(r.robot), result_cell(r), esc(d["service"]), esc(d.get("image") or ""),
            esc(d["state"]), human_duration(d.get("uptime_s")) if d.get("uptime_s") is not None else "-",
            str(d.get("restart_count", "")), str(d.get("exit_code", "")), esc(d.get("health") or "-"),
            "[yellow]differs from compose.yaml[/]" if drift else ("as compose.yaml" if drift is False else "?"),
        )
    print_table(table, fleet)


def print_versions(fleet: FleetResult) -> None:
    table = new_table("panther-ops driver versions (on each robot)", (
        Column("robot", "name"), Column("result"), Column("image", "path"), Column("use"), Column("id", "id"),
        Column("size", justify="right", drop=1)))
    for r in fleet.results:
        images = r.data.get("local")
        if not images:
            table.add_row(esc(r.robot), result_cell(r), "", "", "", "", note=esc(r.message))
            continue
        for i, e in enumerate(images):
            mark = ", ".join(m for m, on in (("in use", e["in_use"]), ("compose.yaml", e["in_compose"])) if on)
            table.add_row(esc(r.robot) if i == 0 else "", result_cell(r) if i == 0 else "",
                          esc(e["image"]), f"[bold]{mark}[/]" if mark else "", e["id"].removeprefix("sha256:")[:12],
                          human_bytes(e.get("size")))
    out = console()
    show(table)
    remote = fleet.data.get("remote")
    if remote:
        rt = new_table("Docker Hub (released Humble tags)", (Column("repository", "name"), "tags, newest first"))
        for repo, info in remote.items():
            rt.add_row(esc(repo), esc(", ".join(t["tag"] for t in info["tags"])) if "tags" in info
                       else f"[red]{esc(info['error'])}[/]")
        show(rt)
        for r in fleet.results:
            if r.data.get("newer"):
                out.print(f"{r.robot}: newer than {esc(r.data['compose_image'])}: "
                          f"{esc(', '.join(r.data['newer']))}")
    print_warnings(fleet)
    print_summary(fleet)
