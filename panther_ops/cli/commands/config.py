"""`panther-ops config ...` and `panther-ops apply`: the robot's launch arguments and files."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from panther_ops.cli import complete
from panther_ops.cli.context import Fleet
from panther_ops.cli.options import (
    GATED,
    READ,
    TARGETS,
    WRITE,
    AskPassword,
    Force,
    LocalFile,
    OptPath,
    OptStr,
    shared,
    sudo_password,
)

app = typer.Typer(
    help="The robot's configuration: launch arguments, controller limits, config files, history.",
    no_args_is_help=True,
)

"""What planning a change imports: loaded in the background while the robots connect."""

KeyArg = Annotated[str, typer.Argument(help="Launch argument (e.g. wheel_type) or controller.<axis>.<limit>.",
                                       autocompletion=complete.config_keys)]


@app.command("get")
@shared(*READ)
def get(fleet: Fleet, key: KeyArg) -> int:
    """Show KEY on each robot: the value in its compose.yaml command (or controller file), else the
    stack's default, with where it came from. No robot chosen: every robot of the inventory.

    \b
    Example:
      panther-ops config get wheel_type --all
    """
    from panther_ops.core.config.checks import precheck_key
    from panther_ops.core.config.read import read_arg
    from panther_ops.results import Outcome, RobotResult

    precheck_key(key)

    def task(c: Any) -> RobotResult:
        info = read_arg(c, key)
        if info.get("unavailable"):
            return RobotResult(c.robot.name, Outcome.SKIPPED, str(info["unavailable"]), data=info)
        return RobotResult(c.robot.name, Outcome.OK, f"{key} = {info['value']} ({info['source']}; {info['stack']})",
                           data=info)

    return fleet.run("config get", task, read_only=True)


@app.command("set")
@shared(*GATED)
def set_(
    fleet: Fleet,
    key: KeyArg,
    value: Annotated[str, typer.Argument(help="The value, e.g. WH02, True, /config/x.yaml, 1.5.")],
    force: Force = False,
    everywhere: Annotated[bool, typer.Option(
        "--everywhere", help="namespace: also change it where the robot's other parts name it (the gamepad "
        "service, ROBOT_NAMESPACE), in the same plan.")] = False,
) -> int:
    """Set a launch argument of the driver (e.g. wheel_type WH02) or a controller limit
    (controller.linear.x.max_velocity 1.0) on each robot, knowing each key per stack version.

    Plans every robot first and shows the exact diff; then (after --yes or your confirmation)
    backs up, writes atomically, recreates the driver as the robot user, and verifies it keeps
    running with the new command; a failed change is rolled back. A new namespace warns of the
    places that keep the old one (gamepad service, ROBOT_NAMESPACE, the WebUI); --everywhere
    changes the first two in the same plan.

    \b
    Examples:
      panther-ops config set wheel_type WH02 -r panther-01 --yes
      panther-ops config set controller.linear.x.max_velocity 1.0 -g warehouse --dry-run
    """
    from panther_ops.core.config.checks import parse_value, precheck

    parsed = parse_value(value) if key.startswith("controller.") else value
    precheck({key: parsed}, force=force)
    if key.startswith("controller."):
        def planner(c: Any) -> Any:
            from panther_ops.core.config.read import read_and_plan_controller

            return read_and_plan_controller(c, {key: parsed}, force=force)
    else:
        def planner(c: Any) -> Any:
            from panther_ops.core.config.read import read_and_plan_args

            return read_and_plan_args(c, {key: value}, [], force=force, everywhere=everywhere)
    label = (f"config set {key} {value}" + (" --everywhere" if everywhere else "")
             + (" --force" if force else ""))
    # the planners (and the YAML editor they bring) load while the robots connect
    return fleet.change(label, planner)


@app.command("unset")
@shared(*WRITE)
def unset(fleet: Fleet, key: KeyArg) -> int:
    """Remove a launch argument from the driver's command (the stack's default applies again).

    \b
    Example:
      panther-ops config unset wheel_type -r panther-01 --yes
    """
    from panther_ops.core.config.checks import precheck_key

    precheck_key(key, known=False)  # an argument not in the catalogue can be removed, a malformed name not

    def planner(c: Any) -> Any:
        from panther_ops.core.config.read import read_and_plan_args

        return read_and_plan_args(c, {}, [key])

    return fleet.change(f"config unset {key}", planner)


@app.command("diff")
@shared(*READ)
def diff(
    fleet: Fleet,
    exit_code: Annotated[bool, typer.Option(
        "--exit-code", help="Exit 6 when a robot differs (drift), 0 when none does, as git diff --exit-code.")] = False,
) -> int:
    """Compare each robot with the inventory's desired: block (launch_args, controller, image,
    GPS, and desired.webui against the WebUI snap's keys on its User Computer): `changed` means
    drift, with the diff (and WebUI keys, current -> new) that `panther-ops apply` would change.
    --exit-code: the answer in the exit code for a script (0 no drift, 6 drift; 3 or 4 when a
    robot could not be read).

    \b
    Examples:
      panther-ops config diff --all
      panther-ops -q config diff --all --exit-code
    """
    from panther_ops.core.apply.read import read_and_plan_desired

    return fleet.change("config diff", read_and_plan_desired, read_only=True, drift_exit=exit_code)


@app.command("history")
@shared(*READ)
def history(fleet: Fleet, file: LocalFile = None) -> int:
    """List the backups each change left on the robot (~/.panther-ops/backups): id, time,
    command, what changed, and how the attempt ended (applied, rolled-back and why). --file:
    the backups of a local hosts file, kept beside it by `shutdown hosts add|remove FILE`.

    \b
    Examples:
      panther-ops config history -r panther-01
      panther-ops config history --file hosts.yaml
    """
    from panther_ops.cli.views.history import print_history
    from panther_ops.core.fleet.history import list_history
    from panther_ops.results import Outcome, RobotResult

    def task(c: Any) -> RobotResult:
        entries = list_history(c, only=str(file.resolve()) if file is not None else None)
        for e in entries:
            e.pop("robot", None)
        return RobotResult(c.robot.name, Outcome.OK, f"{len(entries)} backups", data={"history": entries})

    return fleet.run("config history", task, print_history, read_only=True,
                     on=_local(file, fleet) if file is not None else None)


def _local(file: Path, fleet: Fleet) -> tuple[Any, list[Any]]:
    """--file: the local hosts file's directory as the one target (see core/shutdown/localfile.py)."""
    from panther_ops.core.shutdown.localfile import local_target
    from panther_ops.errors import UsageError

    if fleet.robot or fleet.group or fleet.all_:
        raise UsageError("give either --file FILE (a local hosts file) or robots (-r/-g/--all), not both")
    fleet.robots_only(f"--file {file}")
    inv, target = local_target(file, "--file")
    return inv, [target]


@app.command("rollback")
@shared(*WRITE)
def rollback(
    fleet: Fleet,
    to: Annotated[OptStr, typer.Option("--to",
                                       help="Backup id (or a unique prefix) to restore; default: the newest.")] = None,
    file: LocalFile = None,
) -> int:
    """Restore the files as they were before a change (a backup from `config history`), through
    the same pipeline: diff, confirm, backup, atomic write, recreate, verify. --file: a local
    hosts file from its own backups (nothing recreated).

    \b
    Examples:
      panther-ops config rollback -r panther-01 --to 20261122T101500Z --yes
      panther-ops config rollback --file hosts.yaml --dry-run
    """
    import re

    from panther_ops.core.fleet.history import read_and_plan_rollback
    from panther_ops.errors import UsageError

    if to is not None and not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}", to):
        raise UsageError(f"--to {to!r} is not a backup id",
                         hint="an id (or a prefix) from `panther-ops config history`, e.g. 20261122T101500Z")
    if file is not None:
        from panther_ops.core.shutdown.localfile import plan_local_rollback

        return fleet.change("config rollback", lambda c: plan_local_rollback(c, file, to), on=_local(file, fleet),
                            restart=False, verb="Write")
    return fleet.change("config rollback", lambda c: read_and_plan_rollback(c, to))


@app.command("push")
@shared(*GATED)
def push(
    fleet: Fleet,
    local: Annotated[Path, typer.Argument(help="The file to push (a .btproj for bt-lights/bt-safety).")],
    as_: Annotated[str, typer.Option("--as", help="What it is: controller, wheel, components, led, "
                                     "user-animations, bt-lights, bt-safety, shutdown-hosts, battery, joy2twist.",
                                     autocompletion=complete.kinds)],
    force: Force = False,
) -> int:
    """Upload a config file, mount it into the driver container and point its launch argument
    at it (2.0/2.1), or place it in the robot's ~/config tree (2.2): the manual's four steps in
    one command, with diff, backup, recreate, verify and roll back. A BT project brings the XML
    files it includes; a user animations file brings the images it references.

    \b
    Example:
      panther-ops config push my_controller.yaml --as controller -r panther-01 --yes
    """
    from panther_ops.core.config.read import read_and_plan_push
    from panther_ops.core.robot.push import push_kind, read_bundle

    kind = push_kind(as_)
    bundle = read_bundle(kind, local, force=force)
    return fleet.change(f"config push {local.name} --as {kind.value}" + (" --force" if force else ""),
                        lambda c: read_and_plan_push(c, kind, bundle, force=force))


@app.command("pull")
@shared(*TARGETS, "json_out")
def pull(
    fleet: Fleet,
    kind: Annotated[str, typer.Argument(help="controller, wheel, components, led, user-animations, "
                                        "bt-lights, bt-safety, shutdown-hosts, battery, joy2twist.",
                                        autocompletion=complete.kinds)],
    output: Annotated[OptPath, typer.Option("--output", "-o",
                                            help="Write to this file (one robot) instead of stdout.")] = None,
    dest: Annotated[OptPath, typer.Option("--dest", help="Several robots: write DEST/<robot>/<file>.")] = None,
    force: Annotated[bool, typer.Option("--force", help="A BT project: replace included files that exist "
                                        "beside the output with other content.")] = False,
) -> int:
    """Fetch the config file in use: the mounted one, else the 2.2 config tree's, else the
    default inside the robot's own image, else panther-ops' template for that version. A BT
    project (bt-lights, bt-safety) comes with the files it includes, from the same place,
    written beside it (-o/--dest) at the paths the project names.

    \b
    Example:
      panther-ops config pull controller -r panther-01 -o controller.yaml
    """
    from panther_ops.cli.context import info, run
    from panther_ops.cli.output import write_bytes
    from panther_ops.cli.render import print_warnings
    from panther_ops.core.config.pull_files import check_dest, check_output, local_writes, settle, write_files
    from panther_ops.core.robot.pull import pull as pull_file
    from panther_ops.core.robot.pull import pull_project
    from panther_ops.core.robot.push import BT_ARGS, push_kind
    from panther_ops.results import Outcome, RobotResult

    k = push_kind(kind, "KIND")
    check_output(output)
    inv, chosen = fleet.targets()
    check_dest(dest, len(chosen))
    got: dict[str, bytes] = {}
    includes: dict[str, dict[str, bytes]] = {}

    def task(c: Any) -> RobotResult:
        if k not in BT_ARGS:
            data, source = pull_file(c, k)
            got[c.robot.name] = data
            return RobotResult(c.robot.name, Outcome.OK, f"{len(data)} bytes from {source}", data={"source": source})
        data, source, inc = pull_project(c, k)
        got[c.robot.name], includes[c.robot.name] = data, inc.files
        warnings = [f"included {n}: not found at the source" for n in inc.missing]
        warnings += [f"include {r}: leaves the project's directory, not fetched" for r in inc.refused]
        if inc.files and output is None and dest is None:
            warnings.append(f"the project includes {', '.join(inc.files)}: pull with -o FILE.btproj to write "
                            "them beside it")
        said = f"; includes {', '.join(inc.files)}" if inc.files else ""
        return RobotResult(c.robot.name, Outcome.OK, f"{len(data)} bytes from {source}{said}",
                           data={"source": source, "includes": list(inc.files)}, warnings=warnings)

    result = run("config pull", inv, chosen, task, json_out=True)
    writes, same = settle(local_writes(got, k, output, dest, includes), force)
    write_files(writes)
    for r in result.results:  # which files this machine now has, each named
        written = [str(w.path) for w in writes if w.robot == r.robot]
        unchanged = [str(w.path) for w in same if w.robot == r.robot]
        if written or unchanged:
            r.data.update(written=written, unchanged=unchanged)
            r.message += "; written: " + ", ".join(written) + (f"; already there: {', '.join(unchanged)}"
                                                                 if unchanged else "")
    if fleet.json_out or dest is not None or output is not None:
        return fleet.show(result)
    for data in got.values():
        write_bytes(data)
    for r in result.results:
        info(f"{r.robot}: {r.outcome.value}: {r.message}")
    print_warnings(result)
    return int(result.exit_code)


@shared(*GATED)
def apply(fleet: Fleet, force: Force = False, ask_sudo_password: AskPassword = False) -> int:
    """Converge robots to the inventory's desired: block (launch_args, controller limits, driver
    image, GPS) through the same plan / diff / confirm / backup / recreate / verify / roll back
    pipeline, and desired.webui on each robot's User Computer (sudo snap set, the WebUI
    restarted when it was running; ros.namespace defaults to the robot's namespace).

    \b
    Example:
      panther-ops apply -g warehouse --canary 1 --yes
    """
    from panther_ops.core.apply.read import read_and_plan_desired

    inv, chosen = fleet.targets()
    password = sudo_password(ask_sudo_password) if any(r.desired.get("webui") for r in chosen) else None
    return fleet.change("apply --force" if force else "apply", lambda c: read_and_plan_desired(c, force=force),
                        on=(inv, chosen), sudo_password=password)


def register(root: typer.Typer) -> None:
    root.add_typer(app, name="config")
    root.command("apply")(apply)
