"""`panther-ops manager run --sim`: the runtime manager's trees on a simulated Panther."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated, Any, Optional

import typer

from panther_ops.cli.options import Json

app = typer.Typer(help="The runtime manager (Lights, Safety and Shutdown behaviour trees).", no_args_is_help=True)


@app.command("run")
def run(
    sim: Annotated[bool, typer.Option("--sim", help="Run on the simulated Panther (the only mode off-robot).")] = False,
    scenario: Annotated[
        Optional[Path],  # noqa: UP045
        typer.Option("--scenario", help="Scenario YAML (timed events); default: the shipped charging scenario."),
    ] = None,
    duration: Annotated[
        Optional[float],  # noqa: UP045
        typer.Option("--duration", min=0.1, help="Simulated seconds (default: the scenario's)."),
    ] = None,
    speed: Annotated[float, typer.Option("--speed", min=0.1, help="Simulated seconds per real second.")] = 1.0,
    xml: Annotated[bool, typer.Option("--xml", help="Run the shipped BT.CPP XML trees instead of the Python trees.")]
    = False,
    lights_bt: Annotated[
        Optional[Path],  # noqa: UP045
        typer.Option("--lights-bt", help="A Lights .btproj to run (with --safety-bt)."),
    ] = None,
    safety_bt: Annotated[
        Optional[Path],  # noqa: UP045
        typer.Option("--safety-bt", help="A Safety .btproj to run (with --lights-bt)."),
    ] = None,
    json_out: Json = False,
) -> int:
    """Tick the Lights and Safety trees at 10 Hz against a simulated Panther (linear battery,
    temperatures, e-stop, fan, AUX, charger) driven by a scenario, and show both bumpers,
    battery, temperatures, fan/AUX/e-stop and each tree's active branch live in the terminal.
    With --json, one JSON line per tick (a snapshot) instead; when stdout is not a terminal the
    simulation runs as fast as it can and prints one line per simulated second.

    Examples:
      panther-ops manager run --sim --scenario templates/manager/scenarios/battery_overheat.yaml --speed 10
      panther-ops manager run --sim --xml --duration 30 --json | jq .calls
    """
    from panther_ops.core.templates import template_path
    from panther_ops.errors import UsageError
    from panther_ops.manager import ManualClock, TreeSource, run_simulation
    from panther_ops.manager.clock import ScaledClock

    if not sim:
        raise UsageError("off the robot the manager runs only in simulation: add --sim",
                         hint="on a robot it runs as a compose service: panther-ops manager deploy")
    path = scenario or template_path("manager", "scenarios", "charging.yaml")
    if (lights_bt is None) != (safety_bt is None):
        raise UsageError("--lights-bt and --safety-bt go together")
    if lights_bt and safety_bt:
        trees = TreeSource.projects(lights_bt, safety_bt)
    elif xml:
        trees = TreeSource.projects(template_path("behavior_trees", "PantherLightsBT.btproj"),
                                    template_path("behavior_trees", "PantherSafetyBT.btproj"))
    else:
        trees = TreeSource.python()
    # Nobody watches a pipe: there the simulation runs as fast as it can.
    clock: Any = ManualClock() if json_out or not sys.stdout.isatty() else ScaledClock(speed)
    snapshots = run_simulation(path, trees=trees, clock=clock, duration=duration)
    if json_out:
        import dataclasses
        import json

        for snap in snapshots:
            sys.stdout.write(json.dumps(dataclasses.asdict(snap), default=str) + "\n")
        return 0
    from panther_ops.cli.sim_view import live

    return live(snapshots, str(path))
