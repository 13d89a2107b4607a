"""`panther-ops bt validate FILE`: check a BehaviorTree project before deploying it."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from panther_ops.cli.options import Json

app = typer.Typer(help="BehaviorTree projects (BT.CPP v4 / Groot2) of the Lights and Safety managers.",
                  no_args_is_help=True)


@app.command("validate")
def validate(
    file: Annotated[Path, typer.Argument(help="A .btproj (with the XML files it includes) or one .xml file.")],
    json_out: Json = False,
) -> int:
    """Check a BT project: the required trees (Lights; or Safety and Shutdown), known nodes and
    ports, literal values and script expressions, service names (ROS names by rcl's rules);
    warns when a custom Safety tree drops one of the default safety behaviours (the manual's
    caution). Exit 2 when it would be refused.

    \b
    Example:
      panther-ops bt validate my_trees/PantherSafetyBT.btproj
    """
    from panther_ops.cli.views.findings import report_findings
    from panther_ops.core.kinds.bt import service_name_findings
    from panther_ops.manager import validate_bt_project

    findings = validate_bt_project(file) + service_name_findings(file)
    return report_findings(str(file), findings, json_out=json_out, what="BT project")
