"""`panther-ops trust ROBOT`: show a robot's host key fingerprint and record it on request."""

from __future__ import annotations

from typing import Annotated

import typer

from panther_ops.cli import context
from panther_ops.cli.options import Json


def trust(
    ctx: typer.Context,
    name: Annotated[str, typer.Argument(help="Robot name from the inventory.")],
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Record without asking.")] = False,
    replace: Annotated[
        bool, typer.Option("--replace", help="Replace a key that CHANGED (after checking it on the robot).")
    ] = False,
    json_out: Json = False,
) -> int:
    """Show ROBOT's SSH host key fingerprint and record it in known_hosts when you confirm.

    Compare the fingerprint with the robot's own (on the robot:
    `ssh-keygen -lf /etc/ssh/ssh_host_ed25519_key.pub`). A changed key is refused unless
    --replace. Host keys are never accepted silently. --json: the key, its state (new, known,
    changed) and whether it was recorded (the messages on stderr).

    \b
    Example:
      panther-ops trust panther-07
    """
    from panther_ops.cli.mutate import require
    from panther_ops.core.fleet.trust import plan_trust, record
    from panther_ops.errors import HostKeyError

    inv = context.load(ctx)
    (robot,) = inv.select([name], [], False)[:1]
    plan = plan_trust(inv, robot)

    def done(recorded: bool, said: str) -> int:
        typer.echo(said, err=json_out)
        if json_out:
            from panther_ops.cli.render import emit_json

            emit_json({"schema": 1, "command": "trust", "robot": plan.robot, "address": plan.address,
                       "key_type": plan.key_type, "fingerprint": plan.fingerprint, "state": plan.state,
                       "known_hosts_file": str(plan.known_hosts_file),
                       "known_fingerprints": list(plan.known_fingerprints), "recorded": recorded})
        return 0

    typer.echo(f"{plan.robot} ({plan.address}) offers {plan.key_type} {plan.fingerprint}", err=json_out)
    if plan.state == "known":
        return done(False, f"already trusted in {plan.known_hosts_file}")
    if plan.state == "changed":
        typer.echo(f"WARNING: {plan.known_hosts_file} has a different key: {', '.join(plan.known_fingerprints)}",
                   err=True)
        if not replace:
            raise HostKeyError(robot.name, "host key changed: refused",
                               offered=plan.fingerprint, expected=", ".join(plan.known_fingerprints),
                               hint="if you reinstalled the robot and checked the fingerprint on it: "
                               f"panther-ops trust {robot.name} --replace")
    require(f"Record this key in {plan.known_hosts_file}?", yes, "not recording: pass --yes when not interactive",
            "nothing was recorded")
    record(plan)
    return done(True, f"recorded in {plan.known_hosts_file}")


def register(app: typer.Typer) -> None:
    app.command("trust")(trust)
