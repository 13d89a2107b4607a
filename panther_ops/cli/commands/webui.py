"""`panther-ops webui install|set|get|start|stop|status|url`: the WebUI snap on each robot's
User Computer, reached through the robot."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Optional

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.options import TARGETS, AskPassword, shared, sudo_password

app = typer.Typer(help="The husarion-webui snap on the robots' User Computers (through the robots).",
                  no_args_is_help=True)



@app.command("status")
@shared(*TARGETS, "json_out")
def status(fleet: Fleet, ask_sudo_password: AskPassword = False) -> int:
    """Installed revision and channel, every key, running or not, and whether
    http://<host>:<port>/ui answers (fetched on the robot).

    \b
    Example:
      panther-ops webui status --all
    """
    from panther_ops.core.remote.webui.read import status_task

    return fleet.run("webui status", status_task(sudo_password(ask_sudo_password)), read_only=True)


@app.command("get")
@shared(*TARGETS, "json_out")
def get(fleet: Fleet, ask_sudo_password: AskPassword = False) -> int:
    """Every key of the snap (`snap get -d husarion-webui`), defaults filled in.

    \b
    Example:
      panther-ops webui get -r panther-01 --json
    """
    from panther_ops.core.remote.webui.read import status_task

    return fleet.run("webui get", status_task(sudo_password(ask_sudo_password)), read_only=True)


@app.command("install")
@shared(*TARGETS, "json_out")
def install(fleet: Fleet, channel: Annotated[str, typer.Option("--channel", help="Snap channel.")] = "humble",
            ask_sudo_password: AskPassword = False) -> int:
    """Check the clocks of the User Computer, the robot and this machine (refused beyond 1 s,
    with the fix), then `sudo snap install husarion-webui --channel=humble`; idempotent.

    \b
    Example:
      panther-ops webui install -r panther-01 --ask-sudo-password
    """
    from panther_ops.core.kinds.webui_settings import PROFILE
    from panther_ops.core.remote.webui.install import install_task

    if not PROFILE.match(channel.replace("/", "_")):
        from panther_ops.errors import UsageError

        raise UsageError(f"--channel {channel!r} is not a snap channel", hint="e.g. humble or humble/edge")
    return fleet.run("webui install", install_task(channel, sudo_password(ask_sudo_password)))


def _start_stop(verb: str, start: bool, doc: str) -> Callable[..., int]:
    """`webui start` and `webui stop`: the same options and task, told which way to go."""

    def command(fleet: Fleet, ask_sudo_password: AskPassword = False) -> int:
        from panther_ops.core.remote.webui.apply import start_stop_task

        return fleet.run(f"webui {verb}", start_stop_task(start, sudo_password(ask_sudo_password)))

    command.__name__ = command.__qualname__ = verb
    command.__doc__ = doc
    return command


start = app.command("start")(shared(*TARGETS, "json_out")(_start_stop("start", True, """\
`sudo husarion-webui.start` where it is not running.

    \b
    Example:
      panther-ops webui start -r panther-01
    """)))
stop = app.command("stop")(shared(*TARGETS, "json_out")(_start_stop("stop", False, """\
`sudo husarion-webui.stop` where it runs.

    \b
    Example:
      panther-ops webui stop -r panther-01
    """)))


@app.command("url")
@shared(*TARGETS, "json_out")
def url(fleet: Fleet, ask_sudo_password: AskPassword = False) -> int:
    """The WebUI's addresses: on the robot's LAN and the Husarnet form (port from the snap).

    \b
    Example:
      panther-ops webui url -r panther-01
    """
    from panther_ops.core.remote.webui.read import url_task

    return fleet.run("webui url", url_task(sudo_password(ask_sudo_password)), read_only=True)


@app.command("set")
@shared(*TARGETS, "yes", "dry_run", "json_out", helps={"dry_run": "Only show the plan."})
def set_(
    fleet: Fleet,
    settings: Annotated[Optional[list[str]], typer.Argument(  # noqa: UP045
        help="KEY=VALUE: ros.namespace, ros.transport, ros.domain-id, ros.localhost-only, webui.layout, "
             "webui.port")] = None,
    dds_file: Annotated[Optional[Path], typer.Option(  # noqa: UP045
        "--dds-file", help="A DDS XML profile (Fast DDS <profiles> or <CycloneDDS> root, with its xmlns) "
        "to upload as dds-config-<name>.xml to the snap's common directory and select as <name>.")] = None,
    ask_sudo_password: AskPassword = False,
) -> int:
    """Validate KEY=VALUE with the snap configure hook's rules before anything is sent, show
    the plan (current -> new) per robot, confirm, `sudo snap set`, restart the WebUI where it
    was running, read back.

    \b
    Example:
      panther-ops webui set ros.transport=rmw_cyclonedds_cpp webui.layout=panther -r panther-01 --yes
    """
    from panther_ops.cli.mutate import Asking
    from panther_ops.core.remote.webui.read import read_and_plan_set

    wanted, dds = _wanted(settings or [], dds_file)  # before anything is contacted
    password = sudo_password(ask_sudo_password)
    asking = Asking(refusal=lambda _q: "webui set needs confirmation: pass --yes when not interactive (or --dry-run)",
                    nothing="nothing was sent to any robot", dry_note=lambda _names: "dry run: nothing was sent",
                    idle="nothing to change")
    return fleet.change("webui set", lambda c: read_and_plan_set(c, wanted, password, dds), asking=asking,
                        restart=False, sudo_password=password)


def _wanted(settings: list[str], dds_file: Path | None) -> tuple[dict[str, str], tuple[str, bytes] | None]:
    """KEY=VALUE arguments and the DDS profile, validated (UsageError: nothing is sent)."""
    from panther_ops.core.kinds.webui_settings import (
        SettingConflict,
        SettingError,
        canonical_key,
        dds_profile,
        validate,
    )
    from panther_ops.errors import UsageError

    pairs: dict[str, str] = {}
    given: dict[str, str] = {}  # the snap's key -> the argument that set it
    dds = None
    try:
        for item in settings:
            key, sep, value = item.partition("=")
            if not sep:
                raise UsageError(f"{item!r} is not KEY=VALUE", hint="e.g. webui.port=8081")
            snap_key = canonical_key(key.strip())
            if snap_key in given:  # the same key twice (or as its short name): which one is meant?
                raise SettingConflict(snap_key, given[snap_key], item)
            given[snap_key] = item
            pairs[key.strip()] = value
        if dds_file is not None:
            if "ros.transport" in given:
                raise SettingConflict("ros.transport", given["ros.transport"], f"--dds-file {dds_file}",
                                      "--dds-file uploads the profile and selects it as the transport: leave "
                                      "ros.transport out, or drop --dds-file to select another transport")
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
