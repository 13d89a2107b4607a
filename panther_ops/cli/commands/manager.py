"""`panther-ops manager run --sim` (the trees on a simulated Panther, here) and
`manager deploy|remove|status|logs` (the manager as a compose service on robots)."""

from __future__ import annotations

import sys
from typing import Annotated, Any

import typer

from panther_ops.cli import complete
from panther_ops.cli.context import Fleet
from panther_ops.cli.options import (
    READ,
    RECREATE,
    TARGETS,
    Follow,
    Json,
    Lines,
    OptBool,
    OptFloat,
    OptPath,
    OptStr,
    Timestamps,
    real_number,
    shared,
)

app = typer.Typer(help="The runtime manager (Lights, Safety and Shutdown behaviour trees).", no_args_is_help=True)


@app.command("run")
def run(
    sim: Annotated[bool, typer.Option("--sim", help="Run on the simulated Panther (the only mode off-robot).")] = False,
    scenario: Annotated[OptStr, typer.Option(
        "--scenario", help="A shipped scenario (charging, low_battery, ...) or a scenario YAML file (timed events); "
        "default: charging.", autocompletion=complete.scenarios)] = None,
    duration: Annotated[OptFloat, typer.Option("--duration", parser=real_number(0.1),
                                               help="Simulated seconds (default: the scenario's).")] = None,
    speed: Annotated[float, typer.Option("--speed", parser=real_number(0.1),
                                         help="Simulated seconds per real second.")] = 1.0,
    xml: Annotated[bool, typer.Option("--xml", help="Run the shipped BT.CPP XML trees instead of the Python trees.")]
    = False,
    lights_bt: Annotated[OptPath, typer.Option("--lights-bt",
                                               help="A Lights .btproj to run (with --safety-bt).")] = None,
    safety_bt: Annotated[OptPath, typer.Option("--safety-bt",
                                               help="A Safety .btproj to run (with --lights-bt).")] = None,
    json_out: Json = False,
) -> int:
    """Tick the Lights and Safety trees at 10 Hz against a simulated Panther (linear battery,
    temperatures, e-stop, fan, AUX, charger) driven by a scenario, and show both bumpers,
    battery, temperatures, fan/AUX/e-stop and each tree's active branch live in the terminal.
    With --json, one JSON document with a snapshot per tick instead; when stdout is not a terminal the
    simulation runs as fast as it can and prints one line per simulated second.

    \b
    Examples:
      panther-ops manager run --sim --scenario battery_overheat --speed 10
      panther-ops manager run --sim --xml --duration 30 --json | jq '.snapshots[].calls'
    """
    from panther_ops.core.fleet.templates import template_path
    from panther_ops.errors import UsageError
    from panther_ops.manager import ManualClock, TreeSource, run_simulation
    from panther_ops.manager.clock import ScaledClock

    if not sim:
        raise UsageError("off the robot the manager runs only in simulation: add --sim",
                         hint="on a robot it runs as a compose service: panther-ops manager deploy")
    from panther_ops.core.manager_ops.settings import scenario_path
    from panther_ops.manager import load_scenario

    path = scenario_path(scenario or "charging")
    loaded = load_scenario(path)  # the one scenario validator: a bad file is refused before anything runs
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
    snapshots = run_simulation(loaded, trees=trees, clock=clock, duration=duration)
    if json_out:
        import dataclasses

        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "command": "manager run --sim", "scenario": loaded.name, "source": str(path),
                   "snapshots": [dataclasses.asdict(snap) for snap in snapshots]})
        return 0
    from panther_ops.cli.views.sim import live

    return live(snapshots, f"scenario {loaded.name}")


# ------------------------------------------------------------------ deploy / remove on robots


@app.command("deploy")
@shared(*RECREATE, "canary", "max_fail")
def deploy(
    fleet: Fleet,
    sim: Annotated[OptBool, typer.Option(
        "--sim/--ros2", help="Simulation adapter (labs) or the robot's ROS 2 graph; default: desired.manager.mode, "
        "else ros2.")] = None,
    scenario: Annotated[OptStr, typer.Option(
        "--scenario", help="With --sim: a shipped scenario (charging, low_battery, ...) or a file.",
        autocompletion=complete.scenarios)] = None,
) -> int:
    """Install the runtime manager on each robot as the compose service panther_ops_manager, on
    the robot's own driver image, and set disable_manager:=True on the driver so the stock
    lights/safety managers stand down — one change through the pipeline: diff, confirm, backup,
    atomic writes, recreate, verify both containers stay up, roll back. Uploads the manager
    (one archive with py_trees and PyYAML) under ~/panther-ops/manager/<version>/, its
    parameters (desired.manager.params), the BT projects and deployed.json. A second deploy
    of the same version reports ok; a newer panther-ops replaces the archive.

    Refused on panther_ros 2.0.0 (no disable_manager). See docs/manager-deploy.md.

    \b
    Examples:
      panther-ops manager deploy -r panther-01 --dry-run
      panther-ops manager deploy -g warehouse --canary 1 --yes
      panther-ops manager deploy -r lab-r02 --sim --scenario low_battery --yes
    """
    from panther_ops.core.manager_ops.apply import apply_manager
    from panther_ops.core.manager_ops.bundle import build_bundle
    from panther_ops.core.manager_ops.read import read_and_plan_deploy
    from panther_ops.core.manager_ops.settings import scenario_path

    if scenario is not None:  # checked once, here, whichever robots it would go to
        from panther_ops.manager import load_scenario

        load_scenario(scenario_path(scenario))
    bundle = build_bundle()
    label = "manager deploy" + ("" if sim is None else (" --sim" if sim else " --ros2"))
    return fleet.change(label, lambda c: read_and_plan_deploy(c, sim=sim, scenario=scenario, bundle=bundle),
                        applier=apply_manager)


@app.command("remove")
@shared(*RECREATE)
def remove(fleet: Fleet) -> int:
    """Undo `manager deploy`: stop and delete the panther_ops_manager container, take the service
    out of compose.yaml, put disable_manager back as it was before the first deploy (compose.yaml
    byte-identical to before), delete the uploaded files, recreate the driver so the stock
    manager runs again — through the pipeline, rolled back if the driver does not stay up.

    \b
    Example:
      panther-ops manager remove -r panther-01 --yes
    """
    from panther_ops.core.manager_ops.apply import apply_manager
    from panther_ops.core.manager_ops.read import read_and_plan_remove

    return fleet.change("manager remove", read_and_plan_remove, applier=apply_manager)


@app.command("status")
@shared(*READ)
def status(fleet: Fleet) -> int:
    """The deployed manager on each robot: service in compose.yaml, container state, uptime and
    restart count (docker on the robot's own connection), the version deployed (deployed.json)
    and the one the container runs, and whether disable_manager is set on the driver.

    `failed` (exit 3) when the service's container is not running, or when it runs while
    disable_manager is not set (two managers would drive the same lights and E-stop).

    \b
    Example:
      panther-ops manager status --all
    """
    from panther_ops.cli.views.manager import print_status
    from panther_ops.core.manager_ops.status import status_task

    return fleet.run("manager status", status_task, print_status, read_only=True)


@app.command("logs")
@shared(*TARGETS, "json_out")
def logs(
    fleet: Fleet,
    lines: Lines = None,
    follow: Follow = False,
    timestamps: Timestamps = False,
) -> int:
    """The manager container's output (`docker logs panther_ops_manager`): its start line, and in
    simulation every service call and a status line every 10 s. With several robots every line
    starts with `<robot> | `.

    \b
    Examples:
      panther-ops manager logs -r panther-01 -n 20
      panther-ops manager logs -r panther-01 -f
    """
    from panther_ops.cli.views.logs import show_logs
    from panther_ops.core.manager_ops.status import open_logs

    inv, chosen = fleet.targets(read_only=not follow)  # reading every robot; following one is chosen
    return show_logs("manager logs", inv, chosen, open_logs, lines=lines, since_s=None, timestamps=timestamps,
                     follow=follow, json_out=fleet.json_out)
