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
from typing import TYPE_CHECKING, Annotated

import typer

from panther_ops.cli import context
from panther_ops.cli.commands.shutdown_inputs import (
    AskSecret,
    PowerBudget,
    SecretEnv,
    SecretFile,
    ask_to_confirm,
    refusal,
    secret_from,
    usage_error,
)
from panther_ops.cli.context import Fleet
from panther_ops.cli.options import READ, TARGETS, OptFloat, OptInt, OptPath, OptStr, port_number, real_number, shared
from panther_ops.cli.views.shutdown import finish_hosts, print_findings, print_steps

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Inventory, Robot
    from panther_ops.core.fleet.plan import RobotPlan
    from panther_ops.core.kinds.hostsfile import HostsFile
    from panther_ops.manager.shutdown_executor.hosts import ShutdownHost
    from panther_ops.results import FleetResult


app = typer.Typer(
    help="User computers that shut down with the robot: the hosts file, setup, check, shutdown.",
    invoke_without_command=True,
    no_args_is_help=False,
)


# =================================================================================================
# panther-ops shutdown --hosts FILE
# =================================================================================================
_YES = "Shut down without asking (needed when not interactive)."


@app.callback(invoke_without_command=True)
@shared("yes", "dry_run", "json_out", helps={"yes": _YES,
                                             "dry_run": "Show what would be sent to each host; contact nothing."})
def shutdown(
    fleet: Fleet,
    hosts: Annotated[OptPath, typer.Option("--hosts", help="Hosts file to shut down (the robot's format).")] = None,
    via: Annotated[OptStr, typer.Option("--via", metavar="ROBOT", help="Run through this robot (its LAN, its key "
                                        "and known_hosts), as its manager would.")] = None,
    identity: Annotated[OptPath, typer.Option("--identity", help="SSH key for the hosts (from here; default: "
                                              "~/.ssh/id_*).")] = None,
    known_hosts: Annotated[OptPath, typer.Option("--known-hosts", help="known_hosts for the hosts (from here; "
                                                 "default ~/.ssh/known_hosts).")] = None,
    power_budget: PowerBudget = 15.0,
) -> None:
    """Shut down the hosts of a hosts file, side by side, like the manager's ShutdownHostsFromFile:
    per host ping (no answer: skipped), the command over SSH or the signed HTTP request, then
    ping until it is gone or its timeout passes. Names every host and asks first (--yes).

    \b
    Example:
      panther-ops shutdown --hosts hosts.yaml --yes
    """
    if fleet.ctx.invoked_subcommand is not None:
        if hosts is not None or via is not None:
            raise usage_error("--hosts/--via go without a subcommand: panther-ops shutdown --hosts FILE")
        return
    if hosts is None:
        typer.echo(fleet.ctx.get_help())
        raise typer.Exit(0)
    raise typer.Exit(_shutdown_file(fleet, hosts, via, identity, known_hosts, power_budget))


def _shutdown_file(fleet: Fleet, path: Path, via: str | None, identity: Path | None, known_hosts: Path | None,
                   power_budget: float) -> int:
    from panther_ops.core.kinds.hostsfile import load_hosts_file

    for option, given in (("--identity", identity), ("--known-hosts", known_hosts)):
        if given is not None and not given.is_file():
            raise usage_error(f"{option} {given}: no such file")
    inv: Inventory | None = None
    link_robot: Robot | None = None
    if via is not None:  # the robot must exist and reach its LAN, dry run or not
        from panther_ops.core.shutdown.links import lan_robot

        inv = context.load(fleet.ctx)
        if via not in inv.robots:
            inv.select([via], [], False)  # no robot matches: exit 2 naming the robots
            raise usage_error(f"--via {via!r}: name one robot of the inventory (not a glob)")
        link_robot = lan_robot(inv, via)  # the dry run refuses what the real run would refuse
    parsed = load_hosts_file(path, power_budget=power_budget)
    print_findings(parsed)
    hosts = parsed.hosts()  # exit 2 on errors, before anything is contacted
    return _shutdown_hosts_change(fleet, path, parsed, hosts, (inv, link_robot) if inv and link_robot else None,
                                  known_hosts, identity)


def _shutdown_hosts_change(fleet: Fleet, path: Path, parsed: HostsFile, hosts: list[ShutdownHost],
                           via: tuple[Inventory, Robot] | None, known_hosts: Path | None, identity: Path | None) -> int:
    """The hosts of the file as the change's targets (core/shutdown/localfile.py), each planned
    and shut down by its step (core/shutdown/apply.py), through `fleet.change`."""
    from panther_ops.cli.mutate import Asking
    from panther_ops.core.shutdown.localfile import hosts_as_targets
    from panther_ops.core.shutdown.plan import ShutdownFileHost, plan_file_host

    names = [e.describe() for e in parsed.entries]
    inv, targets = hosts_as_targets(path, names, via)
    where = f"through {via[1].name}" if via else "from here"
    kh, key = str(known_hosts) if known_hosts else None, str(identity) if identity else None
    steps = {name: ShutdownFileHost(host, via[1].name if via else None, kh, key)
             for name, host in zip(names, hosts, strict=True)}
    rows = {e.describe(): e.row() for e in parsed.entries}
    warned = {name: [str(w) for w in parsed.warnings if w.where.startswith(f"hosts[{e.index}]")]
              for name, e in zip(names, parsed.entries, strict=True)}

    def question(to_change: list[str], _plans: object) -> str:
        return f"Shut down {len(to_change)} host(s) {where}: {', '.join(to_change)}?"

    asking = Asking(question=question, refusal=lambda q: refusal(q, "shutting hosts down"), nothing="nothing was done",
                    dry_note=lambda _names: "dry run: nothing was contacted",
                    idle=f"{path}: no hosts, nothing to shut down")
    return fleet.change(f"shutdown --hosts {path.name}" + (f" --via {via[1].name}" if via else ""),
                        lambda c: plan_file_host(c.robot.name, rows[c.robot.name], steps[c.robot.name],
                                                 warned[c.robot.name]),
                        on=(inv, targets), restart=False, asking=asking, view=_show_hosts)


def _show_hosts(fleet: FleetResult) -> None:
    finish_hosts(fleet, False)


# =================================================================================================
# panther-ops shutdown setup / check / robot
# =================================================================================================
@app.command("setup")
@shared(*TARGETS, "yes", "no_restart", "settle", "json_out", helps={
    "yes": "Trust the computer's host key (check the fingerprint shown first) and apply without asking."})
def setup(
    fleet: Fleet,
    host: Annotated[str, typer.Option("--host", help="Address of the user computer on the robot's LAN.")],
    user: Annotated[OptStr, typer.Option("--user", "-u", help="User on the computer (SSH era; default "
                                         "husarion).")] = None,
    port: Annotated[OptInt, typer.Option("--port", parser=port_number(),
                                                  help="SSH port (22) or husarion-shutdown port (3003).")] = None,
    timeout: Annotated[OptFloat, typer.Option("--timeout", parser=real_number(),
                                              help="The host's timeout in the hosts file.")] = None,
    ask_password: Annotated[bool, typer.Option("--ask-password", help="Ask the user's password (login once and "
                                               "sudo on the computer); never on the command line, never "
                                               "logged.")] = False,
    secret_env: SecretEnv = None,
    secret_file: SecretFile = None,
    ask_secret: AskSecret = False,
    power_budget: PowerBudget = 15.0,
) -> int:
    """Set a user computer up to be shut down by the robot, through the robot (the computer sits on
    its LAN): the robot's key pair (~/.ssh/id_rsa, mounted into the driver), its public key in
    the user's authorized_keys (once), the computer's host key in the robot's known_hosts
    (fingerprint shown, --yes), /etc/sudoers.d/panther-shutdown (poweroff, reboot, shutdown
    without a password; checked with visudo, 0440), and the host in the robot's hosts file.
    On 2.2.1+ robots: checks husarion-shutdown and its secret instead. Re-running changes nothing.

    \b
    Example:
      panther-ops shutdown setup -r panther-01 --host 10.15.20.3 --user husarion --ask-password
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
    inv, chosen = fleet.targets()
    if len(chosen) != 1:
        raise usage_error(f"setup works on one robot at a time ({len(chosen)} chosen)")
    password = Secret(getpass.getpass(f"password of {user or 'husarion'}@{host}: ")) if ask_password else None

    refused: list[str] = []

    def confirm(address: str, fp: str) -> bool:
        context.info(f"{host} offers the host key {fp}")
        if not fleet.yes and not sys.stdin.isatty():
            refused.append(address)
        return ask_to_confirm(f"Trust {address} ({fp}) and record it in {chosen[0].name}'s ~/.ssh/known_hosts?",
                              fleet.yes, "trusting a new host key")

    req = SetupRequest(ip=host, user=user, port=port, timeout=timeout, password=password, secret=secret,
                       operator_keys=tuple(r for r in (chosen[0].identity_file,) if r), confirm_host_key=confirm,
                       settle=fleet.settle, restart=not fleet.no_restart, power_budget=power_budget,
                       command=f"shutdown setup --host {host}")
    code = fleet.run("shutdown setup", lambda c: run_setup(c, req), print_steps, on=(inv, chosen))
    return 2 if refused else code


@app.command("check")
@shared(*READ)
def check(fleet: Fleet, power_budget: PowerBudget = 15.0) -> int:
    """Prove, from each robot, that every host of its hosts file would power off, without powering
    it off: ping, host key, login with the robot's key (batch), `sudo -n -l <command>`; HTTP hosts:
    the service answers and accepts the secret. Names the failing step and its fix.

    \b
    Example:
      panther-ops shutdown check -r panther-01
    """
    from panther_ops.cli.views.shutdown import print_check
    from panther_ops.core.shutdown.check import check_robot

    return fleet.run("shutdown check", lambda c: check_robot(c, power_budget), print_check)


@app.command("robot")
@shared(*TARGETS, "yes", "dry_run", "json_out", "forks", helps={
    "yes": _YES, "dry_run": "Show the robots and hosts; contact no host."})
def robot_(fleet: Fleet, power_budget: PowerBudget = 15.0) -> int:
    """Shut each robot down as its Shutdown tree does: the hosts of its hosts file first, side by
    side and from the robot (their failures do not stop it), then the Built-in Computer.
    Names the robot and every host and asks first (--yes).

    \b
    Example:
      panther-ops shutdown robot -r panther-01 --yes
    """
    from panther_ops.cli.mutate import Asking
    from panther_ops.cli.views.shutdown import print_robots_down
    from panther_ops.core.shutdown.plan import ShutdownRobot
    from panther_ops.core.shutdown.run import plan_robot_shutdown

    def asked(names: list[str], plans: dict[str, RobotPlan]) -> str:
        hosts = {n: ", ".join(h.describe() for s in plans[n].steps if isinstance(s, ShutdownRobot)
                              for h in s.plan.hosts) or "no hosts" for n in names}
        return f"Shut down {'; '.join(f'{n} after {hosts[n]}' for n in names)}?"

    asking = Asking(question=asked, refusal=lambda question: refusal(question, "shutting robots down"),
                    nothing="nothing was shut down")
    return fleet.change("shutdown robot", lambda c: plan_robot_shutdown(c, power_budget), asking=asking,
                        restart=False, view=print_robots_down)


def register(root: typer.Typer) -> None:
    from panther_ops.cli.commands.shutdown_hosts import hosts_app

    app.add_typer(hosts_app, name="hosts")
    root.add_typer(app, name="shutdown")
