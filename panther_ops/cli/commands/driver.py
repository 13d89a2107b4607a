"""`panther-ops driver status|logs|restart|versions|update` and `config restore-defaults`."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Annotated, Any, Optional

import typer

from panther_ops.cli import context
from panther_ops.cli.mutate import DryRun, NoRestart, Settle, Yes, mutate
from panther_ops.cli.options import All, Canary, Forks, Groups, Json, MaxFail, Robots

if TYPE_CHECKING:
    from panther_ops.results import FleetResult

app = typer.Typer(
    help="The driver container (panther_ros / husarion_ugv_ros): status, logs, restart, image versions, update.",
    no_args_is_help=True,
)

REGISTRY_ENV = "PANTHER_OPS_DOCKERHUB_URL"
"""Override of the Docker Hub tag-list URL (``{repo}`` = panther / husarion-ugv): a mirror, or tests."""


# ------------------------------------------------------------------ status


def _print_status(fleet: FleetResult) -> None:
    from rich.table import Table

    from panther_ops.cli.render import STYLE, _console, esc, print_summary, print_warnings
    from panther_ops.core.containers.times import human_duration

    table = Table(title="panther-ops driver status")
    for col in ("robot", "result", "service", "image", "state", "uptime", "restarts", "exit", "health", "command"):
        table.add_column(col, overflow="fold")
    for r in fleet.results:
        d = r.data
        if "state" not in d or d.get("state") == "missing":
            table.add_row(r.robot, f"[{STYLE[r.outcome]}]{r.outcome.value}[/]", esc(d.get("service", "")),
                          esc(d.get("compose_image") or ""), esc(r.message), "", "", "", "", "")
            continue
        drift = d.get("command_drift")
        table.add_row(
            r.robot, f"[{STYLE[r.outcome]}]{r.outcome.value}[/]", esc(d["service"]), esc(d.get("image") or ""),
            esc(d["state"]), human_duration(d.get("uptime_s")) if d.get("uptime_s") is not None else "-",
            str(d.get("restart_count", "")), str(d.get("exit_code", "")), esc(d.get("health") or "-"),
            "[yellow]differs from compose.yaml[/]" if drift else ("as compose.yaml" if drift is False else "?"),
        )
    _console().print(table)
    print_warnings(fleet)
    print_summary(fleet)


@app.command("status")
def status(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """The driver container of each robot (its service from compose.yaml): image, state, uptime,
    start time, restart count, exit code, health, and whether it runs compose.yaml's image and
    launch command (else a warning: recreate it with `driver restart`).

    A driver that is not running (exited, restarting, unhealthy, missing) is `failed` (exit 3).
    A demo robot has no docker engine: `skipped`.

    Example: panther-ops driver status --all
    """
    from panther_ops.cli.render import finish
    from panther_ops.core.driver.containers import status_task

    inv, chosen = context.targets(ctx, robot, group, all_, read_only=True)
    return finish(context.run("driver status", inv, chosen, status_task, forks=forks, json_out=json_out), json_out,
                  _print_status)


# ------------------------------------------------------------------ logs


@app.command("logs")
def logs(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    lines: Annotated[
        Optional[int],  # noqa: UP045
        typer.Option("--lines", "-n", min=0, help="Last N lines of each robot (default 100; 0 with -f: only new)."),
    ] = None,
    since: Annotated[
        Optional[str],  # noqa: UP045
        typer.Option("--since", help="Only lines newer than DURATION (90s, 10m, 1h30m, 2d; robot's clock)."),
    ] = None,
    follow: Annotated[bool, typer.Option("--follow", "-f", help="Keep printing new lines (one robot; Ctrl-C ends).")]
    = False,
    timestamps: Annotated[bool, typer.Option("--timestamps", "-t", help="Docker's timestamp on each line.")] = False,
    json_out: Json = False,
) -> int:
    """The driver container's output (stdout and stderr), as `docker logs` shows it. With several
    robots every line starts with `<robot> | `, robots one after the other.

    Examples:
      panther-ops driver logs -r panther-01 -n 50
      panther-ops driver logs -g warehouse --since 10m
      panther-ops driver logs -r panther-01 -f
    """
    from panther_ops.cli.logs_view import show_logs
    from panther_ops.core.containers.engine import NoEngineError
    from panther_ops.core.driver.containers import open_logs, parse_duration

    since_s = parse_duration(since) if since is not None else None
    inv, chosen = context.targets(ctx, robot, group, all_)
    return show_logs("driver logs", inv, chosen, open_logs, lines=lines, since_s=since_s, timestamps=timestamps,
                     follow=follow, json_out=json_out, skip=(NoEngineError,))


# ------------------------------------------------------------------ restart


@app.command("restart")
def restart(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    yes: Yes = False,
    dry_run: DryRun = False,
    settle: Settle = 5.0,
    json_out: Json = False,
    forks: Forks = None,
    canary: Canary = 0,
    max_fail: MaxFail = None,
) -> int:
    """Recreate the driver container: `docker compose up -d --force-recreate <driver service>` as
    the robot user in a login shell (what Husarion's configurator does), then check it keeps
    running, unrestarted, with compose.yaml's launch command for --settle seconds.

    `changed` when it came back up, `failed` (exit 3) when it did not (see `driver logs`).

    Example: panther-ops driver restart -r panther-01 --yes
    """
    from panther_ops.core.driver.restart import apply_restart, plan_restart

    inv, chosen = context.targets(ctx, robot, group, all_)
    return mutate("driver restart", inv, chosen, plan_restart, applier=apply_restart, yes=yes, dry_run=dry_run,
                   settle=settle, json_out=json_out, forks=forks, canary=canary, max_fail=max_fail, verb="Recreate")


# ------------------------------------------------------------------ versions


def _print_versions(fleet: FleetResult) -> None:
    from rich.table import Table

    from panther_ops.cli.render import STYLE, _console, esc, human_bytes, print_summary, print_warnings

    table = Table(title="panther-ops driver versions (on each robot)")
    for col in ("robot", "result", "image", "", "id", "size"):
        table.add_column(col, overflow="fold")
    for r in fleet.results:
        images = r.data.get("local")
        if not images:
            table.add_row(r.robot, f"[{STYLE[r.outcome]}]{r.outcome.value}[/]", esc(r.message), "", "", "")
            continue
        for i, e in enumerate(images):
            mark = ", ".join(m for m, on in (("in use", e["in_use"]), ("compose.yaml", e["in_compose"])) if on)
            table.add_row(r.robot if i == 0 else "", f"[{STYLE[r.outcome]}]{r.outcome.value}[/]" if i == 0 else "",
                          esc(e["image"]), f"[bold]{mark}[/]" if mark else "", e["id"].removeprefix("sha256:")[:12],
                          human_bytes(e.get("size")))
    _console().print(table)
    remote = fleet.data.get("remote")
    if remote:
        rt = Table(title="Docker Hub (released Humble tags)")
        rt.add_column("repository")
        rt.add_column("tags, newest first", overflow="fold")
        for repo, info in remote.items():
            rt.add_row(repo, esc(", ".join(t["tag"] for t in info["tags"])) if "tags" in info
                       else f"[red]{esc(info['error'])}[/]")
        _console().print(rt)
        for r in fleet.results:
            if r.data.get("newer"):
                _console().print(f"{r.robot}: newer than {esc(r.data['compose_image'])}: "
                                 f"{esc(', '.join(r.data['newer']))}")
    print_warnings(fleet)
    print_summary(fleet)


@app.command("versions")
def versions(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    remote: Annotated[bool, typer.Option("--remote", help="Also ask Docker Hub (from this machine) for the "
                                         "released Humble tags.")] = False,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """The driver images each robot has locally (husarion/panther, husarion/husarion-ugv), marking
    the one the driver container runs and the one compose.yaml names. --remote lists Docker Hub's
    released Humble tags (humble-X.Y.Z-YYYYMMDD[-stable]) and, per robot, the newer ones of its
    repository; asked from this machine with a 5 s timeout, "registry unreachable" otherwise.

    Examples:
      panther-ops driver versions --all
      panther-ops driver versions -r panther-01 --remote
    """
    from panther_ops.cli.render import finish
    from panther_ops.core.driver.containers import versions_task
    from panther_ops.core.driver.hub import fetch_hub_tags
    from panther_ops.core.driver.images import DRIVER_REPOS, HUB_URL, HubTag, RegistryError

    inv, chosen = context.targets(ctx, robot, group, all_, read_only=True)
    tags: dict[str, list[HubTag]] | None = None
    remote_data: dict[str, Any] = {}
    notes: list[str] = []
    if remote:
        tags = {}
        url = os.environ.get(REGISTRY_ENV) or HUB_URL
        for repo in DRIVER_REPOS:
            try:
                tags[repo] = fetch_hub_tags(repo, url_template=url)
                remote_data[repo] = {"tags": [t.to_json() for t in tags[repo]]}
            except RegistryError as exc:
                remote_data[repo] = {"error": exc.message}
                notes.append(f"{repo}: {exc.message}")
    fleet = context.run("driver versions", inv, chosen, versions_task(tags), forks=forks, json_out=json_out)
    if remote:
        fleet.data["remote"] = remote_data
        fleet.notes.extend(notes)
    return finish(fleet, json_out, _print_versions)


# ------------------------------------------------------------------ update


@app.command("update")
def update(
    ctx: typer.Context,
    tag: Annotated[
        Optional[str],  # noqa: UP045
        typer.Argument(help="Tag (humble-2.1.2-20241125) or image (husarion/panther:humble-...); "
                            "default: the inventory's desired image."),
    ] = None,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    pull: Annotated[bool, typer.Option("--pull", help="docker compose pull the driver before recreating it "
                                       "(the robot needs internet).")] = False,
    yes: Yes = False,
    dry_run: DryRun = False,
    no_restart: NoRestart = False,
    settle: Settle = 5.0,
    force: Annotated[bool, typer.Option("--force", help="Allow a move between husarion/panther (<=2.1) and "
                                        "husarion/husarion-ugv (2.2), or a repository not matching the version.")]
    = False,
    json_out: Json = False,
    forks: Forks = None,
    canary: Canary = 0,
    max_fail: MaxFail = None,
) -> int:
    """Change the driver image in compose.yaml and recreate the driver, through the pipeline:
    plan, diff, confirm, backup, atomic write, recreate, verify, roll back on failure.

    Humble tags only (Jazzy, 2.3+, is refused). A tag takes the repository of its version; a
    move between panther_ros (<=2.1, husarion/panther, service panther_ros) and husarion_ugv_ros
    (2.2, husarion/husarion-ugv, service husarion_ugv_ros) is a reinstall and needs --force (then
    the service is renamed, the launch package and arguments migrated). A tag not on the robot is
    pulled by `docker compose up` (warned in the plan), or first with --pull; a failed pull rolls
    back. Bad tags exit 2 before anything is changed anywhere.

    Examples:
      panther-ops driver update humble-2.1.1-20240828 -g warehouse --dry-run
      panther-ops driver update humble-2.1.2-20241125 -r panther-01 --pull --yes
    """
    from panther_ops.core.driver.images import parse_target
    from panther_ops.core.driver.update import apply_update, plan_update

    target = parse_target(tag, force=force) if tag is not None else None
    inv, chosen = context.targets(ctx, robot, group, all_)
    command = f"driver update {tag}" if tag else "driver update (desired image)"
    return mutate(command, inv, chosen, lambda c: plan_update(c, target, force=force, pull=pull), applier=apply_update,
                   yes=yes, dry_run=dry_run, restart=not no_restart, settle=settle, json_out=json_out, forks=forks,
                   canary=canary, max_fail=max_fail)


# ------------------------------------------------------------------ config restore-defaults


def restore_defaults(
    ctx: typer.Context,
    robot: Robots = None,
    group: Groups = None,
    all_: All = False,
    hard: Annotated[bool, typer.Option("--hard", help="2.2: first remove everything in ~/config but common/ "
                                       "(Husarion's `restore_default hard`).")] = False,
    yes: Yes = False,
    dry_run: DryRun = False,
    no_restart: NoRestart = False,
    settle: Settle = 5.0,
    json_out: Json = False,
    forks: Forks = None,
) -> int:
    """Put each robot's driver configuration back to the image's defaults.

    2.2 (husarion_ugv_ros): ~/config is archived to ~/.panther-ops/backups/<id>/config.tar.gz, then
    `docker run --rm -v ~/config:/config <driver image> update_config_directory` runs as the robot
    user, and the driver is recreated and verified; on failure ~/config is restored from the archive.

    2.0/2.1 (panther_ros): the mounts from ~/config and the *_config_path / *_file / *_path launch
    arguments pointing into /config (what `config push` added) are removed through the pipeline:
    diff, confirm, backup, write, recreate, verify, roll back. The files stay in ~/config.

    Example: panther-ops config restore-defaults -r panther-01 --dry-run
    """
    from panther_ops.core.driver.restore import apply_restore, plan_restore_defaults

    inv, chosen = context.targets(ctx, robot, group, all_)
    return mutate("config restore-defaults" + (" --hard" if hard else ""), inv, chosen,
                   lambda c: plan_restore_defaults(c, hard=hard), applier=apply_restore, yes=yes, dry_run=dry_run,
                   restart=not no_restart, settle=settle, json_out=json_out, forks=forks)


def register(root: typer.Typer) -> None:
    from panther_ops.cli.commands import config

    root.add_typer(app, name="driver")
    config.app.command("restore-defaults")(restore_defaults)
