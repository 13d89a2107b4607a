"""`panther-ops shutdown ...`: user computers that go down with the robot (docs/shutdown.md).

    panther-ops shutdown --hosts FILE [--via ROBOT] [--dry-run] [--yes]
    panther-ops shutdown hosts list|add|remove|validate [-r ROBOT | FILE]
    panther-ops shutdown setup -r ROBOT --host IP [--user U] [--ask-password] [--yes]
    panther-ops shutdown check [-r ROBOT]
    panther-ops shutdown robot -r ROBOT [--dry-run] [--yes]
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Optional

import typer

from panther_ops.cli import context
from panther_ops.cli.mutate import DryRun, NoRestart, Settle, Yes, mutate
from panther_ops.cli.options import All, Forks, Groups, Json, Robots, finite
from panther_ops.cli.shutdown_view import (
    esc,
    finish_hosts,
    finish_list,
    finish_steps,
    print_findings,
    print_plan,
    stderr,
    stdout,
)

if TYPE_CHECKING:
    from panther_ops.core.config.hostsfile import HostsFile
    from panther_ops.core.fleet.inventory import Inventory, Robot
    from panther_ops.results import RobotResult
    from panther_ops.transport.base import Secret


app = typer.Typer(
    help="User computers that shut down with the robot: the hosts file, setup, check, shutdown.",
    invoke_without_command=True,
    no_args_is_help=False,
)


hosts_app = typer.Typer(help="The shutdown hosts file: the robot's (-r ROBOT) or a local FILE.", no_args_is_help=True)


app.add_typer(hosts_app, name="hosts")


FileArg = Annotated[
    Optional[Path],  # noqa: UP045 - typer needs Optional on Python 3.10
    typer.Argument(help="A local hosts file (instead of -r ROBOT).", show_default=False),
]


PowerBudget = Annotated[
    float,
    typer.Option("--power-budget", min=0.1, callback=finite,
                 help="Seconds the robot's hardware gives its computers before it cuts "
                 "the power (a timeout above it is warned)."),
]


OptStr = Optional[str]  # noqa: UP045


OptInt = Optional[int]  # noqa: UP045


OptFloat = Optional[float]  # noqa: UP045


OptPath = Optional[Path]  # noqa: UP045


SecretEnv = Annotated[OptStr, typer.Option("--secret-env", metavar="VAR",
                                           help="HTTP hosts: the shared secret from this environment variable.")]


SecretFile = Annotated[OptPath, typer.Option("--secret-file", metavar="PATH",
                                             help="HTTP hosts: the shared secret from this file.")]


AskSecret = Annotated[bool, typer.Option("--ask-secret", help="HTTP hosts: ask for the shared secret.")]


def _usage(message: str, hint: str | None = None) -> Exception:
    from panther_ops.errors import UsageError

    return UsageError(message, hint=hint)


def _confirm(question: str, yes: bool, what: str) -> bool:
    if yes:
        return True
    if not sys.stdin.isatty():
        from panther_ops.cli.render import error

        error(f"{question} -- {what} needs confirmation: pass --yes when not interactive (or --dry-run to only "
              "look)")
        return False
    return bool(typer.confirm(question, default=False))


def _secret(env: str | None, file: Path | None, ask: bool) -> Secret | None:
    import getpass
    import os

    from panther_ops.transport.base import Secret

    given = [x for x in (env, file, ask or None) if x]
    if len(given) > 1:
        raise _usage("give the secret one way: --secret-env, --secret-file or --ask-secret")
    if env:
        value = os.environ.get(env)
        if value is None:
            raise _usage(f"--secret-env {env}: the variable is not set")
        return Secret(value)
    if file:
        try:
            return Secret(file.read_text().strip())
        except OSError as exc:
            raise _usage(f"--secret-file {file}: {exc.strerror}") from None
    if ask:
        return Secret(getpass.getpass("shared secret of the husarion-shutdown service: "))
    return None


# =================================================================================================
# panther-ops shutdown --hosts FILE
# =================================================================================================
@app.callback(invoke_without_command=True)
def shutdown(
    ctx: typer.Context,
    hosts: Annotated[OptPath, typer.Option("--hosts", help="Hosts file to shut down (the robot's format).")] = None,
    via: Annotated[OptStr, typer.Option("--via", metavar="ROBOT", help="Run through this robot (its LAN, its key "
                                        "and known_hosts), as its manager would.")] = None,
    identity: Annotated[OptPath, typer.Option("--identity", help="SSH key for the hosts (from here; default: "
                                              "~/.ssh/id_*).")] = None,
    known_hosts: Annotated[OptPath, typer.Option("--known-hosts", help="known_hosts for the hosts (from here; "
                                                 "default ~/.ssh/known_hosts).")] = None,
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Shut down without asking (needed when not "
                                      "interactive).")] = False,
    dry_run: Annotated[bool, typer.Option("--dry-run", help="Show what would be sent to each host; contact "
                                          "nothing.")] = False,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
) -> None:
    """Shut down the hosts of a hosts file, side by side, like the manager's ShutdownHostsFromFile:
    per host ping (no answer: skipped), the command over SSH or the signed HTTP request, then
    ping until it is gone or its timeout passes. Names every host and asks first (--yes).

    Example: panther-ops shutdown --hosts hosts.yaml --yes
    """
    if ctx.invoked_subcommand is not None:
        if hosts is not None or via is not None:
            raise _usage("--hosts/--via go without a subcommand: panther-ops shutdown --hosts FILE")
        return
    if hosts is None:
        typer.echo(ctx.get_help())
        raise typer.Exit(0)
    raise typer.Exit(_shutdown_file(ctx, hosts, via, identity, known_hosts, yes, dry_run, power_budget, json_out))


def _shutdown_file(ctx: typer.Context, path: Path, via: str | None, identity: Path | None,
                   known_hosts: Path | None, yes: bool, dry_run: bool, power_budget: float, json_out: bool) -> int:
    from panther_ops.core.config.hostsfile import load_hosts_file
    from panther_ops.core.shutdown.run import shutdown_hosts

    for option, given in (("--identity", identity), ("--known-hosts", known_hosts)):
        if given is not None and not given.is_file():
            raise _usage(f"{option} {given}: no such file")
    inv: Inventory | None = None
    link_robot: Robot | None = None
    if via is not None:  # the robot must exist and reach its LAN, dry run or not
        from panther_ops.core.shutdown.remote import lan_robot

        inv = context.load(ctx)
        if via not in inv.robots:
            inv.select([via], [], False)  # no robot matches: exit 2 naming the robots
            raise _usage(f"--via {via!r}: name one robot of the inventory (not a glob)")
        link_robot = lan_robot(inv, via)  # the dry run refuses what the real run would refuse
    parsed = load_hosts_file(path, power_budget=power_budget)
    print_findings(parsed)
    hosts = parsed.hosts()  # exit 2 on errors, before anything is contacted
    where = f"through {via}" if via else "from here"
    if json_out and (dry_run or not hosts):
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "command": f"shutdown --hosts {path}", "via": via, "dry_run": dry_run,
                   "hosts": [e.row() for e in parsed.entries], "warnings": [str(w) for w in parsed.warnings]})
        return 0
    if not hosts:
        context.info(f"{path}: no hosts, nothing to shut down")
        return 0
    if not json_out:
        print_plan(parsed, title=f"shutdown --hosts {path} ({where})" + (" -- dry run" if dry_run else ""))
    if dry_run:
        context.info("dry run: nothing was contacted")
        return 0
    names = ", ".join(h.describe() for h in hosts)
    if not _confirm(f"Shut down {len(hosts)} host(s) {where}: {names}?", yes, "shutting hosts down"):
        return 2
    if inv is not None and link_robot is not None:
        from panther_ops.core.fleet.runner import Connections
        from panther_ops.core.shutdown.remote import RobotLink, backends_via

        with Connections(inv) as conns:
            link = RobotLink(conns.get(link_robot), link_robot.name)
            fleet = shutdown_hosts(hosts, backends_via(link), command=f"shutdown --hosts {path.name} --via {via}")
    else:
        from panther_ops.core.shutdown.remote import backends_here

        fleet = shutdown_hosts(hosts, backends_here(str(known_hosts) if known_hosts else None,
                                                    str(identity) if identity else None),
                               command=f"shutdown --hosts {path.name}")
    return finish_hosts(fleet, json_out)


# =================================================================================================
# panther-ops shutdown hosts ...
# =================================================================================================
def _local_or_robots(file: Path | None, robot: list[str] | None, group: list[str] | None, all_: bool) -> None:
    if file is not None and (robot or group or all_):
        raise _usage("give either a local FILE or robots (-r/-g/--all), not both")


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
    from panther_ops.core.config.hostsfile import load_hosts_file
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
    from panther_ops.core.config.hostsfile import valid_address

    if not valid_address(ip):
        raise _usage(f"--ip {ip!r} is not an IP address or host name")


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
    from panther_ops.core.config.hostsfile import Mode, load_hosts_file
    from panther_ops.results import FleetResult, Outcome

    _local_or_robots(file, robot, group, all_)
    if stack and file is None:
        raise _usage("--stack goes with a local FILE (a robot's hosts file is checked for the robot's own stack)")
    if file is not None:
        mode = None
        if stack:
            from panther_ops.core.fleet.stack import stack_option

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
    from panther_ops.core.config.hostsfile import check_entry, new_entry

    if http and user:
        raise _usage("--http hosts have no --user (husarion-shutdown takes a signed request, not a login)")
    if not http and not user:
        raise _usage("an SSH host needs --user (or --http for a husarion-shutdown host)")
    entry = new_entry(ip, username=None if http else user, port=port, command=command, timeout=timeout,
                      ping_for_success=not no_ping, secret=secret)
    errors = [f for f in check_entry(entry) if f.level == "error"]
    if errors:
        raise _usage("; ".join(str(f) for f in errors), hint="nothing was changed")
    return entry


def _check_local(path: Path, after: str) -> None:
    """The hosts file as it would be written, through the one hosts file validator (an invalid
    entry already in the file is refused too, naming it)."""
    from panther_ops.core.config.kinds import FileKind, check_file

    check_file(FileKind.SHUTDOWN_HOSTS, str(path), after.encode(), local=path)


def _write_local(path: Path, before: str | None, after: str, yes: bool, dry_run: bool, json_out: bool,
                 command: str, message: str) -> int:
    import os
    import tempfile

    from panther_ops.cli.render import emit_json, print_diffs
    from panther_ops.core.config.hostsfile import mask_secrets
    from panther_ops.core.yaml.diff import unified_diff
    from panther_ops.results import Diff, FleetResult, Outcome, RobotResult

    changed = after != (before or "")
    diff = Diff(str(path), unified_diff(mask_secrets(before or ""), mask_secrets(after), str(path)))
    res = RobotResult(str(path), Outcome.CHANGED if changed else Outcome.OK,
                      (("would change (dry run): " if dry_run else "") + message) if changed else message,
                      diffs=[diff] if changed else [])
    fleet = FleetResult(command, [res])
    if changed and not dry_run:
        if not json_out:
            print_diffs(fleet)
        if not _confirm(f"Write {path}?", yes, "changing the file"):
            return 2
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=str(path.parent.resolve()))
        with os.fdopen(fd, "w") as fh:
            fh.write(after)
        if before is not None:
            os.chmod(tmp, path.stat().st_mode & 0o7777)
        os.replace(tmp, path)
    if json_out:
        emit_json(fleet.to_json())
    else:
        if dry_run and changed:
            print_diffs(fleet)
        stdout().print(f"{esc(path)}: {res.outcome.value}: {esc(res.message)}")
    return 0


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
    shutdown_hosts_config_path (2.0/2.1), recreate, verify. A local FILE keeps a secret given
    with --secret-env as {env: VAR}; a robot's file gets the value (its manager reads it).

    Examples:
      panther-ops shutdown hosts add -r panther-01 --ip 10.15.20.3 --user husarion --yes
      panther-ops shutdown hosts add hosts.yaml --ip 10.15.20.5 --http --secret-env NUC_SECRET
    """
    from panther_ops.core.config.hostsfile import add_host

    if not ip:
        raise _usage("--ip is required")
    _local_or_robots(file, robot, group, all_)
    if file is not None:
        secret_value: Any = None
        if secret_env:
            secret_value = {"env": secret_env}
        elif secret_file:
            secret_value = {"file": str(secret_file)}
        elif ask_secret:
            sec = _secret(None, None, True)
            secret_value = sec.reveal() if sec else None
        entry = _entry(ip, user, port, command, timeout, no_ping, http, secret_value)
        before = file.read_text() if file.exists() else None
        edit = add_host(before or "", entry, str(file))
        _check_local(file, edit.text)
        return _write_local(file, before, edit.text, yes, dry_run, json_out, "shutdown hosts add", edit.message)
    sec = _secret(secret_env, secret_file, ask_secret)
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
    from panther_ops.core.config.hostsfile import remove_host

    if not ip:
        raise _usage("--ip is required")
    _check_ip(ip)
    _local_or_robots(file, robot, group, all_)
    if file is not None:
        if not file.exists():
            raise _usage(f"{file} does not exist")
        before = file.read_text()
        edit = remove_host(before, ip, user, port, str(file))
        _check_local(file, edit.text)
        return _write_local(file, before, edit.text, yes, dry_run, json_out, "shutdown hosts remove", edit.message)
    from panther_ops.core.shutdown.robotfile import plan_hosts_edit

    inv, chosen = context.targets(ctx, robot, group, all_)
    return mutate(f"shutdown hosts remove {ip}", inv, chosen,
                  lambda c: plan_hosts_edit(c, lambda text, _mode: remove_host(text, ip, user, port),
                                            power_budget=power_budget),
                  yes=yes, dry_run=dry_run, restart=not no_restart, settle=settle, json_out=json_out, forks=forks)


# =================================================================================================
# panther-ops shutdown setup / check / robot
# =================================================================================================
@app.command("setup")
def setup(
    ctx: typer.Context,
    host: Annotated[str, typer.Option("--host", help="Address of the user computer on the robot's LAN.")],
    user: Annotated[OptStr, typer.Option("--user", "-u", help="User on the computer (SSH era; default "
                                         "husarion).")] = None,
    port: Annotated[OptInt, typer.Option("--port", help="SSH port (22) or husarion-shutdown port (3003).")] = None,
    timeout: Annotated[OptFloat, typer.Option("--timeout", callback=finite,
                                              help="The host's timeout in the hosts file.")] = None,
    ask_password: Annotated[bool, typer.Option("--ask-password", help="Ask the user's password (login once and "
                                               "sudo on the computer); never on the command line, never "
                                               "logged.")] = False,
    secret_env: SecretEnv = None,
    secret_file: SecretFile = None,
    ask_secret: AskSecret = False,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Trust the computer's host key (check the fingerprint "
                                      "shown first) and apply without asking.")] = False,
    no_restart: NoRestart = False,
    settle: Settle = 5.0,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
) -> int:
    """Set a user computer up to be shut down by the robot, through the robot (the computer sits on
    its LAN): the robot's key pair (~/.ssh/id_rsa, mounted into the driver), its public key in
    the user's authorized_keys (once), the computer's host key in the robot's known_hosts
    (fingerprint shown, --yes), /etc/sudoers.d/panther-shutdown (poweroff, reboot, shutdown
    without a password; checked with visudo, 0440), and the host in the robot's hosts file.
    On 2.2.1+ robots: checks husarion-shutdown and its secret instead. Re-running changes nothing.

    Example: panther-ops shutdown setup -r panther-01 --host 10.15.20.3 --user husarion --ask-password
    """
    import getpass

    from panther_ops.core.config.hostsfile import check_entry, new_entry
    from panther_ops.core.shutdown.setup import SetupRequest, run_setup
    from panther_ops.transport.base import Secret

    errors = [f for f in check_entry(new_entry(host, username=user or "husarion", port=port, timeout=timeout))
              if f.level == "error"]
    if errors:
        raise _usage("; ".join(str(f) for f in errors), hint="nothing was changed")
    secret = _secret(secret_env, secret_file, ask_secret)
    inv, chosen = context.targets(ctx, robot, group, all_)
    if len(chosen) != 1:
        raise _usage(f"setup works on one robot at a time ({len(chosen)} chosen)")
    password = Secret(getpass.getpass(f"password of {user or 'husarion'}@{host}: ")) if ask_password else None

    refused: list[str] = []

    def confirm(address: str, fp: str) -> bool:
        context.info(f"{host} offers the host key {fp}")
        if not yes and not sys.stdin.isatty():
            refused.append(address)
        return _confirm(f"Trust {address} ({fp}) and record it in {chosen[0].name}'s ~/.ssh/known_hosts?", yes,
                        "trusting a new host key")

    req = SetupRequest(ip=host, user=user, port=port, timeout=timeout, password=password, secret=secret,
                       operator_keys=tuple(r for r in (chosen[0].identity_file,) if r), confirm_host_key=confirm,
                       settle=settle, restart=not no_restart, power_budget=power_budget,
                       command=f"shutdown setup --host {host}")
    fleet = context.run("shutdown setup", inv, chosen, lambda c: run_setup(c, req), json_out=json_out)
    code = finish_steps(fleet, json_out)
    return 2 if refused else code


@app.command("check")
def check(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Prove, from each robot, that every host of its hosts file would power off, without powering
    it off: ping, host key, login with the robot's key (batch), `sudo -n -l <command>`; HTTP hosts:
    the service answers and accepts the secret. Names the failing step and its fix.

    Example: panther-ops shutdown check -r panther-01
    """
    from panther_ops.core.shutdown.check import check_robot

    inv, chosen = context.targets(ctx, robot, group, all_)
    fleet = context.run("shutdown check", inv, chosen, lambda c: check_robot(c, power_budget), forks=forks,
                        json_out=json_out)
    from panther_ops.cli.render import STYLE, emit_json, print_warnings

    if json_out:
        emit_json(fleet.to_json())
        return int(fleet.exit_code)
    from rich.table import Table

    table = Table(title="panther-ops shutdown check")
    for col in ("robot", "host", "result", "step", "message", "fix"):
        table.add_column(col, overflow="fold")
    for r in fleet.results:
        rows = r.data.get("hosts", [])
        if not rows:
            table.add_row(r.robot, "-", f"[{STYLE[r.outcome]}]{r.outcome.value}[/]", "", esc(r.message), "")
        for i, h in enumerate(rows):
            result = "[green]ok[/]" if h["ok"] else "[red]failed[/]"
            table.add_row(r.robot if i == 0 else "", esc(h["host"]), result, h["step"], esc(h["message"]),
                          esc(h["fix"]))
    stdout().print(table)
    print_warnings(fleet)
    return int(fleet.exit_code)


@app.command("robot")
def robot_(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Shut down without asking (needed when not "
                                      "interactive).")] = False,
    dry_run: Annotated[bool, typer.Option("--dry-run", help="Show the robots and hosts; contact no host.")] = False,
    power_budget: PowerBudget = 15.0,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Shut each robot down as its Shutdown tree does: the hosts of its hosts file first, side by
    side and from the robot (their failures do not stop it), then the Built-in Computer.
    Names the robot and every host and asks first (--yes).

    Example: panther-ops shutdown robot -r panther-01 --yes
    """
    from panther_ops.core.fleet.runner import Connections, RunOptions, run_fleet
    from panther_ops.core.shutdown.run import RobotShutdownPlan, plan_robot_shutdown, shutdown_robot
    from panther_ops.errors import ExitCode, UsageError
    from panther_ops.results import Outcome, RobotResult

    inv, chosen = context.targets(ctx, robot, group, all_)
    plans: dict[str, RobotShutdownPlan] = {}
    usage: dict[str, UsageError] = {}
    opts = RunOptions(forks=forks or inv.forks)

    def plan_task(c: Any) -> RobotResult:
        try:
            p = plan_robot_shutdown(c, power_budget)
        except UsageError as exc:
            usage[c.robot.name] = exc
            raise
        plans[c.robot.name] = p
        names = ", ".join(h.describe() for h in p.hosts) or "no hosts"
        return RobotResult(c.robot.name, Outcome.OK, f"{len(p.hosts)} host(s) first: {names}",
                           data={"hosts_file": p.hosts_file.source},
                           warnings=[str(f) for f in p.parsed.warnings])

    from panther_ops.cli.render import emit_json, error, print_results

    with Connections(inv) as conns:
        planned = run_fleet("shutdown robot (plan)", inv, chosen, plan_task, opts, None, conns)
        if usage:
            for name, exc in usage.items():
                error(f"{name}: {exc}")
            return int(ExitCode.USAGE)
        if not json_out:  # with --json, stdout holds one JSON document and nothing else
            print_results(planned, title="shutdown robot: " + ("dry run" if dry_run else "plan"))
        if dry_run or not plans:
            if json_out:
                emit_json(planned.to_json())
            return int(planned.exit_code)
        what = "; ".join(f"{n} after {', '.join(h.describe() for h in p.hosts) or 'no hosts'}"
                         for n, p in plans.items())
        if not _confirm(f"Shut down {what}?", yes, "shutting robots down"):
            return int(ExitCode.USAGE)
        todo = [r for r in chosen if r.name in plans]
        fleet = run_fleet("shutdown robot", inv, todo, lambda c: shutdown_robot(c, plans[c.robot.name]), opts,
                          None, conns)
    if json_out:
        emit_json(fleet.to_json())
        return int(fleet.exit_code)
    from rich.table import Table

    from panther_ops.cli.render import STYLE, print_summary, print_warnings

    for r in fleet.results:
        table = Table(title=f"shutdown robot: {r.robot}")
        for col in ("host", "result", "message", "time"):
            table.add_column(col, overflow="fold")
        for h in r.data.get("hosts", []):
            o = Outcome(h["outcome"])
            table.add_row(esc(h["robot"]), f"[{STYLE[o]}]{o.value}[/]", esc(h["message"]), f"{h['duration_s']:.1f} s")
        table.add_row(f"{esc(r.robot)} (Built-in Computer)", f"[{STYLE[r.outcome]}]{r.outcome.value}[/]",
                      esc(r.message), f"{r.duration_s:.1f} s")
        stdout().print(table)
    print_warnings(fleet)
    print_summary(fleet)
    return int(fleet.exit_code)


def register(root: typer.Typer) -> None:
    root.add_typer(app, name="shutdown")
