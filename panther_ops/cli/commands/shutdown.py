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
from panther_ops.cli.mutate import NoRestart, Settle
from panther_ops.cli.options import All, Forks, Groups, Json, Robots, finite
from panther_ops.cli.shutdown_view import (
    esc,
    finish_hosts,
    finish_steps,
    print_findings,
    print_plan,
    stdout,
)

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Inventory, Robot
    from panther_ops.results import RobotResult
    from panther_ops.secret import Secret


app = typer.Typer(
    help="User computers that shut down with the robot: the hosts file, setup, check, shutdown.",
    invoke_without_command=True,
    no_args_is_help=False,
)




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


def usage_error(message: str, hint: str | None = None) -> Exception:
    from panther_ops.errors import UsageError

    return UsageError(message, hint=hint)


def ask_to_confirm(question: str, yes: bool, what: str) -> bool:
    if yes:
        return True
    if not sys.stdin.isatty():
        from panther_ops.cli.render import error

        error(f"{question} -- {what} needs confirmation: pass --yes when not interactive (or --dry-run to only "
              "look)")
        return False
    return bool(typer.confirm(question, default=False))


def secret_from(env: str | None, file: Path | None, ask: bool) -> Secret | None:
    import getpass
    import os

    from panther_ops.secret import Secret

    given = [x for x in (env, file, ask or None) if x]
    if len(given) > 1:
        raise usage_error("give the secret one way: --secret-env, --secret-file or --ask-secret")
    if env:
        value = os.environ.get(env)
        if value is None:
            raise usage_error(f"--secret-env {env}: the variable is not set")
        return Secret(value)
    if file:
        try:
            return Secret(file.read_text().strip())
        except OSError as exc:
            raise usage_error(f"--secret-file {file}: {exc.strerror}") from None
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
            raise usage_error("--hosts/--via go without a subcommand: panther-ops shutdown --hosts FILE")
        return
    if hosts is None:
        typer.echo(ctx.get_help())
        raise typer.Exit(0)
    raise typer.Exit(_shutdown_file(ctx, hosts, via, identity, known_hosts, yes, dry_run, power_budget, json_out))


def _shutdown_file(ctx: typer.Context, path: Path, via: str | None, identity: Path | None,
                   known_hosts: Path | None, yes: bool, dry_run: bool, power_budget: float, json_out: bool) -> int:
    from panther_ops.core.kinds.hostsfile import load_hosts_file
    from panther_ops.core.shutdown.run import shutdown_hosts

    for option, given in (("--identity", identity), ("--known-hosts", known_hosts)):
        if given is not None and not given.is_file():
            raise usage_error(f"{option} {given}: no such file")
    inv: Inventory | None = None
    link_robot: Robot | None = None
    if via is not None:  # the robot must exist and reach its LAN, dry run or not
        from panther_ops.core.shutdown.remote import lan_robot

        inv = context.load(ctx)
        if via not in inv.robots:
            inv.select([via], [], False)  # no robot matches: exit 2 naming the robots
            raise usage_error(f"--via {via!r}: name one robot of the inventory (not a glob)")
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
    if not ask_to_confirm(f"Shut down {len(hosts)} host(s) {where}: {names}?", yes, "shutting hosts down"):
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

    from panther_ops.core.kinds.hostsfile import check_entry, new_entry
    from panther_ops.core.shutdown.setup import SetupRequest, run_setup
    from panther_ops.secret import Secret

    errors = [f for f in check_entry(new_entry(host, username=user or "husarion", port=port, timeout=timeout))
              if f.level == "error"]
    if errors:
        raise usage_error("; ".join(str(f) for f in errors), hint="nothing was changed")
    secret = secret_from(secret_env, secret_file, ask_secret)
    inv, chosen = context.targets(ctx, robot, group, all_)
    if len(chosen) != 1:
        raise usage_error(f"setup works on one robot at a time ({len(chosen)} chosen)")
    password = Secret(getpass.getpass(f"password of {user or 'husarion'}@{host}: ")) if ask_password else None

    refused: list[str] = []

    def confirm(address: str, fp: str) -> bool:
        context.info(f"{host} offers the host key {fp}")
        if not yes and not sys.stdin.isatty():
            refused.append(address)
        return ask_to_confirm(f"Trust {address} ({fp}) and record it in {chosen[0].name}'s ~/.ssh/known_hosts?", yes,
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
    from panther_ops.core.shutdown.plan_hosts import RobotShutdownPlan
    from panther_ops.core.shutdown.run import plan_robot_shutdown, shutdown_robot
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
        if not ask_to_confirm(f"Shut down {what}?", yes, "shutting robots down"):
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
    from panther_ops.cli.commands.shutdown_hosts import hosts_app

    app.add_typer(hosts_app, name="hosts")
    root.add_typer(app, name="shutdown")
