"""`panther-ops sim ...`: the manual's simulation steps on local files (GPS in simulation, the
battery plugin)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated, Any, Optional

import typer

from panther_ops.cli.options import DryRun, Json, Yes, real_number

app = typer.Typer(help="Simulation files: the ANT02 (GPS) component, a world's spherical coordinates, the battery "
                       "plugin.", no_args_is_help=True)
gps_app = typer.Typer(help="GPS in simulation (manual: Use of GPS in Simulation).", no_args_is_help=True)
world_app = typer.Typer(help="A world SDF's <spherical_coordinates> (the NavSat origin).", no_args_is_help=True)
battery_app = typer.Typer(help="The LinearBatteryPlugin file (battery_plugin_config.yaml).", no_args_is_help=True)
app.add_typer(gps_app, name="gps")
app.add_typer(world_app, name="world")
app.add_typer(battery_app, name="battery")

File = Annotated[Path, typer.Argument(help="The file (on this machine).")]


def _read(path: Path) -> str:
    from panther_ops.core.sim.files import read_text

    return read_text(path)


def _write(path: Path, before: str, after: str, what: str, command: str, *, yes: bool, dry_run: bool,
           json_out: bool) -> int:
    """Show the exact diff, confirm, then write atomically with a backup beside the file."""
    from panther_ops.cli.mutate import require
    from panther_ops.cli.render import emit_json, print_diffs, print_warnings
    from panther_ops.core.yaml.diff import unified_diff
    from panther_ops.results import Diff, FleetResult, Outcome, RobotResult

    changed = after != before
    planned = dry_run and changed  # said as the fleet commands' dry runs say it: would change
    res = RobotResult("local", Outcome.CHANGED if changed else Outcome.OK, ("would change: " if planned else "") + what,
                      diffs=[Diff(str(path), unified_diff(before, after, str(path)))] if changed else [],
                      data={"dry_run": True} if planned else {})
    fleet = FleetResult(command, [res], notes=["dry run: nothing was written"] if dry_run else [])
    if changed and not json_out:
        print_diffs(fleet)
    if changed and not dry_run:
        require(f"Write {path}?", yes,
                "changes need confirmation: pass --yes when not interactive (or --dry-run to only look)")
        from panther_ops.core.sim.files import write_text

        res.data["backup"] = str(write_text(path, after))
    if json_out:
        emit_json(fleet.to_json())
    else:
        sys.stdout.write(f"{path}: {res.message}\n" if planned else f"{path}: {res.outcome.value}: {res.message}\n")
        print_warnings(fleet)
    return 0


@gps_app.command("add")
def gps_add(
    file: File,
    xyz: Annotated[str, typer.Option("--xyz", help="Position on the parent link, \"x y z\" [m].")] = "0.185 -0.12 0.0",
    rpy: Annotated[str, typer.Option("--rpy", help="Orientation, \"r p y\" [rad].")] = "0.0 0.0 3.14",
    parent_link: Annotated[str, typer.Option("--parent-link", help="Link it is mounted on.")] = "cover_link",
    device_namespace: Annotated[str, typer.Option("--device-namespace", help="Its namespace (gps).")] = "gps",
    yes: Yes = False,
    dry_run: DryRun = False,
    json_out: Json = False,
) -> int:
    """Add the ANT02 (Wi-Fi/LTE/GPS antenna) to a components.yaml: the manual's entry (type
    ANT02, parent_link cover_link, xyz 0.185 -0.12 0.0, rpy 0.0 0.0 3.14, device_namespace
    gps), the rest of the file kept. An ANT02 entry already there gets these values.

    \b
    Example:
      panther-ops sim gps add components.yaml --dry-run
    """
    from panther_ops.core.sim.components import add_ant02, check_triple

    entry = {"type": "ANT02", "parent_link": parent_link, "xyz": check_triple(xyz, "--xyz"),
             "rpy": check_triple(rpy, "--rpy"), "device_namespace": device_namespace}
    before = _read(file)
    after, what = add_ant02(before, str(file), entry)
    return _write(file, before, after, what, "sim gps add", yes=yes, dry_run=dry_run, json_out=json_out)


@world_app.command("show")
def world_show(file: File, json_out: Json = False) -> int:
    """The world's <spherical_coordinates> (surface_model must be EARTH_WGS84), and what the
    world file kind's validator finds wrong in it (a latitude out of range, degrees-minutes-
    seconds instead of decimal degrees...), each with its fix: exit 3 then."""
    from panther_ops.core.sim.world import problems, read_coordinates

    text = _read(file)
    found = read_coordinates(text, str(file))
    wrong = problems(text, str(file))
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "command": "sim world show", "file": str(file), "spherical_coordinates": found,
                   "problems": wrong})
    elif not found["present"]:
        sys.stdout.write(f"{file}: no <spherical_coordinates> (NavSat needs one: panther-ops sim world set)\n")
    else:
        for k, v in found.items():
            if k not in ("present", "surface_model_ok"):
                sys.stdout.write(f"{k}: {v}\n")
    if not json_out:
        for problem in wrong:
            sys.stderr.write(f"warning: {problem}\n")
    return 3 if wrong else 0


def _opt(name: str, help_: str) -> Any:
    return typer.Option(f"--{name}", parser=real_number(), help=help_)


@world_app.command("set")
def world_set(
    file: File,
    lat: Annotated[Optional[float], _opt("latitude", "Latitude [deg], -90..90.")] = None,  # noqa: UP045
    lon: Annotated[Optional[float], _opt("longitude", "Longitude [deg], -180..180.")] = None,  # noqa: UP045
    elevation: Annotated[Optional[float], _opt("elevation", "Elevation [m].")] = None,  # noqa: UP045
    heading: Annotated[Optional[float], _opt("heading", "Heading [deg].")] = None,  # noqa: UP045
    yes: Yes = False,
    dry_run: DryRun = False,
    json_out: Json = False,
) -> int:
    """Set the world origin's latitude, longitude, elevation, heading; only those texts change.
    A world without <spherical_coordinates> gets the manual's block first.

    \b
    Example:
      panther-ops sim world set my_world.sdf --latitude 52.2297 --longitude 21.0122 --yes
    """
    from panther_ops.core.sim.world import set_coordinates
    from panther_ops.errors import UsageError

    values = {k: v for k, v in (("latitude", lat), ("longitude", lon), ("elevation", elevation),
                                ("heading", heading)) if v is not None}
    if not values:
        raise UsageError("nothing to set", hint="--latitude, --longitude, --elevation, --heading")
    before = _read(file)
    after = set_coordinates(before, str(file), values)
    what = ", ".join(f"{k} {v:g}" for k, v in values.items())
    return _write(file, before, after, what, "sim world set", yes=yes, dry_run=dry_run, json_out=json_out)


@battery_app.command("check")
def battery_check(file: File, json_out: Json = False) -> int:
    """Check the battery plugin file: simulate_discharging a boolean, initial_charge_percentage
    0-100 (the 0-1 form of panther_ros 2.1.1 reported), charging_time, power_load and capacity
    positive. Bad file: exit 2 naming the key."""
    from ruamel.yaml import YAML

    from panther_ops.core.sim.battery import validate_battery

    text = _read(file)
    notes = validate_battery(text.encode(), str(file))
    doc = YAML(typ="safe", pure=True).load(text)
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "command": "sim battery check", "file": str(file), "valid": True, "notes": notes,
                   "values": doc})
    else:
        sys.stdout.write(f"{file}: valid\n")
        for n in notes:
            sys.stderr.write(f"note: {n}\n")
    return 0


@battery_app.command("charge")
def battery_charge(
    action: Annotated[str, typer.Argument(help="start or stop charging.")],
    robot_model: Annotated[str, typer.Option("--robot-model", help="panther or lynx (the model's name when the "
                                             "simulation has no namespace).")] = "panther",
    namespace: Annotated[str, typer.Option("--namespace", help="The simulation's ROS namespace, if any (the "
                                           "model is spawned under it).")] = "",
    tool: Annotated[str, typer.Option("--tool", help="Gazebo's CLI: ign (Humble, Fortress) or gz (Jazzy, "
                                      "Harmonic).")] = "ign",
    yes: Yes = False,
    dry_run: DryRun = False,
    json_out: Json = False,
) -> int:
    """Start or stop charging the simulated battery: the LinearBatteryPlugin's recharge service,
    called as Husarion's manual does (`ign service --service /model/panther/battery/battery/
    recharge/start ... --timeout 0`), on this machine, where the simulation runs. The plan shows
    the exact command; it asks (or --yes); --dry-run only shows it. The service must be among
    those the simulation serves (`ign service --list`), else exit 3 naming the ones it has.

    \b
    Examples:
      panther-ops sim battery charge start --yes
      panther-ops sim battery charge stop --namespace panther --yes
    """
    from panther_ops.cli.mutate import require
    from panther_ops.cli.render import emit_json, error
    from panther_ops.core.sim.plan import plan_charge
    from panther_ops.transport.base import quote_command

    call = plan_charge(action, robot_model, namespace, tool)
    shown = quote_command(call.argv, reveal=True)
    doc: dict[str, Any] = {"schema": 1, "command": "sim battery charge", "action": call.action,
                           "service": call.service, "argv": list(call.argv), "dry_run": dry_run}
    if dry_run:
        if json_out:
            emit_json({**doc, "outcome": "changed", "exit_code": 0})
        else:
            sys.stdout.write(f"would run: {shown}\nnote dry run: nothing was called\n")
        return 0
    if not yes:
        if sys.stdin.isatty():
            sys.stdout.write(f"{shown}\n")
        require(f"{call.action.capitalize()} charging?", yes,
                "this calls the simulation: pass --yes when not interactive (or --dry-run to only look)",
                "nothing was called")
    from panther_ops.core.sim.plan import missing_service
    from panther_ops.transport.local_command import run_local

    listed = run_local(call.listing)
    why = missing_service(call, listed.stdout) if listed.ok else f"{shown}: cannot list services: {listed.stderr}"
    if why is not None:
        if json_out:
            emit_json({**doc, "outcome": "failed", "output": why, "exit_code": 3})
        else:
            error(why)
        return 3
    res = run_local(call.argv)
    said = (res.stdout + res.stderr).strip()
    # --timeout 0, as documented: the request is sent and the CLI does not wait for an answer
    # (it says "Service call timed out"); anything else it says is an error.
    ok = res.ok and said in ("", "Service call timed out")
    if json_out:
        emit_json({**doc, "outcome": "changed" if ok else "failed", "output": said, "exit_code": 0 if ok else 3})
    elif ok:
        sys.stdout.write(f"charging {call.action}: sent to {call.service}\n"
                         "check: ros2 topic echo battery/battery_status (power_supply_status 1 = charging)\n")
    else:
        error(f"{call.argv[0]} service failed (exit {res.exit_status}): {said[-400:]}")
    return 0 if ok else 3
