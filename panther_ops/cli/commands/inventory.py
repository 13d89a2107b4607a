"""`panther-ops inventory list|show|validate`."""

from __future__ import annotations

from typing import Annotated, Any

import typer

from panther_ops.cli import complete, context
from panther_ops.cli.context import Fleet
from panther_ops.cli.options import TARGETS, Json, shared

app = typer.Typer(help="Read and check the inventory (nothing is contacted).", no_args_is_help=True)


def _robot_json(r: Any, inv: Any) -> dict[str, Any]:
    return {
        "name": r.name,
        "host": r.host,
        "port": r.port,
        "user": r.user,
        "transport": r.transport,
        "root": str(r.root) if r.root else None,
        "jump": r.jump,
        "identity_file": r.identity_file,
        "namespace": r.namespace,
        "stack": r.stack,
        "groups": list(r.groups),
        "compose_file": r.compose_file,
        "vars": r.vars,
        "desired": r.desired,
        "defined_at": r.source,
    }


@app.command("list")
@shared(*TARGETS, "json_out")
def list_(fleet: Fleet) -> int:
    """List robots with how each is reached. With no selection, every robot is listed.

    \b
    Example:
      panther-ops inventory list -g warehouse
    """
    inv = context.load(fleet.ctx)
    robot, group = fleet.robot or [], fleet.group or []
    chosen = inv.select(robot, group, fleet.all_ or not (robot or group))
    if fleet.json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "inventory": str(inv.path), "origin": inv.origin,
                   "robots": [_robot_json(r, inv) for r in chosen], "groups": sorted(inv.groups)})
        return 0
    from panther_ops.cli.views.inventory import print_robots

    print_robots(inv, chosen)
    return 0


@app.command("show")
def show(
    ctx: typer.Context,
    name: Annotated[str, typer.Argument(help="Robot name.", autocompletion=complete.robot)],
    json_out: Json = False,
) -> int:
    """Show one robot with defaults and group values applied (its effective desired state).

    \b
    Example:
      panther-ops inventory show panther-01
    """
    inv = context.load(ctx)
    (robot,) = inv.select([name], [], False)[:1]
    doc = _robot_json(robot, inv)
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "robot": doc})
        return 0
    import yaml

    if robot.transport == "local":  # a directory standing in for the robot: no SSH address to show
        for key in ("host", "port", "jump", "identity_file"):
            doc.pop(key, None)
    typer.echo(yaml.safe_dump(doc, sort_keys=False).rstrip())
    return 0


@app.command("validate")
def validate(ctx: typer.Context, json_out: Json = False) -> int:
    """Check the inventory: syntax, keys, values, groups, jump hosts, no plaintext secrets, and
    that every robot's identity_file is a readable file here.

    Errors name the file, line and key, with what is allowed; exit code 2.

    \b
    Example:
      panther-ops -i inventory/ inventory validate
    """
    inv = context.load(ctx)
    context.check_keys(inv, list(inv.robots.values()))
    from panther_ops.cli.render import counted

    msg = f"{inv.path}: {counted(len(inv.robots), 'robot')}, {counted(len(inv.groups), 'group')}, valid"
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "inventory": str(inv.path), "valid": True, "robots": len(inv.robots),
                   "groups": len(inv.groups), "files": [str(f) for f in inv.files]})
    else:
        typer.echo(msg)
    return 0


@app.command("export")
def export(
    ctx: typer.Context,
    ansible: Annotated[bool, typer.Option("--ansible", help="As an Ansible YAML inventory (the one format so far).")]
    = False,
    out: Annotated[str | None, typer.Option("--out", "-o", help="Write it to this file (atomically), "
                                            "not to standard output.")] = None,
) -> int:
    """Write the inventory as an Ansible inventory: each robot a host (ansible_host, ansible_port,
    ansible_user, ansible_ssh_private_key_file, panther_ops_<key> for the rest), each group a child
    of `all`, the known_hosts files as panther_ops_known_hosts. `-i` reads it back (docs/ansible.md).

    \b
    Example:
      panther-ops inventory export --ansible -o hosts.yaml
    """
    from panther_ops.errors import UsageError

    if not ansible:
        raise UsageError("choose the format to export", hint="--ansible (an Ansible YAML inventory)")
    import yaml

    from panther_ops.core.fleet.inventory_ansible import export_ansible

    inv = context.load(ctx)
    text = yaml.safe_dump(export_ansible(inv), sort_keys=False, default_flow_style=False)
    if out is None:
        typer.echo(text, nl=False)
        return 0
    from pathlib import Path

    from panther_ops.transport.localfile import write_atomic

    write_atomic(Path(out), text.encode())
    context.info(f"wrote {out}")
    return 0
