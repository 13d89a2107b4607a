"""`panther-ops trust ROBOT`: show a robot's host key fingerprint and record it on request."""

from __future__ import annotations

from typing import Annotated

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.options import shared


@shared("yes", "dry_run", "json_out", helps={"yes": "Record without asking.",
                                             "dry_run": "Only show the key and the edit of known_hosts."})
def trust(
    fleet: Fleet,
    name: Annotated[str, typer.Argument(help="Robot name from the inventory.")],
    replace: Annotated[
        bool, typer.Option("--replace", help="Replace a key that CHANGED (after checking it on the robot).")
    ] = False,
) -> int:
    """Show ROBOT's SSH host key fingerprint and record it in known_hosts when you confirm.

    Compare the fingerprint with the robot's own (on the robot:
    `ssh-keygen -lf /etc/ssh/ssh_host_ed25519_key.pub`). A changed key is refused unless
    --replace. Host keys are never accepted silently. A change as any other: the plan is the
    exact edit of your known_hosts file, written atomically with a backup beside it
    (.panther-ops/backups/); its subject is the host key, so nothing connects to the robot but
    to read the key it offers. --json: the change's document, the key, its state (new, known,
    changed) and the known fingerprints in the result's data.

    \b
    Example:
      panther-ops trust panther-07
    """
    from panther_ops.cli import context
    from panther_ops.cli.mutate import Asking
    from panther_ops.core.fleet.trust import read_and_plan_trust, trust_target

    inv = context.load(fleet.ctx)
    (robot,) = inv.select([name], [], False)[:1]
    target_inv, target = trust_target(inv, robot)
    asking = Asking(
        question=lambda _names, plans: f"{plans[robot.name].summary.capitalize()}?",
        refusal=lambda _q: "not recording: pass --yes when not interactive (or --dry-run to only look)",
        nothing="nothing was recorded")
    return fleet.change("trust", lambda c: read_and_plan_trust(c, inv, robot, replace), on=(target_inv, [target]),
                        restart=False, asking=asking)


def register(app: typer.Typer) -> None:
    app.command("trust")(trust)
