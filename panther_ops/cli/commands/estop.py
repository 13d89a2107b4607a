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
    """Reset the E-stop (hardware/e_stop_reset). First checks every robot: its E-stop and the
    nodes publishing velocity commands; a robot whose E-stop is not triggered is left alone.
    Then names each robot to be reset and asks (--yes), resets them and reads the E-stop back.
    The driver refuses a reset while the last velocity command is not zero (a node sending zero
    does not block it); its refusal names the publishers to stop.

    \b
    Example:
      panther-ops estop reset -r panther-01 --yes
    """
    from panther_ops.cli.mutate import Asking
    from panther_ops.core.remote.estop.calls import read_and_plan_reset

    warning = "They move again as soon as velocity commands arrive."
    asking = Asking(
        question=lambda names, _plans: f"Reset the E-stop of {len(names)} robot(s): {', '.join(names)}? {warning}",
        refusal=lambda question: f"{question} -- resetting the E-stop needs confirmation: pass --yes when not "
                                 "interactive (or --dry-run to only check)",
        nothing="nothing was reset",
        dry_note=lambda names: f"dry run: would reset {', '.join(names)}" if names else "no robot to reset",
        idle="no robot to reset")
    return fleet.change("estop reset", read_and_plan_reset, asking=asking, restart=False)
