"""`panther-ops estop status|trigger|reset`: the driver's E-stop, through its ROS API."""

from __future__ import annotations

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.options import TARGETS, shared

app = typer.Typer(help="The E-stop: see it, trigger it (all targeted robots at once), reset it.",
                  no_args_is_help=True)



@app.command("status")
@shared(*TARGETS, "json_out")
def status(fleet: Fleet) -> int:
    """Each robot's E-stop (the driver's hardware/e_stop topic) and the nodes publishing on
    cmd_vel, asked inside the driver container in the robot's namespace.

    \b
    Example:
      panther-ops estop status --all
    """
    from panther_ops.cli.views.estop import print_state
    from panther_ops.core.remote.estop.calls import status_task

    return fleet.run("estop status", status_task, print_state, at_once=True, read_only=True)


@app.command("trigger")
@shared(*TARGETS, "json_out")
def trigger(fleet: Fleet) -> int:
    """Trigger the E-stop (hardware/e_stop_trigger) on every targeted robot at once: an
    emergency, so no confirmation, no fork limit, all connections opened in parallel; the
    driver's answer per robot. Exit 3 when any robot did not confirm.

    \b
    Example:
      panther-ops estop trigger --all
    """
    from panther_ops.core.remote.estop.calls import trigger_task

    # every robot at once; no progress bar
    return fleet.show(fleet.results("estop trigger", trigger_task, at_once=True, progress=False))


@app.command("reset")
@shared(*TARGETS, "yes", "dry_run", "json_out", helps={
    "yes": "Reset without asking (needed when not interactive).",
    "dry_run": "Only check: state and cmd_vel publishers."})
def reset(fleet: Fleet) -> int:
    """Reset the E-stop (hardware/e_stop_reset). First checks every robot: a robot where a
    node publishes on cmd_vel is refused, naming the node (the manual: a reset is impossible
    while messages arrive); a robot whose E-stop is not triggered is left alone. Then names
    each robot to be reset and asks (--yes), resets them and reads the E-stop back.

    \b
    Example:
      panther-ops estop reset -r panther-01 --yes
    """
    from panther_ops.cli.mutate import require
    from panther_ops.cli.render import print_results
    from panther_ops.core.fleet.runner import Connections, RunOptions, run_fleet
    from panther_ops.core.remote.estop.calls import reset_check_task, reset_task

    inv, chosen = fleet.targets()
    opts = RunOptions(forks=max(1, len(chosen)))
    with Connections(inv) as conns:
        checked = run_fleet("estop reset", inv, chosen, reset_check_task, opts, connections=conns)
        ready_names = {r.robot for r in checked.results if r.data.get("ready")}
        ready = [r for r in chosen if r.name in ready_names]
        if fleet.dry_run or not ready:
            if not ready:
                checked.notes.append("no robot to reset")
            else:
                checked.notes.append(f"dry run: would reset {', '.join(r.name for r in ready)}")
            return fleet.show(checked)
        if not fleet.json_out:
            print_results(checked, title="estop reset: checks")
        names = ", ".join(r.name for r in ready)
        question = (f"Reset the E-stop of {len(ready)} robot(s): {names}? They move again as soon as velocity "
                    "commands arrive.")
        require(question, fleet.yes, f"{question} -- resetting the E-stop needs confirmation: pass --yes "
                "when not interactive (or --dry-run to only check)", "nothing was reset")
        done = run_fleet("estop reset", inv, ready, reset_task, opts, connections=conns)
    by_name = {r.robot: r for r in done.results}
    checked.results = [by_name.get(r.robot, r) for r in checked.results]
    checked.duration_s += done.duration_s
    return fleet.show(checked)
