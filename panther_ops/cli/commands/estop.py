"""`panther-ops estop status|trigger|reset`: the driver's E-stop, through its ROS API."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Annotated

import typer

from panther_ops.cli import context
from panther_ops.cli.options import All, Groups, Json, Robots

if TYPE_CHECKING:
    from panther_ops.results import FleetResult

app = typer.Typer(help="The E-stop: see it, trigger it (all targeted robots at once), reset it.",
                  no_args_is_help=True)

_PRELOAD = ("panther_ops.core.remote.estop.calls",)


@app.command("status")
def status(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    json_out: Json = False,
) -> int:
    """Each robot's E-stop (the driver's hardware/e_stop topic) and the nodes publishing on
    cmd_vel, asked inside the driver container in the robot's namespace.

    Example: panther-ops estop status --all
    """
    from panther_ops.cli.render import finish
    from panther_ops.core.remote.estop.calls import status_task

    inv, chosen = context.targets(ctx, robot, group, all_, preload=_PRELOAD, tables=not json_out)
    fleet = context.run("estop status", inv, chosen, status_task, forks=len(chosen) or None, json_out=json_out)
    return finish(fleet, json_out, _print_state)


@app.command("trigger")
def trigger(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    json_out: Json = False,
) -> int:
    """Trigger the E-stop (hardware/e_stop_trigger) on every targeted robot at once: an
    emergency, so no confirmation, no fork limit, all connections opened in parallel; the
    driver's answer per robot. Exit 3 when any robot did not confirm.

    Example: panther-ops estop trigger --all
    """
    from panther_ops.cli.render import finish, print_results
    from panther_ops.core.remote.estop.calls import trigger_task

    inv, chosen = context.targets(ctx, robot, group, all_, preload=_PRELOAD, tables=not json_out)
    # every robot at once; no progress bar (json_out=True only turns it off)
    fleet = context.run("estop trigger", inv, chosen, trigger_task, forks=len(chosen) or None, json_out=True)
    return finish(fleet, json_out, print_results)


@app.command("reset")
def reset(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Reset without asking (needed when not interactive).")]
    = False,
    dry_run: Annotated[bool, typer.Option("--dry-run", help="Only check: state and cmd_vel publishers.")] = False,
    json_out: Json = False,
) -> int:
    """Reset the E-stop (hardware/e_stop_reset). First checks every robot: a robot where a
    node publishes on cmd_vel is refused, naming the node (the manual: a reset is impossible
    while messages arrive); a robot whose E-stop is not triggered is left alone. Then names
    each robot to be reset and asks (--yes), resets them and reads the E-stop back.

    Example: panther-ops estop reset -r panther-01 --yes
    """
    from panther_ops.cli.render import finish, print_results
    from panther_ops.core.fleet.runner import Connections, RunOptions, run_fleet
    from panther_ops.core.remote.estop.calls import reset_check_task, reset_task

    inv, chosen = context.targets(ctx, robot, group, all_, preload=_PRELOAD, tables=not json_out)
    opts = RunOptions(forks=max(1, len(chosen)))
    with Connections(inv) as conns:
        checked = run_fleet("estop reset", inv, chosen, reset_check_task, opts, connections=conns)
        ready_names = {r.robot for r in checked.results if r.data.get("ready")}
        ready = [r for r in chosen if r.name in ready_names]
        if dry_run or not ready:
            if not ready:
                checked.notes.append("no robot to reset")
            else:
                checked.notes.append(f"dry run: would reset {', '.join(r.name for r in ready)}")
            return finish(checked, json_out, print_results)
        if not json_out:
            print_results(checked, title="estop reset: checks")
        names = ", ".join(r.name for r in ready)
        if not _confirm(f"Reset the E-stop of {len(ready)} robot(s): {names}? They move again as soon as "
                        "velocity commands arrive.", yes):
            return 2
        done = run_fleet("estop reset", inv, ready, reset_task, opts, connections=conns)
    by_name = {r.robot: r for r in done.results}
    checked.results = [by_name.get(r.robot, r) for r in checked.results]
    checked.duration_s += done.duration_s
    return finish(checked, json_out, print_results)


def _confirm(question: str, yes: bool) -> bool:
    if yes:
        return True
    if not sys.stdin.isatty():
        from panther_ops.cli.render import error

        error(f"{question} -- resetting the E-stop needs confirmation: pass --yes when not interactive "
              "(or --dry-run to only check)")
        return False
    return bool(typer.confirm(question, default=False))


def _print_state(fleet: FleetResult) -> None:
    from rich.table import Table

    from panther_ops.cli.render import STYLE, _console, esc, print_summary, print_warnings

    table = Table(title=None, show_lines=False)
    for col in ("robot", "e-stop", "cmd_vel publishers", "namespace", "note"):
        table.add_column(col, overflow="fold")
    for r in fleet.results:
        e_stop = r.data.get("e_stop")
        shown = ("[red]triggered[/]" if e_stop is True else "[green]released[/]" if e_stop is False
                 else f"[{STYLE[r.outcome]}]{r.outcome.value}[/]")
        pubs = r.data.get("cmd_vel_publishers")
        note = "recorded (demo robot)" if r.data.get("recorded") else ("" if e_stop is not None else r.message)
        table.add_row(r.robot, shown, esc(", ".join(pubs) if pubs else ("none" if pubs == [] else "-")),
                      esc(r.data.get("namespace", "-")), esc(note))
    _console().print(table)
    print_warnings(fleet)
    print_summary(fleet)
