"""How the shutdown commands show their results: the hosts file's findings, the hosts shut
down (`shutdown --hosts`' results table; its plan is the change's), the robots' hosts files,
the setup steps (tables on a terminal, one JSON document with --json)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from panther_ops.core.kinds.hostsfile import HostsFile
    from panther_ops.results import FleetResult


def print_findings(parsed: HostsFile) -> None:
    err = stderr()
    for f in parsed.warnings:
        err.print(f"[yellow]warning[/] {esc(parsed.source)}: {esc(f)}")


def finish_hosts(fleet: FleetResult, json_out: bool) -> int:
    from panther_ops.cli.render import emit_json, result_cell
    from panther_ops.core.shutdown.run import summary

    if json_out:
        emit_json(fleet.to_json())
        return int(fleet.exit_code)
    from panther_ops.cli.render import new_table
    from panther_ops.cli.tables import Column

    table = new_table(fleet.command, (Column("host", "name"), Column("result"), Column("message", "message"),
                                      Column("time")))
    for r in fleet.results:
        table.add_row(esc(r.robot), result_cell(r), esc(r.message),
                      f"{r.duration_s:.1f} s")
    show(table)
    from panther_ops.cli.render import counted

    stderr().print(f"{counted(len(fleet.results), 'host')}: {summary(fleet)} in {fleet.duration_s:.1f} s"
                    + ("" if fleet.exit_code == 0 else f" (exit {int(fleet.exit_code)})"))
    return int(fleet.exit_code)


def show(table: Any) -> None:
    from panther_ops.cli.render import show

    show(table)


def stdout() -> Any:
    from panther_ops.cli.render import _console

    return _console()


def stderr() -> Any:
    from panther_ops.cli.render import _console

    return _console(stderr=True)


def esc(text: object) -> str:
    from panther_ops.cli.render import esc

    return esc(text)


def print_list(fleet: FleetResult) -> None:
    """`shutdown hosts list`: each file's hosts."""
    from panther_ops.cli.render import new_table, print_warnings, result_cell
    from panther_ops.cli.tables import Column

    for r in fleet.results:
        title = f"{r.robot}: {r.data.get('hosts_file', '')}"
        table = new_table(esc(title), (Column("ip", "name"), Column("method"), Column("user"),
                                       Column("port", drop=1), Column("command / secret"),
                                       Column("timeout", drop=2), Column("ping", drop=3)))
        for h in r.data.get("hosts", []):
            http = h["method"] == "http"
            table.add_row(esc(h["ip"]), h["method"], "" if http else esc(h["username"]), str(h["port"]),
                          esc(h["secret"] if http else h["command"]), f"{h['timeout']:g} s",
                          "" if http else ("yes" if h["ping_for_success"] else "no"))
        if r.outcome.is_failure and not r.data.get("hosts"):
            table.add_row(result_cell(r), "", "", "", "", "", "", note=esc(r.message))
        show(table)
        for e in r.data.get("errors", []):
            stderr().print(f"[red]error[/] {esc(r.robot)}: {esc(e)}")
    print_warnings(fleet)


def print_steps(fleet: FleetResult) -> None:
    """`shutdown setup`: each robot's steps."""
    from panther_ops.cli.render import new_table, outcome_cell, print_diffs, print_warnings, result_cell
    from panther_ops.cli.tables import Column
    from panther_ops.results import Outcome

    for r in fleet.results:
        table = new_table(esc(f"{fleet.command}: {r.robot}"), (Column("step"), Column("result"),
                                                               Column("message", "message")))
        for s in r.data.get("steps", []):
            outcome = Outcome(s["outcome"])
            table.add_row(esc(s["step"]), outcome_cell(outcome), esc(s["message"]))
        if not r.data.get("steps"):
            table.add_row("-", result_cell(r), esc(r.message))
        show(table)
    print_diffs(fleet)
    print_warnings(fleet)
    for r in fleet.results:  # the message once: a failure's is the table's failing step
        shown = r.data.get("steps") and not r.outcome.is_failure
        stderr().print(f"{esc(r.robot)}: {result_cell(r)}"
                        + (f" {esc(r.message)}" if shown else ""))


def print_validated(fleet: FleetResult) -> None:
    """`shutdown hosts validate`: each file's errors and warnings, and its verdict."""
    from panther_ops.results import Outcome

    out, err = stdout(), stderr()
    for r in fleet.results:
        for e in r.data.get("errors", []):
            err.print(f"[red]error[/] {esc(r.robot)}: {esc(e)}")
        for w in r.warnings:
            err.print(f"[yellow]warning[/] {esc(r.robot)}: {esc(w)}")
        colour = "red" if r.outcome is not Outcome.OK else "green"
        out.print(f"{esc(r.robot)}: [{colour}]{r.outcome.value}[/] {esc(r.message)}")


def print_check(fleet: FleetResult) -> None:
    """`shutdown check`: each host of each robot, the step it stopped at and its fix."""
    from panther_ops.cli.render import new_table, print_warnings, result_cell
    from panther_ops.cli.tables import Column

    table = new_table("panther-ops shutdown check", (Column("robot", "name"), Column("host", "name"),
                                                     Column("result"), Column("step"),
                                                     Column("message"), Column("fix")))
    for r in fleet.results:
        rows = r.data.get("hosts", [])
        if not rows:
            table.add_row(esc(r.robot), "-", result_cell(r), "", "", "", note=esc(r.message))
        for i, h in enumerate(rows):
            result = "[green]ok[/]" if h["ok"] else "[red]failed[/]"
            table.add_row(esc(r.robot) if i == 0 else "", esc(h["host"]), result, esc(h["step"]), esc(h["message"]),
                          esc(h["fix"]))
    show(table)
    print_warnings(fleet)


def print_robots_down(fleet: FleetResult) -> None:
    """`shutdown robot`: per robot its hosts, then its Built-in Computer."""
    from panther_ops.cli.render import new_table, outcome_cell, print_summary, print_warnings, result_cell
    from panther_ops.cli.tables import Column
    from panther_ops.results import Outcome

    for r in fleet.results:
        table = new_table(esc(f"shutdown robot: {r.robot}"), (Column("host", "name"), Column("result"),
                                                              Column("message", "message"), Column("time")))
        for h in r.data.get("hosts", []):
            table.add_row(esc(h["robot"]), outcome_cell(Outcome(h["outcome"])), esc(h["message"]),
                          f"{h['duration_s']:.1f} s")
        table.add_row(f"{esc(r.robot)} (Built-in Computer)", result_cell(r), esc(r.message),
                      f"{r.duration_s:.1f} s")
        show(table)
    print_warnings(fleet)
    print_summary(fleet)
