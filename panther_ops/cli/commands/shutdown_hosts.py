"""`panther-ops shutdown hosts list|validate|add|remove`: the shutdown hosts file, a robot's
(-r ROBOT) or a local FILE."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from panther_ops.cli.commands.shutdown_inputs import (
    AskSecret,
    FileArg,
    PowerBudget,
    SecretEnv,
    SecretFile,
    secret_from,
    usage_error,
)
from panther_ops.cli.context import Fleet
from panther_ops.cli.options import READ, WRITE, OptFloat, OptInt, OptStr, port_number, real_number, shared
from panther_ops.cli.views.shutdown import print_list, print_validated

hosts_app = typer.Typer(help="The shutdown hosts file: the robot's (-r ROBOT) or a local FILE.", no_args_is_help=True)

if TYPE_CHECKING:
    from panther_ops.core.kinds.hostsfile import HostsFile
    from panther_ops.results import RobotResult


# =================================================================================================
# panther-ops shutdown hosts ...
# =================================================================================================
def _local_or_robots(file: Path | None, fleet: Fleet) -> None:
    if file is not None and (fleet.robot or fleet.group or fleet.all_):
        raise usage_error("give either a local FILE or robots (-r/-g/--all), not both")
    if file is not None:
        fleet.robots_only(f"the local FILE {file}")


@hosts_app.command("list")
@shared(*READ)
def hosts_list(fleet: Fleet, file: FileArg = None, power_budget: PowerBudget = 15.0) -> int:
    """Show the hosts of a local FILE, or of each robot's hosts file (the one its manager reads).

    \b
    Example:
      panther-ops shutdown hosts list -r panther-01
    """
    from panther_ops.core.kinds.hostsfile import load_hosts_file
    from panther_ops.results import FleetResult, Outcome, RobotResult

    _local_or_robots(file, fleet)
    if file is not None:
        parsed = load_hosts_file(file, power_budget=power_budget)
        res = RobotResult(str(file), Outcome.FAILED if parsed.errors else Outcome.OK, f"{len(parsed.entries)} hosts",
                          data=_file_data(parsed, str(file)), warnings=[str(f) for f in parsed.warnings])
        return fleet.show(FleetResult("shutdown hosts list", [res]), print_list)
    from panther_ops.core.shutdown.read import read_robot_hosts

    def task(c: Any) -> RobotResult:
        rf = read_robot_hosts(c)
        parsed = rf.parse(power_budget)
        return RobotResult(c.robot.name, Outcome.FAILED if parsed.errors else Outcome.OK,
                           f"{len(parsed.entries)} hosts in {rf.source}", data=_file_data(parsed, rf.source, rf),
                           warnings=[str(f) for f in parsed.warnings])

    return fleet.run("shutdown hosts list", task, print_list)


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
@shared(*READ)
def hosts_validate(
    fleet: Fleet,
    file: FileArg = None,
    stack: Annotated[OptStr, typer.Option("--stack", help="A local file: check it for this stack version "
                                          "(e.g. 2.1.1: SSH entries; 2.2.2: HTTP entries).")] = None,
    power_budget: PowerBudget = 15.0,
) -> int:
    """Check a hosts file: addresses, POSIX user names, ports, timeouts > 0, duplicates (same ip,
    user and port), the entry format of the robot's stack; warn about commands that are not a
    shutdown/poweroff and timeouts longer than the robot gives before cutting the power.
    Exit 2 when there are errors.

    \b
    Example:
      panther-ops shutdown hosts validate my_hosts.yaml --stack 2.1.1
    """
    from panther_ops.core.kinds.hostsfile import Mode, load_hosts_file
    from panther_ops.results import FleetResult

    _local_or_robots(file, fleet)
    if stack and file is None:
        raise usage_error("--stack goes with a local FILE (a robot's hosts file is checked for the robot's own stack)")
    if file is not None:
        mode = None
        if stack:
            from panther_ops.core.stack import stack_option

            mode = Mode.HTTP if stack_option(stack).shutdown_over_http else Mode.SSH
        parsed = load_hosts_file(file, mode=mode, power_budget=power_budget)
        results = [_validate_result(str(file), parsed, str(file))]
        result = FleetResult("shutdown hosts validate", results)
    else:
        from panther_ops.core.shutdown.read import read_robot_hosts

        def task(c: Any) -> RobotResult:
            rf = read_robot_hosts(c)
            return _validate_result(c.robot.name, rf.parse(power_budget), rf.source)

        result = fleet.results("shutdown hosts validate", task)
    code = fleet.show(result, print_validated)
    return 2 if any(r.data.get("errors") for r in result.results) else code


def _validate_result(name: str, parsed: HostsFile, source: str) -> RobotResult:
    from panther_ops.cli.render import counted
    from panther_ops.results import Outcome, RobotResult

    errors = [str(f) for f in parsed.errors]
    where = "" if source == name else f" in {source}"  # a local file: its name starts the line already
    warnings = counted(len(parsed.warnings), "warning")
    if errors:
        msg = f"{counted(len(errors), 'error')}, {warnings}{where}"
        outcome = Outcome.FAILED
    else:
        msg = f"{counted(len(parsed.entries), 'host')} valid, {warnings}{where}"
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


def _edit_local(fleet: Fleet, file: Path, change: Any, command: str) -> int:
    """A local hosts file through the change pipeline (its directory is the target: diff,
    confirm, backup beside it, atomic write; see core/shutdown/localfile.py)."""
    from panther_ops.core.shutdown.localfile import local_target, plan_local_hosts_edit

    inv, target = local_target(file)
    return fleet.change(command, lambda c: plan_local_hosts_edit(c, file, change), on=(inv, [target]), restart=False,
                        verb="Write")


@hosts_app.command("add")
@shared(*WRITE)
def hosts_add(
    fleet: Fleet,
    file: FileArg = None,
    ip: Annotated[str, typer.Option("--ip", help="Address or host name of the computer.")] = "",
    user: Annotated[OptStr, typer.Option("--user", "-u", help="SSH user on the computer (SSH hosts).")] = None,
    port: Annotated[OptInt, typer.Option("--port", parser=port_number(),
                                                  help="SSH port (22) or husarion-shutdown port (3003).")] = None,
    command: Annotated[OptStr, typer.Option("--command", help="Command run over SSH (default: sudo shutdown "
                                            "now).")] = None,
    timeout: Annotated[OptFloat, typer.Option("--timeout", parser=real_number(),
                                              help="Seconds to wait for the host to go down (default 5).")] = None,
    no_ping: Annotated[bool, typer.Option("--no-ping-for-success", help="Done at the response (no pinging).")] = False,
    http: Annotated[bool, typer.Option("--http", help="A husarion-shutdown (HTTP) host (2.2.1+ robots).")] = False,
    secret_env: SecretEnv = None,
    secret_file: SecretFile = None,
    ask_secret: AskSecret = False,
    power_budget: PowerBudget = 15.0,
) -> int:
    """Add a host (or update the listed one with the same ip, user and port). On robots the file
    goes through the configuration pipeline: diff, confirm, backup, write, mount and
    shutdown_hosts_config_path (2.0/2.1), recreate, verify. A local FILE goes through it too
    (diff, confirm, backup in .panther-ops/backups/ beside it, atomic write) and keeps a secret
    given with --secret-env as {env: VAR}; a robot's file gets the value (its manager reads it).

    \b
    Examples:
      panther-ops shutdown hosts add -r panther-01 --ip 10.15.20.3 --user husarion --yes
      panther-ops shutdown hosts add hosts.yaml --ip 10.15.20.5 --http --secret-env NUC_SECRET
    """
    from panther_ops.core.kinds.hostsfile import add_host

    if not ip:
        raise usage_error("--ip is required")
    _local_or_robots(file, fleet)
    label = f"shutdown hosts add {f'{user}@{ip}' if user else f'http://{ip}'}"
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
        return _edit_local(fleet, file, lambda text: add_host(text, entry, str(file)), label)
    sec = secret_from(secret_env, secret_file, ask_secret)
    entry = _entry(ip, user, port, command, timeout, no_ping, http, sec.reveal() if sec else None)
    from panther_ops.core.shutdown.read import plan_hosts_edit

    return fleet.change(label,
                        lambda c: plan_hosts_edit(c, lambda text, _mode: add_host(text, entry),
                                                  power_budget=power_budget))


@hosts_app.command("remove")
@shared(*WRITE)
def hosts_remove(
    fleet: Fleet,
    file: FileArg = None,
    ip: Annotated[str, typer.Option("--ip", help="Address of the host to remove.")] = "",
    user: Annotated[OptStr, typer.Option("--user", "-u", help="Only the entry of this user.")] = None,
    port: Annotated[OptInt, typer.Option("--port", parser=port_number(),
                                                  help="Only the entry of this port.")] = None,
    power_budget: PowerBudget = 15.0,
) -> int:
    """Remove a host's entries (every entry of --ip, narrowed by --user/--port).

    \b
    Example:
      panther-ops shutdown hosts remove -r panther-01 --ip 10.15.20.3 --yes
    """
    from panther_ops.core.kinds.hostsfile import remove_host

    if not ip:
        raise usage_error("--ip is required")
    _check_ip(ip)
    _local_or_robots(file, fleet)
    if file is not None:
        if not file.exists():
            raise usage_error(f"{file} does not exist")
        return _edit_local(fleet, file, lambda text: remove_host(text, ip, user, port, str(file)),
                           f"shutdown hosts remove {ip}")
    from panther_ops.core.shutdown.read import plan_hosts_edit

    return fleet.change(f"shutdown hosts remove {ip}",
                        lambda c: plan_hosts_edit(c, lambda text, _mode: remove_host(text, ip, user, port),
                                                  power_budget=power_budget))
