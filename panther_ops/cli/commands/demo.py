"""`panther-ops demo init`: the embedded demo fleet (no robot needed)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

app = typer.Typer(help="The embedded demo fleet: robots that are local directories.", no_args_is_help=True)


@app.command("init")
def init(
    dest: Annotated[Path, typer.Option("--dest", help="Where to create it.")] = Path("demo-fleet"),
    force: Annotated[bool, typer.Option("--force", help="Recreate it if it exists.")] = False,
) -> int:
    """Create a demo fleet of three robots (panther_ros 2.1.1 and 2.0.4, husarion_ugv 2.2.2),
    each a directory standing in for its Built-in Computer, and an inventory for them.

    Example: panther-ops demo init && panther-ops -i demo-fleet status --all
    """
    from panther_ops.core.demo.fleet import init_demo

    inventory = init_demo(dest, force=force)
    typer.echo(f"demo fleet created: {inventory}")
    typer.echo(f"try: panther-ops -i {dest} status --all")
    return 0
