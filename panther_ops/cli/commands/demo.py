"""`panther-ops demo init`: the embedded demo fleet (no robot needed)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from panther_ops.cli.options import Json

app = typer.Typer(help="The embedded demo fleet: robots that are local directories.", no_args_is_help=True)


@app.command("init")
def init(
    dest: Annotated[Path, typer.Option("--dest", help="Where to create it.")] = Path("demo-fleet"),
    force: Annotated[bool, typer.Option("--force", help="Recreate it if it exists.")] = False,
    json_out: Json = False,
) -> int:
    """Create a demo fleet of four robots (panther_ros 2.1.1 and 2.0.4, husarion_ugv 2.2.2 and
    2.3.2), each a directory standing in for its Built-in Computer, and an inventory for them. It
    prints the `export PANTHER_OPS_INVENTORY=...` line that makes it the inventory in use (no
    -i needed then).

    \b
    Examples:
      panther-ops demo init
      panther-ops -i demo-fleet status --all
    """
    import shlex

    from panther_ops.core.demo.fleet import init_demo
    from panther_ops.core.fleet.inventory_file import ENV_VAR

    inventory = init_demo(dest, force=force)
    export = f"export {ENV_VAR}={shlex.quote(str(dest.resolve()))}"
    if json_out:
        from panther_ops.cli.render import emit_json
        from panther_ops.core.fleet.inventory_file import load_inventory

        inv = load_inventory(str(dest))
        emit_json({"schema": 1, "command": "demo init", "dest": str(dest), "inventory": str(inventory),
                   "robots": list(inv.robots), "export": export, "next": f"panther-ops -i {dest} status --all"})
        return 0
    typer.echo(f"demo fleet created: {inventory}")
    typer.echo("make it the inventory in use in this shell (then no -i is needed):")
    typer.echo(export)
    typer.echo("try: panther-ops status --all")
    return 0
