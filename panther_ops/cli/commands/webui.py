"""`panther-ops webui install|set|get|start|stop|status|url`: the WebUI snap on each robot's
User Computer, reached through the robot."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated, Optional

import typer

from panther_ops.cli import context
from panther_ops.cli.options import All, AskPassword, Groups, Json, Robots, sudo_password

app = typer.Typer(help="The husarion-webui snap on the robots' User Computers (through the robots).",
                  no_args_is_help=True)

_PRELOAD = ("panther_ops.core.remote.webui.remote", "fabric")


def _run(ctx: typer.Context, command: str, task_of: object, robot: list[str] | None, group: list[str] | None,
         all_: bool, json_out: bool) -> int:
    from panther_ops.cli.render import finish, print_results

    inv, chosen = context.targets(ctx, robot, group, all_, preload=_PRELOAD)
    fleet = context.run(command, inv, chosen, task_of, json_out=json_out)  # type: ignore[arg-type]
    return finish(fleet, json_out, print_results)


@app.command("status")
def status(ctx: typer.Context, robot: Robots = None, group: Groups = None, all_: All = False,
           ask_sudo_password: AskPassword = False, json_out: Json = False) -> int:
    """Installed revision and channel, every key, running or not, and whether
    http://<host>:<port>/ui answers (fetched on the robot).

    Example: panther-ops webui status --all
    """
    from panther_ops.core.remote.webui.remote import status_task

    return _run(ctx, "webui status", status_task(sudo_password(ask_sudo_password)), robot, group, all_, json_out)


@app.command("get")
def get(ctx: typer.Context, robot: Robots = None, group: Groups = None, all_: All = False,
        ask_sudo_password: AskPassword = False, json_out: Json = False) -> int:
    """Every key of the snap (`snap get -d husarion-webui`), defaults filled in.

    Example: panther-ops webui get -r panther-01 --json
    """
    return status(ctx, robot, group, all_, ask_sudo_password, json_out)


@app.command("install")
def install(ctx: typer.Context, robot: Robots = None, group: Groups = None, all_: All = False,
            channel: Annotated[str, typer.Option("--channel", help="Snap channel.")] = "humble",
            ask_sudo_password: AskPassword = False, json_out: Json = False) -> int:
    """Check the clocks of the User Computer, the robot and this machine (refused beyond 1 s,
    with the fix), then `sudo snap install husarion-webui --channel=humble`; idempotent.

    Example: panther-ops webui install -r panther-01 --ask-sudo-password
    """
    from panther_ops.core.kinds.webui_settings import PROFILE
    from panther_ops.core.remote.webui.install import install_task

    if not PROFILE.match(channel.replace("/", "_")):
        from panther_ops.errors import UsageError

        raise UsageError(f"--channel {channel!r} is not a snap channel", hint="e.g. humble or humble/edge")
    return _run(ctx, "webui install", install_task(channel, sudo_password(ask_sudo_password)), robot, group, all_,
                json_out)


@app.command("start")
def start(ctx: typer.Context, robot: Robots = None, group: Groups = None, all_: All = False,
          ask_sudo_password: AskPassword = False, json_out: Json = False) -> int:
    """`sudo husarion-webui.start` where it is not running.

    Example: panther-ops webui start -r panther-01
    """
    from panther_ops.core.remote.webui.remote import start_stop_task

    return _run(ctx, "webui start", start_stop_task(True, sudo_password(ask_sudo_password)), robot, group, all_,
                json_out)


@app.command("stop")
def stop(ctx: typer.Context, robot: Robots = None, group: Groups = None, all_: All = False,
         ask_sudo_password: AskPassword = False, json_out: Json = False) -> int:
    """`sudo husarion-webui.stop` where it runs.

    Example: panther-ops webui stop -r panther-01
    """
    from panther_ops.core.remote.webui.remote import start_stop_task

    return _run(ctx, "webui stop", start_stop_task(False, sudo_password(ask_sudo_password)), robot, group, all_,
                json_out)


@app.command("url")
def url(ctx: typer.Context, robot: Robots = None, group: Groups = None, all_: All = False,
        ask_sudo_password: AskPassword = False, json_out: Json = False) -> int:
    """The WebUI's addresses: on the robot's LAN and the Husarnet form (port from the snap).

    Example: panther-ops webui url -r panther-01
    """
    from panther_ops.core.remote.webui.remote import url_task

    return _run(ctx, "webui url", url_task(sudo_password(ask_sudo_password)), robot, group, all_, json_out)


@app.command("set")
def set_(
    ctx: typer.Context,
    settings: Annotated[Optional[list[str]], typer.Argument(  # noqa: UP045
        help="KEY=VALUE: ros.namespace, ros.transport, ros.domain-id, ros.localhost-only, webui.layout, "
             "webui.port")] = None,
    dds_file: Annotated[Optional[Path], typer.Option(  # noqa: UP045
        "--dds-file", help="A DDS XML profile to upload to the snap's common directory and select.")] = None,
    robot: Robots = None, group: Groups = None, all_: All = False,
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Apply without asking.")] = False,
    dry_run: Annotated[bool, typer.Option("--dry-run", help="Only show the plan.")] = False,
    ask_sudo_password: AskPassword = False, json_out: Json = False,
) -> int:
    """Validate KEY=VALUE with the snap configure hook's rules before anything is sent, show
    the plan (current -> new) per robot, confirm, `sudo snap set`, restart the WebUI where it
    was running, read back.

    Example: panther-ops webui set ros.transport=rmw_cyclonedds_cpp webui.layout=panther -r panther-01 --yes
    """
    from panther_ops.cli.render import finish, print_results
    from panther_ops.core.fleet.runner import Connections, RunOptions, run_fleet
    from panther_ops.core.remote.webui.remote import set_apply_task, set_plan_task

    wanted, dds = _wanted(settings or [], dds_file)  # before anything is contacted
    password = sudo_password(ask_sudo_password)
    inv, chosen = context.targets(ctx, robot, group, all_, preload=_PRELOAD)
    with Connections(inv) as conns:
        plan_wanted = dict(wanted)
        if dds is not None:  # the profile is uploaded before the set: its presence is not a refusal
            plan_wanted.pop("ros.transport", None)
        planned = run_fleet("webui set", inv, chosen, set_plan_task(plan_wanted, password),
                            RunOptions(forks=inv.forks), connections=conns)
        if dds is not None:
            for r in planned.results:
                r.data["ready"] = r.outcome.value == "ok"
        refused = [r for r in planned.results if r.data.get("refused")]
        if refused:  # bad input for a robot (e.g. no such DDS profile there): nothing is sent anywhere
            from panther_ops.errors import UsageError

            raise UsageError("; ".join(f"{r.robot}: {r.data['refused']}" for r in refused),
                             hint="nothing was sent to any robot")
        ready = [r for r in chosen if any(x.robot == r.name and x.data.get("ready") for x in planned.results)]
        if dry_run or not ready:
            planned.notes.append("dry run: nothing was sent" if dry_run else "nothing to change")
            return finish(planned, json_out, print_results)
        if not json_out:
            print_results(planned, title="webui set: plan")
        if not yes:
            if not sys.stdin.isatty():
                from panther_ops.cli.render import error

                error("webui set needs confirmation: pass --yes when not interactive (or --dry-run)")
                return 2
            if not typer.confirm(f"Apply to {', '.join(r.name for r in ready)}?", default=False):
                return 2
        done = run_fleet("webui set", inv, ready, set_apply_task(wanted, password, dds), RunOptions(forks=inv.forks),
                         connections=conns)
    by_name = {r.robot: r for r in done.results}
    planned.results = [by_name.get(r.robot, r) for r in planned.results]
    return finish(planned, json_out, print_results)


def _wanted(settings: list[str], dds_file: Path | None) -> tuple[dict[str, str], tuple[str, bytes] | None]:
    """KEY=VALUE arguments and the DDS profile, validated (UsageError: nothing is sent)."""
    from panther_ops.core.kinds.webui_settings import SettingError, dds_profile, validate
    from panther_ops.errors import UsageError

    pairs: dict[str, str] = {}
    for item in settings:
        key, sep, value = item.partition("=")
        if not sep:
            raise UsageError(f"{item!r} is not KEY=VALUE", hint="e.g. webui.port=8081")
        pairs[key.strip()] = value
    dds = None
    try:
        if dds_file is not None:
            try:
                data = dds_file.read_bytes()
            except OSError as exc:
                raise UsageError(f"{dds_file}: cannot read ({exc.strerror})") from None
            dds = dds_profile(dds_file.name, data)
            pairs["ros.transport"] = dds[0]
        if not pairs:
            raise UsageError("nothing to set", hint="KEY=VALUE ... or --dds-file FILE")
        return validate(pairs), dds
    except SettingError as exc:
        raise UsageError(f"{dds_file if exc.key == '--dds-file' else 'webui set'}: {exc}",
                         hint="nothing was sent") from None
