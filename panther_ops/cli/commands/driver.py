"""`panther-ops driver status|logs|restart|stop|start|versions|update` and `config restore-defaults`."""

from __future__ import annotations

import os
from typing import Annotated, Any

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.options import GATED, READ, RECREATE, TARGETS, WRITE, Follow, Lines, OptStr, Timestamps, shared

app = typer.Typer(
    help=("The driver container (panther_ros / husarion_ugv_ros): status, logs, restart, stop, start, image "
          "versions, update."),
    no_args_is_help=True,
)

REGISTRY_ENV = "PANTHER_OPS_DOCKERHUB_URL"
"""Override of the Docker Hub tag-list URL (``{repo}`` = panther / husarion-ugv): a mirror, or tests."""


# ------------------------------------------------------------------ status


@app.command("status")
@shared(*READ)
def status(fleet: Fleet) -> int:
    """The driver container of each robot (its service from compose.yaml): image, state, uptime,
    start time, restart count, exit code, health, and whether it runs compose.yaml's image and
    launch command (else a warning: recreate it with `driver restart`).

    A driver that is not running (exited, restarting, unhealthy, missing) is `failed` (exit 3).
    A demo robot has no docker engine: `skipped`.

    \b
    Example:
      panther-ops driver status --all
    """
    from panther_ops.cli.views.driver import print_status
    from panther_ops.core.driver.containers import status_task

    return fleet.run("driver status", status_task, print_status, read_only=True)


# ------------------------------------------------------------------ logs


@app.command("logs")
@shared(*TARGETS, "json_out")
def logs(
    fleet: Fleet,
    lines: Lines = None,
    since: Annotated[OptStr, typer.Option(
        "--since", help="Only lines newer than DURATION (90s, 10m, 1h30m, 2d; robot's clock).")] = None,
    follow: Follow = False,
    timestamps: Timestamps = False,
) -> int:
    """The driver container's output (stdout and stderr), as `docker logs` shows it. With several
    robots every line starts with `<robot> | `, robots one after the other.

    \b
    Examples:
      panther-ops driver logs -r panther-01 -n 50
      panther-ops driver logs -g warehouse --since 10m
      panther-ops driver logs -r panther-01 -f
    """
    from panther_ops.cli.views.logs import show_logs
    from panther_ops.core.containers.engine import NoEngineError
    from panther_ops.core.driver.containers import open_logs, parse_duration

    since_s = parse_duration(since) if since is not None else None
    inv, chosen = fleet.targets(read_only=not follow)  # reading every robot; following one is chosen
    return show_logs("driver logs", inv, chosen, open_logs, lines=lines, since_s=since_s, timestamps=timestamps,
                     follow=follow, json_out=fleet.json_out, skip=(NoEngineError,))


# ------------------------------------------------------------------ restart


@app.command("restart")
@shared(*RECREATE, "canary", "max_fail")
def restart(fleet: Fleet) -> int:
    """Recreate the driver container: `docker compose up -d --force-recreate <driver service>` as
    the robot user in a login shell (what Husarion's configurator does), then check it keeps
    running, unrestarted, with compose.yaml's launch command: ready after 2 s up, at most --settle seconds.

    `changed` when it came back up, `failed` (exit 3) when it did not (see `driver logs`).

    \b
    Example:
      panther-ops driver restart -r panther-01 --yes
    """
    from panther_ops.core.driver.read import read_and_plan_restart

    return fleet.change("driver restart", read_and_plan_restart, verb="Recreate")


@app.command("stop")
@shared(*(n for n in RECREATE if n != "settle"), "canary", "max_fail")
def stop(fleet: Fleet) -> int:
    """Stop the driver container: `docker compose stop <driver service>` as the robot user (the
    container is kept; `driver start` brings it back). The robot's motors are then not driven:
    Panther's E-stop engages while its driver is down. `restart: always` in Husarion's compose
    file starts it again when the robot boots.

    `changed` when it stopped, `ok` when it was already stopped.

    \b
    Example:
      panther-ops driver stop -r panther-01 --yes
    """
    from panther_ops.core.driver.read import read_and_plan_stop

    return fleet.change("driver stop", read_and_plan_stop, verb="Stop the driver on")


@app.command("start")
@shared(*RECREATE, "canary", "max_fail")
def start(fleet: Fleet) -> int:
    """Start a stopped driver container as it is: `docker compose start <driver service>` (no
    recreate: a change made with --no-restart still waits for `driver restart`), then check it
    keeps running, unrestarted: ready after 2 s up, at most --settle seconds.

    `changed` when it started, `ok` when it was already running, `failed` (exit 3) when it did
    not stay up (see `driver logs`).

    \b
    Example:
      panther-ops driver start -r panther-01 --yes
    """
    from panther_ops.core.driver.read import read_and_plan_start

    return fleet.change("driver start", read_and_plan_start, verb="Start the driver on")


# ------------------------------------------------------------------ versions


@app.command("versions")
@shared(*READ)
def versions(
    fleet: Fleet,
    remote: Annotated[bool, typer.Option("--remote", help="Also ask Docker Hub (from this machine) for the "
                                         "released Humble tags.")] = False,
) -> int:
    """The driver images each robot has locally (husarion/panther, husarion/husarion-ugv), marking
    the one the driver container runs and the one compose.yaml names. --remote lists Docker Hub's
    released Humble tags (humble-X.Y.Z-YYYYMMDD[-stable]) and, per robot, the newer ones of its
    repository; asked from this machine with a 5 s timeout, "registry unreachable" otherwise.

    \b
    Examples:
      panther-ops driver versions --all
      panther-ops driver versions -r panther-01 --remote
    """
    from panther_ops.cli.views.driver import print_versions
    from panther_ops.core.driver.containers import versions_task
    from panther_ops.core.driver.hub import fetch_hub_tags
    from panther_ops.core.driver.images import DRIVER_REPOS, HUB_URL, HubTag, RegistryError

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
    result = fleet.results("driver versions", versions_task(tags), read_only=True)
    if remote:
        result.data["remote"] = remote_data
        result.notes.extend(notes)
    return fleet.show(result, print_versions)


# ------------------------------------------------------------------ update


@app.command("update")
@shared(*GATED)
def update(
    fleet: Fleet,
    tag: Annotated[OptStr, typer.Argument(
        help="Tag (humble-2.1.2-20241125, jazzy-2.3.2-20260622) or image (husarion/panther:humble-...); default: "
        "the inventory's desired image.")] = None,
    pull: Annotated[bool, typer.Option("--pull", help="docker compose pull the driver before recreating it "
                                       "(the robot needs internet).")] = False,
    force: Annotated[bool, typer.Option("--force", help="Allow a move between husarion/panther (<=2.1) and "
                                        "husarion/husarion-ugv (2.2), or a repository not matching the version.")]
    = False,
) -> int:
    """Change the driver image in compose.yaml and recreate the driver, through the pipeline:
    plan, diff, confirm, backup, atomic write, recreate, verify, roll back on failure.

    Humble 2.0-2.2 and Jazzy 2.3.1/2.3.2 tags. On a husarion_ugv 2.2 robot a 2.3 tag is a
    migration: every file of ~/config the driver reads is translated into its 2.3 form in the
    same plan (controller limits, gamepad moved to husarion_ugv_teleop, components, EKF), files
    whose schema did not change are left as they are, and a value 2.3 cannot carry is refused
    (exit 2) naming the file, the key and the fix; a 2.2 tag on a migrated robot restores the
    migration's backup (docs/jazzy.md, "Migrating a robot"). A tag takes the repository of its version; a
    move between panther_ros (<=2.1, husarion/panther, service panther_ros) and husarion_ugv_ros
    (2.2, husarion/husarion-ugv, service husarion_ugv_ros) is a reinstall and needs --force (then
    the service is renamed, the launch package and arguments migrated). A tag not on the robot is
    pulled by `docker compose up` (warned in the plan), or first with --pull; a failed pull rolls
    back. Bad tags exit 2 before anything is changed anywhere.

    \b
    Examples:
      panther-ops driver update humble-2.1.1-20240828 -g warehouse --dry-run
      panther-ops driver update humble-2.1.2-20241125 -r panther-01 --pull --yes
      panther-ops driver update jazzy-2.3.2-20260622 -r panther-03 --canary 1 --yes
    """
    from panther_ops.core.driver.images import parse_target
    from panther_ops.core.driver.read import read_and_plan_update

    target = parse_target(tag, force=force) if tag is not None else None
    command = f"driver update {tag}" if tag else "driver update (desired image)"
    return fleet.change(command, lambda c: read_and_plan_update(c, target, force=force, pull=pull))


# ------------------------------------------------------------------ config restore-defaults


@shared(*WRITE)
def restore_defaults(
    fleet: Fleet,
    hard: Annotated[bool, typer.Option("--hard", help="2.2: first remove everything in ~/config but common/ "
                                       "(Husarion's `restore_default hard`).")] = False,
) -> int:
    """Put each robot's driver configuration back to the image's defaults.

    2.2 (husarion_ugv_ros): ~/config is archived to ~/.panther-ops/backups/<id>/config.tar.gz, then
    `docker run --rm -v ~/config:/config <driver image> update_config_directory` runs as the robot
    user, and the driver is recreated and verified; on failure ~/config is restored from the archive.

    2.0/2.1 (panther_ros): the mounts from ~/config and the *_config_path / *_file / *_path launch
    arguments pointing into /config (what `config push` added) are removed through the pipeline:
    diff, confirm, backup, write, recreate, verify, roll back. The files stay in ~/config.

    \b
    Example:
      panther-ops config restore-defaults -r panther-01 --dry-run
    """
    from panther_ops.core.driver.read import read_and_plan_restore_defaults

    return fleet.change("config restore-defaults" + (" --hard" if hard else ""),
                        lambda c: read_and_plan_restore_defaults(c, hard=hard))


def register(root: typer.Typer) -> None:
    from panther_ops.cli.commands import config

    root.add_typer(app, name="driver")
    config.app.command("restore-defaults")(restore_defaults)
