"""`panther-ops shutdown hosts list|validate|add|remove`: the shutdown hosts file, a robot's
(-r ROBOT) or a local FILE."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from panther_ops.cli import context
from panther_ops.cli.commands.shutdown import (
    AskSecret,
    FileArg,
    OptFloat,
    OptInt,
    OptStr,
    PowerBudget,
    SecretEnv,
    SecretFile,
    secret_from,
    usage_error,
)
from panther_ops.cli.mutate import DryRun, NoRestart, Settle, Yes, mutate
from panther_ops.cli.options import All, Forks, Groups, Json, Robots, finite
from panther_ops.cli.shutdown_view import (
    esc,
    finish_list,
    stderr,
    stdout,
)

hosts_app = typer.Typer(help="The shutdown hosts file: the robot's (-r ROBOT) or a local FILE.", no_args_is_help=True)

if TYPE_CHECKING:
    from panther_ops.core.kinds.hostsfile import HostsFile
    from panther_ops.results import RobotResult


# =================================================================================================
# panther-ops shutdown hosts ...
# =================================================================================================
def _local_or_robots(file: Path | None, robot: list[str] | None, group: list[str] | None, all_: bool) -> None:
    if file is not None and (robot or group or all_):
        raise usage_error("give either a local FILE or robots (-r/-g/--all), not both")


@hosts_app.command("list")
def hosts_list(
    ctx: typer.Context,
    file: FileArg = None,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Show the hosts of a local FILE, or of each robot's hosts file (the one its manager reads).

    Example: panther-ops shutdown hosts list -r panther-01
    """
    from panther_ops.core.kinds.hostsfile import load_hosts_file
    from panther_ops.results import FleetResult, Outcome, RobotResult

    _local_or_robots(file, robot, group, all_)
    if file is not None:
        parsed = load_hosts_file(file, power_budget=power_budget)
        res = RobotResult(str(file), Outcome.FAILED if parsed.errors else Outcome.OK, f"{len(parsed.entries)} hosts",
                          data=_file_data(parsed, str(file)), warnings=[str(f) for f in parsed.warnings])
        fleet = FleetResult("shutdown hosts list", [res])
        return finish_list(fleet, json_out)
    from panther_ops.core.shutdown.robotfile import read_robot_hosts

    def task(c: Any) -> RobotResult:
        rf = read_robot_hosts(c)
        parsed = rf.parse(power_budget)
        return RobotResult(c.robot.name, Outcome.FAILED if parsed.errors else Outcome.OK,
                           f"{len(parsed.entries)} hosts in {rf.source}", data=_file_data(parsed, rf.source, rf),
                           warnings=[str(f) for f in parsed.warnings])

    inv, chosen = context.targets(ctx, robot, group, all_)
    return finish_list(context.run("shutdown hosts list", inv, chosen, task, forks=forks, json_out=json_out),
                        json_out)


def _file_data(parsed: HostsFile, source: str, rf: Any = None) -> dict[str, Any]:
    data: dict[str, Any] = {"hosts_file": source, "hosts": [e.row() for e in parsed.entries],
                            "errors": [str(f) for f in parsed.errors]}
    if rf is not None:
        data["stack"] = rf.stack.label()
        data["mode"] = rf.mode.value
    return data


def _check_ip(ip: str) -> None:
    """--ip of `hosts remove` is what a hosts file's ip may be (the hosts file validator's rule)."""
    from panther_ops.core.kinds.hostsfile import valid_address

    if not valid_address(ip):
        raise usage_error(f"--ip {ip!r} is not an IP address or host name")


@hosts_app.command("validate")
def hosts_validate(
    ctx: typer.Context,
    file: FileArg = None,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    stack: Annotated[OptStr, typer.Option("--stack", help="A local file: check it for this stack version "
                                          "(e.g. 2.1.1: SSH entries; 2.2.2: HTTP entries).")] = None,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Check a hosts file: addresses, POSIX user names, ports, timeouts > 0, duplicates (same ip,
    user and port), the entry format of the robot's stack; warn about commands that are not a
    shutdown/poweroff and timeouts longer than the robot gives before cutting the power.
    Exit 2 when there are errors.

    Example: panther-ops shutdown hosts validate my_hosts.yaml --stack 2.1.1
    """
    from panther_ops.core.kinds.hostsfile import Mode, load_hosts_file
    from panther_ops.results import FleetResult, Outcome

    _local_or_robots(file, robot, group, all_)
    if stack and file is None:
        raise usage_error("--stack goes with a local FILE (a robot's hosts file is checked for the robot's own stack)")
    if file is not None:
        mode = None
        if stack:
            from panther_ops.core.stack import stack_option

            mode = Mode.HTTP if stack_option(stack).shutdown_over_http else Mode.SSH
        parsed = load_hosts_file(file, mode=mode, power_budget=power_budget)
        results = [_validate_result(str(file), parsed, str(file))]
        fleet = FleetResult("shutdown hosts validate", results)
    else:
        from panther_ops.core.shutdown.robotfile import read_robot_hosts

        def task(c: Any) -> RobotResult:
            rf = read_robot_hosts(c)
            return _validate_result(c.robot.name, rf.parse(power_budget), rf.source)

        inv, chosen = context.targets(ctx, robot, group, all_)
        fleet = context.run("shutdown hosts validate", inv, chosen, task, forks=forks, json_out=json_out)
    bad = any(r.data.get("errors") for r in fleet.results)
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json(fleet.to_json())
    else:
        out, err = stdout(), stderr()
        for r in fleet.results:
            for e in r.data.get("errors", []):
                err.print(f"[red]error[/] {esc(r.robot)}: {esc(e)}")
            for w in r.warnings:
                err.print(f"[yellow]warning[/] {esc(r.robot)}: {esc(w)}")
            colour = "red" if r.outcome is not Outcome.OK else "green"
            out.print(f"{esc(r.robot)}: [{colour}]{r.outcome.value}[/] {esc(r.message)}")
    if bad:
        return 2
    return int(fleet.exit_code)


def _validate_result(name: str, parsed: HostsFile, source: str) -> RobotResult:
    from panther_ops.results import Outcome, RobotResult

    errors = [str(f) for f in parsed.errors]
    if errors:
        msg = f"{len(errors)} error(s), {len(parsed.warnings)} warning(s) in {source}"
        outcome = Outcome.FAILED
    else:
        msg = f"{len(parsed.entries)} host(s) valid, {len(parsed.warnings)} warning(s) ({source})"
        outcome = Outcome.OK
    return RobotResult(name, outcome, msg, data={"hosts_file": source, "errors": errors,
                                                 "hosts": [e.row() for e in parsed.entries]},
                       warnings=[str(f) for f in parsed.warnings])


def _entry(ip: str, user: str | None, port: int | None, command: str | None, timeout: float | None,
           no_ping: bool, http: bool, secret: Any) -> dict[str, Any]:
    from panther_ops.core.kinds.hostsfile import check_entry, new_entry

    if http and user:
        raise usage_error("--http hosts have no --user (husarion-shutdown takes a signed request, not a login)")
    if not http and not user:
        raise usage_error("an SSH host needs --user (or --http for a husarion-shutdown host)")
    entry = new_entry(ip, username=None if http else user, port=port, command=command, timeout=timeout,
                      ping_for_success=not no_ping, secret=secret)
    errors = [f for f in check_entry(entry) if f.level == "error"]
    if errors:
        raise usage_error("; ".join(str(f) for f in errors), hint="nothing was changed")
    return entry


def _edit_local(file: Path, change: Any, yes: bool, dry_run: bool, json_out: bool, command: str) -> int:
    """A local hosts file through the change pipeline (its directory is the target: diff,
    confirm, backup beside it, atomic write; see core/shutdown/localfile.py)."""
    from panther_ops.core.shutdown.localfile import local_target, plan_local_hosts_edit

    inv, target = local_target(file)
    return mutate(command, inv, [target], lambda c: plan_local_hosts_edit(c, file, change), yes=yes,
                  dry_run=dry_run, restart=False, json_out=json_out, verb="Write")


@hosts_app.command("add")
def hosts_add(
    ctx: typer.Context,
    file: FileArg = None,
    ip: Annotated[str, typer.Option("--ip", help="Address or host name of the computer.")] = "",
    user: Annotated[OptStr, typer.Option("--user", "-u", help="SSH user on the computer (SSH hosts).")] = None,
    port: Annotated[OptInt, typer.Option("--port", help="SSH port (22) or husarion-shutdown port (3003).")] = None,
    command: Annotated[OptStr, typer.Option("--command", help="Command run over SSH (default: sudo shutdown "
                                            "now).")] = None,
    timeout: Annotated[OptFloat, typer.Option("--timeout", callback=finite,
                                              help="Seconds to wait for the host to go down (default 5).")] = None,
    no_ping: Annotated[bool, typer.Option("--no-ping-for-success", help="Done at the response (no pinging).")] = False,
    http: Annotated[bool, typer.Option("--http", help="A husarion-shutdown (HTTP) host (2.2.1+ robots).")] = False,
    secret_env: SecretEnv = None,
    secret_file: SecretFile = None,
    ask_secret: AskSecret = False,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    yes: Yes = False,
    dry_run: DryRun = False,
    no_restart: NoRestart = False,
    settle: Settle = 5.0,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Add a host (or update the listed one with the same ip, user and port). On robots the file
    goes through the configuration pipeline: diff, confirm, backup, write, mount and
    shutdown_hosts_config_path (2.0/2.1), recreate, verify. A local FILE goes through it too
    (diff, confirm, backup in .panther-ops/backups/ beside it, atomic write) and keeps a secret
    given with --secret-env as {env: VAR}; a robot's file gets the value (its manager reads it).

    Examples:
      panther-ops shutdown hosts add -r panther-01 --ip 10.15.20.3 --user husarion --yes
      panther-ops shutdown hosts add hosts.yaml --ip 10.15.20.5 --http --secret-env NUC_SECRET
    """
    from panther_ops.core.kinds.hostsfile import add_host

    if not ip:
        raise usage_error("--ip is required")
    _local_or_robots(file, robot, group, all_)
    if file is not None:
        secret_value: Any = None
        if secret_env:
            secret_value = {"env": secret_env}
        elif secret_file:
            secret_value = {"file": str(secret_file)}
        elif ask_secret:
            sec = secret_from(None, None, True)
            secret_value = sec.reveal() if sec else None
        entry = _entry(ip, user, port, command, timeout, no_ping, http, secret_value)
        return _edit_local(file, lambda text: add_host(text, entry, str(file)), yes, dry_run, json_out,
                           f"shutdown hosts add {f'{user}@{ip}' if user else f'http://{ip}'}")
    sec = secret_from(secret_env, secret_file, ask_secret)
    entry = _entry(ip, user, port, command, timeout, no_ping, http, sec.reveal() if sec else None)
    from panther_ops.core.shutdown.robotfile import plan_hosts_edit

    inv, chosen = context.targets(ctx, robot, group, all_)
    label = f"{user}@{ip}" if user else f"http://{ip}"
    return mutate(f"shutdown hosts add {label}", inv, chosen,
                  lambda c: plan_hosts_edit(c, lambda text, _mode: add_host(text, entry), power_budget=power_budget),
                  yes=yes, dry_run=dry_run, restart=not no_restart, settle=settle, json_out=json_out, forks=forks)


@hosts_app.command("remove")
def hosts_remove(
    ctx: typer.Context,
    file: FileArg = None,
    ip: Annotated[str, typer.Option("--ip", help="Address of the host to remove.")] = "",
    user: Annotated[OptStr, typer.Option("--user", "-u", help="Only the entry of this user.")] = None,
    port: Annotated[OptInt, typer.Option("--port", help="Only the entry of this port.")] = None,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    yes: Yes = False,
    dry_run: DryRun = False,
    no_restart: NoRestart = False,
    settle: Settle = 5.0,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Remove a host's entries (every entry of --ip, narrowed by --user/--port).

    Example: panther-ops shutdown hosts remove -r panther-01 --ip 10.15.20.3 --yes
    """
    from panther_ops.core.kinds.hostsfile import remove_host

    if not ip:
        raise usage_error("--ip is required")
    _check_ip(ip)
    _local_or_robots(file, robot, group, all_)
    if file is not None:
        if not file.exists():
            raise usage_error(f"{file} does not exist")
        return _edit_local(file, lambda text: remove_host(text, ip, user, port, str(file)), yes, dry_run,
                           json_out, f"shutdown hosts remove {ip}")
    from panther_ops.core.shutdown.robotfile import plan_hosts_edit

    inv, chosen = context.targets(ctx, robot, group, all_)
    return mutate(f"shutdown hosts remove {ip}", inv, chosen,
                  lambda c: plan_hosts_edit(c, lambda text, _mode: remove_host(text, ip, user, port),
                                            power_budget=power_budget),
                  yes=yes, dry_run=dry_run, restart=not no_restart, settle=settle, json_out=json_out, forks=forks)
