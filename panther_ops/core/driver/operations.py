"""`panther-ops driver ...` and `config restore-defaults`: the driver container and its image.

Pure parts first (image references and tags, Docker Hub pages, durations, a container's
inspect data as a status), then the robot-facing tasks. Every robot step goes through the
robot's transport: the docker SDK rides its one SSH connection (`Transport.docker`), and
``docker compose`` runs as the robot user in a login shell, as Husarion's tools do. Changes
to compose.yaml go through the apply pipeline (`pipeline.apply_plan`); `apply_update` and
`apply_restore` add the steps the pipeline has no slot for (pull before recreating, removing
the container of a renamed service, the 2.2 config tree reset) and roll back the same way.

The one operator-side effect is `fetch_hub_tags`: an HTTPS GET to Docker Hub from this
machine (robots usually have no route to the internet), with a short timeout.
"""

from __future__ import annotations

import json
import posixpath
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from datetime import datetime, timezone
from typing import Any

from panther_ops.core.config.compose import ComposeError, ComposeFile, image_repo
from panther_ops.core.config.files import CONTAINER_CONFIG_DIR
from panther_ops.core.config.launch_args import check_args, migrate_args
from panther_ops.core.config.plans import compose_plan
from panther_ops.core.config.robot import RobotConfig, read_config
from panther_ops.core.containers.logs import LogOptions, read_logs
from panther_ops.core.containers.times import engine_now, human_duration, parse_timestamp
from panther_ops.core.fleet.pipeline import (
    BACKUP_ROOT,
    ApplyOptions,
    RobotPlan,
    Verify,
    apply_plan,
    new_backup_id,
    recreate_and_verify,
)
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.stack import PANTHER_REPO, UGV_REPO, Family, parse_image
from panther_ops.errors import OpsError, RemoteStateError, TransportError, UsageError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport import scripts_backup
from panther_ops.transport.base import Command

DRIVER_REPOS = (PANTHER_REPO, UGV_REPO)
HUB_URL = "https://hub.docker.com/v2/namespaces/husarion/repositories/{repo}/tags?page_size=100"
"""Docker Hub's tag list (what Husarion's configurator asks); ``{repo}`` is panther / husarion-ugv."""
HUB_TAG = re.compile(r"^humble-\d+\.\d+\.\d+-\d{8}(-stable)?$")
"""Released Humble driver tags (the configurator's filter, for Humble)."""
HUB_TIMEOUT_S = 5.0
NEWEST_HUMBLE = "husarion/husarion-ugv:humble-2.2.2-20250702"

_TAG_WORD = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,127}$")
_TAG = re.compile(
    r"^(?P<distro>[a-z]+)-(?P<major>\d+)\.(?P<minor>\d+)\.(?P<patch>\d+)"
    r"(?:-(?P<date>\d{8}))?(?:-(?P<suffix>[A-Za-z0-9._-]+))?$"
)
_DEFAULT_SERVICE = {Family.PANTHER_ROS: "panther_ros", Family.HUSARION_UGV: "husarion_ugv_ros"}
_FAMILY_LABEL = {Family.PANTHER_ROS: "panther_ros (2.0-2.1)", Family.HUSARION_UGV: "husarion_ugv_ros (2.2)"}
_BRINGUP = {Family.PANTHER_ROS: "panther_bringup", Family.HUSARION_UGV: "husarion_ugv_bringup"}
_PATH_ARG = re.compile(r"(_config_path|_file|_path)$")


# ------------------------------------------------------------------ image references


def repo_for(version: tuple[int, int, int]) -> str:
    """The Docker Hub repository of a driver version: 2.2+ husarion/husarion-ugv, else husarion/panther."""
    return UGV_REPO if version >= (2, 2, 0) else PANTHER_REPO


@dataclass(frozen=True)
class TargetImage:
    """What `driver update` was asked for, checked before any robot is contacted."""

    text: str
    tag: str
    repo: str | None
    """The repository when a full reference was given (None: a tag, repo from the version)."""
    version: tuple[int, int, int]
    warnings: tuple[str, ...] = ()

    def ref_for(self, current: str) -> str:
        """The full reference for a robot whose compose.yaml has ``current``.

        A bare tag keeps the registry prefix of the current image (a mirror stays a mirror)
        and takes the repository of its version; a full reference is used as given.
        """
        if self.repo is not None:
            return self.text
        name = current.split("@", 1)[0]
        head, sep, tail = name.rpartition(":")
        if sep and "/" not in tail:
            name = head
        prefix = name[: len(name) - len(image_repo(name))] if name.endswith(image_repo(name)) else ""
        return f"{prefix}{repo_for(self.version)}:{self.tag}"


def _jazzy(tag: str) -> UsageError:
    return UsageError(
        f"{tag} is a ROS 2 Jazzy driver (husarion_ugv_ros 2.3+): panther-ops manages Humble robots "
        "(panther_ros 2.0-2.1, husarion_ugv_ros 2.2)",
        hint=f"the newest Humble driver is {NEWEST_HUMBLE}; Jazzy needs another OS image on the Built-in Computer",
    )


def parse_target(text: str, *, force: bool = False) -> TargetImage:
    """Check a `driver update` argument: a tag (``humble-2.1.2-20241125``) or a full reference.

    Humble only; Jazzy (2.3+) is refused with its own message; the repository must be the one
    of the version's family (2.2+ husarion/husarion-ugv, 2.0-2.1 husarion/panther) unless
    ``force`` (then a warning).

    Raises:
        UsageError: anything else (exit 2, before any robot is contacted).
    """
    ref = text.strip()
    if not ref:
        raise UsageError("empty image tag")
    if "@" in ref:
        raise UsageError(f"{ref}: a digest does not say the driver version; give the tag",
                         hint="e.g. panther-ops driver update humble-2.1.2-20241125")
    repo: str | None = None
    tag = ref
    if "/" in ref or ":" in ref:
        name, sep, tag = ref.rpartition(":")
        if not sep or "/" in tag or not name:
            raise UsageError(f"{ref!r} has no tag", hint="REPOSITORY:TAG, e.g. husarion/panther:humble-2.1.2-20241125")
        repo = image_repo(name)
        if repo not in DRIVER_REPOS:
            raise UsageError(f"{ref}: {repo} is not a Panther driver image",
                             hint=f"expected {PANTHER_REPO}:<tag> (2.0-2.1) or {UGV_REPO}:<tag> (2.2)")
    if not _TAG_WORD.match(tag):
        raise UsageError(f"{tag!r} is not a docker image tag")
    m = _TAG.match(tag)
    if not m:
        raise UsageError(f"tag {tag!r} does not say the driver version",
                         hint="tags look like humble-<X.Y.Z>-<YYYYMMDD>, e.g. humble-2.1.2-20241125 "
                              "(panther-ops driver versions --remote lists them)")
    version = (int(m["major"]), int(m["minor"]), int(m["patch"]))
    if m["distro"] == "jazzy" or version >= (2, 3, 0):
        raise _jazzy(tag)
    if m["distro"] != "humble":
        raise UsageError(f"{tag}: ROS 2 {m['distro'].capitalize()} is not a Panther driver distribution here",
                         hint="panther-ops manages Humble drivers: humble-<X.Y.Z>-<YYYYMMDD>")
    if version < (2, 0, 0):
        raise UsageError(f"{tag}: ROS 1 drivers (1.x) are not supported")
    warnings: list[str] = []
    expected = repo_for(version)
    if repo is not None and repo != expected:
        message = (f"{ref}: driver {'.'.join(map(str, version))} is published as {expected}, not {repo} "
                   "(2.2+ is husarion/husarion-ugv, 2.0-2.1 husarion/panther)")
        if not force:
            raise UsageError(message, hint=f"use {expected}:{tag}, or just the tag {tag}")
        warnings.append(message + " (--force)")
    return TargetImage(ref, tag, repo, version, tuple(warnings))


def tag_key(tag: str) -> tuple[Any, ...]:
    """Sort key of a driver tag: version, then build date, then the rest."""
    m = _TAG.match(tag)
    if not m:
        return ((-1, -1, -1), "", tag)
    return ((int(m["major"]), int(m["minor"]), int(m["patch"])), m["date"] or "", tag)


def _version_of(tag: str) -> tuple[int, int, int] | None:
    m = _TAG.match(tag)
    return (int(m["major"]), int(m["minor"]), int(m["patch"])) if m else None


# ------------------------------------------------------------------ durations and times


_DURATION_PART = re.compile(r"(\d+(?:\.\d+)?)([smhd])")
_UNIT_S = {"s": 1.0, "m": 60.0, "h": 3600.0, "d": 86400.0}


def parse_duration(text: str) -> float:
    """``90`` / ``90s`` / ``10m`` / ``1h30m`` / ``2d`` -> seconds.

    Raises:
        UsageError: anything else.
    """
    t = text.strip().lower()
    if re.fullmatch(r"\d+(?:\.\d+)?", t):
        return float(t)
    if t and re.fullmatch(r"(?:\d+(?:\.\d+)?[smhd])+", t):
        return sum(float(n) * _UNIT_S[u] for n, u in _DURATION_PART.findall(t))
    raise UsageError(f"{text!r} is not a duration", hint="e.g. 90s, 10m, 1h30m, 2d")








# ------------------------------------------------------------------ container view (pure)


def argv_matches(running: list[str], compose: list[str]) -> bool:
    """The container's command is compose.yaml's (a word with ``$`` is interpolated by compose)."""
    if len(running) != len(compose):
        return False
    return all(a == b or "$" in b for a, b in zip(running, compose, strict=True))


@dataclass
class ContainerView:
    data: dict[str, Any]
    warnings: list[str] = field(default_factory=list)
    healthy: bool = True
    problem: str | None = None


def describe_container(attrs: Mapping[str, Any], *, compose_image: str | None, compose_argv: list[str] | None,
                       now: datetime | None) -> ContainerView:
    """A driver container's inspect data as the `driver status` view (pure)."""
    state = attrs.get("State") or {}
    config = attrs.get("Config") or {}
    status = str(state.get("Status") or "?")
    restarting = bool(state.get("Restarting"))
    started = parse_timestamp(state.get("StartedAt"))
    finished = parse_timestamp(state.get("FinishedAt"))
    health = (state.get("Health") or {}).get("Status")
    cmd = [str(x) for x in (config.get("Cmd") or [])]
    running = status == "running" and not restarting
    uptime = (now - started).total_seconds() if running and started and now else None
    data: dict[str, Any] = {
        "container": str(attrs.get("Name", "")).lstrip("/"),
        "container_id": str(attrs.get("Id", ""))[:12],
        "image": config.get("Image"),
        "state": "restarting" if restarting else status,
        "started_at": state.get("StartedAt") if started else None,
        "finished_at": state.get("FinishedAt") if finished else None,
        "uptime_s": None if uptime is None else round(uptime, 1),
        "restart_count": int(attrs.get("RestartCount") or 0),
        "exit_code": state.get("ExitCode"),
        "health": health,
        "command": cmd,
        "compose_image": compose_image,
        "compose_command": compose_argv,
        "command_drift": None if compose_argv is None else not argv_matches(cmd, compose_argv),
        "image_drift": None if compose_image is None else config.get("Image") != compose_image,
    }
    view = ContainerView(data)
    if data["image_drift"]:
        view.warnings.append(f"the container runs {config.get('Image')} but compose.yaml says {compose_image}: "
                             "recreate it (panther-ops driver restart)")
    if data["command_drift"]:
        view.warnings.append("the container's launch command differs from compose.yaml's: recreate it "
                             "(panther-ops driver restart); running: " + " ".join(cmd))
    if data["restart_count"] and running:
        view.warnings.append(f"restarted {data['restart_count']} time(s) since it was created "
                             f"(last exit code {state.get('ExitCode')}): see panther-ops driver logs")
    if health == "unhealthy":
        view.healthy = False
        view.problem = "unhealthy (healthcheck failing)"
    if not running:
        view.healthy = False
        view.problem = (f"restarting (exit code {state.get('ExitCode')}, {data['restart_count']} restarts)"
                        if restarting else f"{status} (exit code {state.get('ExitCode')})")
    return view


# ------------------------------------------------------------------ Docker Hub


class NoEngineError(RemoteStateError):
    """The robot has no docker engine to ask (a demo robot, or docker not installed)."""


class RegistryError(OpsError):
    """Docker Hub could not be asked (no network, timeout, not JSON)."""


@dataclass(frozen=True)
class HubTag:
    repo: str
    name: str
    last_updated: str | None = None
    digest: str | None = None
    size: int | None = None

    def to_json(self) -> dict[str, Any]:
        return {"tag": self.name, "image": f"{self.repo}:{self.name}", "last_updated": self.last_updated,
                "digest": self.digest, "size": self.size}


def parse_hub_page(doc: Any, repo: str) -> tuple[list[HubTag], str | None]:
    """One page of Docker Hub's tag list -> (released Humble tags, next page URL)."""
    if not isinstance(doc, dict) or not isinstance(doc.get("results"), list):
        raise RegistryError("unexpected answer from Docker Hub (no results list)")
    tags: list[HubTag] = []
    for item in doc["results"]:
        if not isinstance(item, dict):
            continue
        name = item.get("name")
        if not isinstance(name, str) or not HUB_TAG.match(name):
            continue
        size = item.get("full_size")
        tags.append(HubTag(repo, name, item.get("last_updated") or item.get("tag_last_pushed"),
                           item.get("digest"), size if isinstance(size, int) else None))
    nxt = doc.get("next")
    return tags, nxt if isinstance(nxt, str) and nxt else None


def fetch_hub_tags(repo: str, *, url_template: str = HUB_URL, timeout: float = HUB_TIMEOUT_S,
                   max_pages: int = 3) -> list[HubTag]:
    """Released Humble tags of ``husarion/<repo>`` from Docker Hub (newest version first).

    Raises:
        RegistryError: ``registry unreachable: <why>`` (no network, timeout, HTTP error, not JSON).
    """
    import urllib.error
    import urllib.request
    from urllib.parse import urlsplit

    from panther_ops import __version__

    name = repo.rsplit("/", maxsplit=1)[-1]
    url = url_template.format(repo=name)
    origin = urlsplit(url)[:2]
    if origin[0] not in ("http", "https"):
        raise RegistryError(f"registry URL {url!r} is not http(s)")
    tags: list[HubTag] = []
    for _ in range(max_pages):
        req = urllib.request.Request(url, headers={"Accept": "application/json",  # noqa: S310 - scheme checked
                                                   "User-Agent": f"panther-ops/{__version__}"})
        try:
            with urllib.request.urlopen(req, timeout=timeout) as resp:  # noqa: S310 - scheme checked
                doc = json.loads(resp.read(8_000_000))
        except urllib.error.HTTPError as exc:
            raise RegistryError(f"registry unreachable: {url} answered HTTP {exc.code}") from None
        except urllib.error.URLError as exc:
            raise RegistryError(f"registry unreachable: {exc.reason}") from None
        except (OSError, TimeoutError) as exc:
            raise RegistryError(f"registry unreachable: {exc}") from None
        except ValueError:
            raise RegistryError(f"registry unreachable: {url} did not answer JSON") from None
        page, nxt = parse_hub_page(doc, f"husarion/{name}")
        tags.extend(page)
        if nxt is None or urlsplit(nxt)[:2] != origin:
            break
        url = nxt
    return sorted(set(tags), key=lambda t: tag_key(t.name), reverse=True)


def newer_tags(current: str, remote: list[HubTag]) -> list[str]:
    """Remote images of the current image's repository with a newer version (newest first)."""
    repo = image_repo(current)
    cur = _version_of(current.rpartition(":")[2])
    if cur is None:
        return []
    out = [t for t in remote if t.repo == repo and (_version_of(t.name) or (0, 0, 0)) > cur]
    return [f"{t.repo}:{t.name}" for t in sorted(out, key=lambda t: tag_key(t.name), reverse=True)]


# ------------------------------------------------------------------ robot helpers


def engine(ctx: RobotContext) -> tuple[Any | None, str | None]:
    """The robot's docker SDK client over its SSH connection, or (None, why)."""
    if ctx.robot.transport == "local":
        return None, "demo robot: no docker engine"
    client = ctx.transport.docker()
    if client is None:
        return None, "no docker engine on this robot"
    return client, None


def _compose_dir(cfg: RobotConfig) -> tuple[str, str]:
    return posixpath.dirname(cfg.compose_path) or "~", posixpath.basename(cfg.compose_path)


def service_containers(client: Any, service: str, working_dir: str | None = None) -> list[Any]:
    """Containers of a compose service (of the project in ``working_dir`` when given), running first."""
    found = list(client.containers.list(all=True, filters={"label": f"com.docker.compose.service={service}"}))
    if working_dir:
        own = [c for c in found
               if (c.attrs.get("Config", {}).get("Labels") or {}).get("com.docker.compose.project.working_dir")
               in (working_dir, None)]
        found = own or found
    found.sort(key=lambda c: not (c.attrs.get("State") or {}).get("Running"))
    return found


def driver_container(client: Any, cfg: RobotConfig) -> Any | None:
    """The driver's container: by compose service label, else by container_name."""
    service = cfg.service
    found = service_containers(client, service, _compose_dir(cfg)[0])
    if found:
        return found[0]
    name = cfg.compose.service(service).get("container_name") or service
    import docker.errors

    try:
        return client.containers.get(str(name))
    except docker.errors.NotFound:
        return None





def _compose_argv(cfg: RobotConfig) -> list[str] | None:
    try:
        return list(cfg.compose.command().argv)
    except OpsError:
        return None


def last_line(text: str, limit: int = 300) -> str:
    """The last non-empty line of a command's output (docker puts the error there), shortened."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[-1][-limit:] if lines else ""


def _mark(ctx: RobotContext, backup_id: str, status: str) -> None:
    try:
        ctx.transport.run(Command.sh(scripts_backup.MARK, f"{BACKUP_ROOT}/{backup_id}", status))
    except OpsError:
        return


# ------------------------------------------------------------------ driver status


def status_task(ctx: RobotContext) -> RobotResult:
    """`driver status`: the driver container against compose.yaml."""
    cfg = read_config(ctx)
    service, image, argv = cfg.service, cfg.compose.driver_image, _compose_argv(cfg)
    base = {"service": service, "compose_image": image, "compose_command": argv, "stack": cfg.stack.label()}
    client, why = engine(ctx)
    if client is None:
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, str(why), data={**base, "docker_skipped": why})
    ctr = driver_container(client, cfg)
    if ctr is None:
        res = RobotResult(ctx.robot.name, Outcome.FAILED, f"no container for service {service}",
                          data={**base, "state": "missing"})
        res.data["hint"] = "start it: panther-ops driver restart"
        return res
    view = describe_container(ctr.attrs, compose_image=image, compose_argv=argv, now=engine_now(client))
    data = {**base, **view.data}
    if view.problem:
        return RobotResult(ctx.robot.name, Outcome.FAILED, f"{service}: {view.problem}", data=data,
                           warnings=view.warnings)
    msg = f"{service} running {human_duration(data['uptime_s'])}, {data['image']}"
    return RobotResult(ctx.robot.name, Outcome.OK, msg, data=data, warnings=view.warnings)


# ------------------------------------------------------------------ driver logs


def open_logs(ctx: RobotContext, opts: LogOptions) -> tuple[str, Any]:
    """(container name, logs): bytes, or an iterator of bytes chunks when following.

    Raises:
        NoEngineError: no docker engine.
        RemoteStateError: no driver container.
    """
    cfg = read_config(ctx)
    client, why = engine(ctx)
    if client is None:
        raise NoEngineError(str(why))
    ctr = driver_container(client, cfg)
    if ctr is None:
        raise RemoteStateError(f"no container for service {cfg.service}", hint="panther-ops driver restart")
    return read_logs(client, ctr, opts)





# ------------------------------------------------------------------ driver versions


def local_images(images: list[Mapping[str, Any]], *, compose_image: str | None, running_ref: str | None,
                 running_image_id: str | None) -> list[dict[str, Any]]:
    """Driver images among an engine's images (``/images/json`` attrs), newest version first.

    ``in_use`` marks the reference the driver container was created from (several tags may
    share one image id); by id only when that reference is no tag here (an id or a digest).
    """
    refs = {ref for img in images for ref in (img.get("RepoTags") or [])}
    by_ref = running_ref in refs
    out: list[dict[str, Any]] = []
    for img in images:
        for ref in img.get("RepoTags") or []:
            if not isinstance(ref, str) or image_repo(ref) not in DRIVER_REPOS:
                continue
            in_use = ref == running_ref if by_ref else bool(running_image_id) and img.get("Id") == running_image_id
            out.append({"image": ref, "repo": image_repo(ref), "tag": ref.rpartition(":")[2],
                        "id": str(img.get("Id", ""))[:19], "size": img.get("Size"), "in_use": in_use,
                        "in_compose": ref == compose_image})
    out.sort(key=lambda e: (tag_key(e["tag"]), e["repo"]), reverse=True)
    return out


def versions_task(remote: Mapping[str, list[HubTag]] | None) -> Callable[[RobotContext], RobotResult]:
    """`driver versions`: driver images on each robot, and newer ones on Docker Hub when asked."""

    def task(ctx: RobotContext) -> RobotResult:
        cfg = read_config(ctx)
        image = cfg.compose.driver_image
        data: dict[str, Any] = {"compose_image": image, "service": cfg.service}
        if remote is not None:
            data["newer"] = newer_tags(image, [t for tags in remote.values() for t in tags])
        client, why = engine(ctx)
        if client is None:
            data["docker_skipped"] = why
            return RobotResult(ctx.robot.name, Outcome.SKIPPED, str(why), data=data)
        ctr = driver_container(client, cfg)
        running_id = ctr.attrs.get("Image") if ctr is not None else None
        data["running_image"] = ctr.attrs.get("Config", {}).get("Image") if ctr is not None else None
        data["local"] = local_images([i.attrs for i in client.images.list()], compose_image=image,
                                     running_ref=data["running_image"], running_image_id=running_id)
        used = next((e["image"] for e in data["local"] if e["in_use"]), None)
        msg = f"{len(data['local'])} driver image(s); in use: {used or 'none (no driver container)'}"
        if data.get("newer"):
            msg += f"; newer on Docker Hub: {data['newer'][0]}"
        return RobotResult(ctx.robot.name, Outcome.OK, msg, data=data)

    return task


# ------------------------------------------------------------------ driver restart


def plan_restart(ctx: RobotContext) -> RobotPlan:
    """`driver restart`: what will be recreated (reads compose.yaml only)."""
    cfg = read_config(ctx)
    words = tuple(f"{k}:={v}" for k, v in cfg.compose.args.items()) if _compose_argv(cfg) else ()
    plan = RobotPlan(ctx.robot.name, f"recreate {cfg.service} ({cfg.compose.driver_image})", [], (cfg.service,),
                     cfg.compose_path, [Verify(cfg.service, words)])
    plan.data.update(action="recreate", service=cfg.service, image=cfg.compose.driver_image)
    return plan


def apply_restart(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """``docker compose up -d --force-recreate <driver>`` as the robot user, then watch it for the settle time."""
    name = ctx.robot.name
    client, why = engine(ctx)
    if client is None:
        return RobotResult(name, Outcome.SKIPPED, f"{why}: nothing to restart", data=dict(plan.data))
    service = plan.recreate[0]
    before = service_containers(client, service)
    result = RobotResult(name, Outcome.CHANGED, "", data=dict(plan.data))
    result.data["previous_container"] = before[0].id[:12] if before else None
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem:
        result.outcome = Outcome.FAILED
        result.message = problem
        result.data["hint"] = "see panther-ops driver logs"
        return result
    after = service_containers(client, service)
    result.data["container"] = after[0].id[:12] if after else None
    result.message = f"recreated {service} ({plan.data.get('image')}); running after {opts.settle_s:g} s"
    return result


# ------------------------------------------------------------------ driver update


def _rename_service(compose: ComposeFile, old: str, new: str) -> ComposeFile:
    """compose.yaml with service key ``old`` renamed ``new`` (only that line changes)."""
    text = compose.text()
    start = compose.doc.info(("services", old)).start
    keys = [m for m in re.finditer(rf"^([ \t]*){re.escape(old)}:(?=[ \t]*(?:#.*)?$)", text, re.M)
            if m.start() < start]
    if not keys:
        raise ComposeError(f"cannot rename service {old}: its key is not written plainly", path=compose.path)
    k = keys[-1]
    renamed = ComposeFile.parse(text[: k.start()] + k[1] + new + ":" + text[k.end():], compose.path)
    if new not in renamed.services() or old in renamed.services() or renamed.service(new) != compose.service(old):
        raise ComposeError(f"cannot rename service {old} to {new} in place", path=compose.path)
    return renamed


def _replace_package(compose: ComposeFile, service: str, old: str, new: str) -> ComposeFile:
    info = compose.doc.info(("services", service, "command"))
    text = compose.text()
    region = re.sub(rf"(?<![\w/-]){re.escape(old)}(?![\w/-])", new, text[info.start:info.end])
    out = ComposeFile.parse(text[: info.start] + region + text[info.end:], compose.path)
    if out.command(service).package != new:
        raise ComposeError(f"cannot change the launch package of {service} to {new}", path=compose.path)
    return out


_FAMILY_NOTES = {
    Family.HUSARION_UGV: (
        "husarion_ugv_ros 2.2 expects Built-in Computer OS 2.x: /run/husarion/robot_config.env, the config tree "
        "~/config mounted at /config with common_dir_path:=/config and env_file ~/config/common/.env, the gamepad "
        "inside the driver (launch_gamepad:=true); none of that is added here (Husarion's path: reinstall the OS)"
    ),
    Family.PANTHER_ROS: (
        "panther_ros 2.0-2.1 expects /run/husarion/panther_config.env and its config inside the image "
        "(no ~/config tree, gamepad as its own gamepad_controller service); none of that is added here"
    ),
}


def _change_family(cfg: RobotConfig, target: Family, warnings: list[str]) -> str | None:
    """Rename the driver service and launch package for the other family; returns the old service name."""
    old_service = cfg.service
    new_service = _DEFAULT_SERVICE[target]
    compose = cfg.compose
    renamed_from: str | None = None
    if old_service == _DEFAULT_SERVICE[cfg.stack.family] and new_service not in compose.services():
        compose = _rename_service(compose, old_service, new_service)
        renamed_from = old_service
    else:
        new_service = old_service
    if compose.command(new_service).package == _BRINGUP[cfg.stack.family]:
        compose = _replace_package(compose, new_service, _BRINGUP[cfg.stack.family], _BRINGUP[target])
    if compose.service(new_service).get("container_name") == old_service and renamed_from:
        compose.doc.set(("services", new_service, "container_name"), new_service)
    cfg.compose = compose
    warnings.append(_FAMILY_NOTES[target])
    return renamed_from


def plan_update(ctx: RobotContext, target: TargetImage | None, *, force: bool = False, pull: bool = False) -> RobotPlan:
    """`driver update`: the driver image in compose.yaml (``target`` None: the inventory's desired image)."""
    cfg = read_config(ctx)
    if target is None:
        wanted = ctx.robot.desired.get("image")
        if not wanted:
            return compose_plan(ctx, cfg, "no change", [], [], "no TAG given and no desired image in the inventory")
        target = parse_target(str(wanted), force=force)
    current = cfg.compose.driver_image
    new_ref = target.ref_for(current)
    warnings = list(target.warnings)
    old_stack = cfg.stack
    new_stack = parse_image(f"{repo_for(target.version)}:{target.tag}")
    if new_ref == current:
        plan = compose_plan(ctx, cfg, "no change", warnings, [], f"compose.yaml already has {current}")
        plan.data.update(image_from=current, image_to=new_ref)
        return plan
    old_service = cfg.service
    renamed_from: str | None = None
    if new_stack.family is not old_stack.family:
        if not force:
            raise UsageError(
                f"{current} -> {new_ref} moves the robot from {_FAMILY_LABEL[old_stack.family]} to "
                f"{_FAMILY_LABEL[new_stack.family]}: another image repository and service name ({old_service} -> "
                f"{_DEFAULT_SERVICE[new_stack.family]}), another config layout and OS; that is a reinstall, "
                "not an update",
                hint="Husarion's path is reinstalling the Built-in Computer's OS image; --force edits compose.yaml "
                     "anyway (image, service name, launch package, launch arguments) and rolls back if the driver "
                     "fails",
            )
        renamed_from = _change_family(cfg, new_stack.family, warnings)
    old_args = dict(cfg.compose.args)
    migration = migrate_args(old_stack, new_stack, old_args)
    service = cfg.service
    for name in migration.dropped:
        cfg.compose.unset_arg(name, service)
        warnings.append(f"launch argument {name}:={old_args[name]} dropped: {new_stack.label()} has no such argument")
    for old, new in migration.renamed.items():
        cfg.compose.unset_arg(old, service)
        cfg.compose.set_arg(new, old_args[old], service)
        warnings.append(f"launch argument {old} renamed {new} for {new_stack.label()}; check the file it points "
                        "to has that version's format")
    cfg.compose.set_image(new_ref, service, force=force)
    volumes = cfg.compose.list_volumes(service)
    before = {(f.rule, f.keys) for f in check_args(old_stack, old_args, volumes=volumes)}
    warnings += [f"after the update: {f.message}" for f in check_args(new_stack, cfg.compose.args, volumes=volumes)
                 if (f.rule, f.keys) not in before]
    if ctx.robot.stack != "auto":
        warnings.append(f"the inventory pins stack: {ctx.robot.stack} for this robot: change it to "
                        f"{new_stack.version_str} (or auto) with the update")
    warnings += _device_notes(cfg.compose.service(service).get("devices") or [], new_stack.version)
    present = _image_present(ctx, new_ref)
    if present is False:
        warnings.append(f"{new_ref} is not on the robot: it needs a pull (internet on the robot); "
                        + ("--pull runs docker compose pull first" if not pull else "pulled before recreating"))
    parts = [f"image {current} -> {new_ref}"]
    if renamed_from:
        parts.append(f"service {renamed_from} -> {service}")
    parts += [f"{o} -> {n}" for o, n in migration.renamed.items()] + [f"drop {d}" for d in migration.dropped]
    words = tuple(f"{k}:={v}" for k, v in cfg.compose.args.items())
    plan = compose_plan(ctx, cfg, "; ".join(parts), warnings, [Verify(service, words)], "no change")
    plan.data.update(image_from=current, image_to=new_ref, image_local=present, pull=pull,
                     stack_from=old_stack.label(), stack_to=new_stack.label())
    if renamed_from:
        plan.data["service_from"] = renamed_from
    return plan


def _device_notes(devices: list[Any], version: tuple[int, int, int]) -> list[str]:
    """The LED SPI devices were renamed at 2.1.0 (spidev0.x -> spiled-channelN, with cgroup rules)."""
    text = " ".join(str(d) for d in devices)
    if version >= (2, 1, 0) and "/dev/spidev0." in text:
        return ["2.1+ drives the LEDs through /dev/spiled-channel1/2 (with device_cgroup_rules), not /dev/spidev0.x: "
                "update the devices of the driver service (see the 2.1 compose file) or the lights will not work"]
    if version < (2, 1, 0) and "/dev/spiled-channel" in text:
        return ["2.0 drives the LEDs through /dev/spidev0.0/0.1, not /dev/spiled-channelN: update the devices of "
                "the driver service (see the 2.0 compose file) or the lights will not work"]
    return []


def _image_present(ctx: RobotContext, ref: str) -> bool | None:
    """Whether the robot's engine has ``ref`` (None: no engine to ask)."""
    client, _why = engine(ctx)
    if client is None:
        return None
    import docker.errors

    try:
        client.images.get(ref)
    except docker.errors.ImageNotFound:
        return False
    except docker.errors.APIError:
        return None
    return True


def apply_update(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """Apply a `driver update` plan: the pipeline, plus pull / orphan removal when the plan needs them."""
    renamed_from = plan.data.get("service_from")
    pull = bool(plan.data.get("pull"))
    if not (renamed_from or pull) or not plan.edits or opts.dry_run or not opts.restart:
        result = apply_plan(ctx, plan, opts)
        if renamed_from and result.outcome is Outcome.CHANGED and not opts.restart and not opts.dry_run:
            result.warnings.append(
                f"the {renamed_from} container keeps running until the driver is recreated: then remove it "
                f"(docker compose up -d --remove-orphans {plan.recreate[0]}) or two drivers hold the hardware")
        return result
    client, _why = engine(ctx)
    if client is None:
        return apply_plan(ctx, plan, opts)
    result = apply_plan(ctx, plan, replace(opts, restart=False))
    if result.outcome is not Outcome.CHANGED:
        return result
    backup_id = str(result.data["backup"])
    result.message = plan.summary
    cdir = posixpath.dirname(plan.compose_file) or "~"
    if pull:
        res = ctx.transport.run(Command.of("docker", "compose", "-f", posixpath.basename(plan.compose_file), "pull",
                                           *plan.recreate, login=True, cwd=cdir), timeout=1800)
        if not res.ok:
            failed = f"docker compose pull failed: {last_line(res.stderr)}"
            return _roll_back_update(ctx, plan, opts, result, failed, backup_id, client, recreated=False)
    if renamed_from:
        for c in service_containers(client, str(renamed_from), cdir):
            c.remove(force=True)
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.outcome = Outcome.CHANGED
        _mark(ctx, backup_id, "applied")
        return result
    return _roll_back_update(ctx, plan, opts, result, problem, backup_id, client, recreated=True)


def _roll_back_update(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, result: RobotResult, problem: str,
                      backup_id: str, client: Any, *, recreated: bool) -> RobotResult:
    """Write compose.yaml back; when containers were touched, put the old driver back up."""
    renamed_from = plan.data.get("service_from")
    cdir = posixpath.dirname(plan.compose_file) or "~"
    again: str | None = None
    try:
        for e in plan.edits:
            if e.before is not None:
                ctx.transport.write_file_atomic(e.path, e.before)
        if recreated:
            services = plan.recreate
            if renamed_from:
                for svc in plan.recreate:
                    for c in service_containers(client, svc, cdir):
                        c.remove(force=True)
                services = (str(renamed_from),)
            restore = RobotPlan(plan.robot, "restore", [], services, plan.compose_file, [])
            again = recreate_and_verify(ctx, restore, min(opts.settle_s, 3.0),
                                        RobotResult(plan.robot, Outcome.OK, ""))
    except OpsError as exc:
        result.outcome = Outcome.FAILED
        result.message = f"{problem}; ROLLBACK FAILED: {exc.message} (backup {backup_id} on the robot)"
        return result
    result.outcome = Outcome.ROLLED_BACK
    result.message = f"{problem}; restored backup {backup_id}" + (f" (after restore: {again})" if again else "")
    if not recreated:
        result.message += "; the driver was not touched"
    _mark(ctx, backup_id, f"rolled-back: {problem}")
    return result


# ------------------------------------------------------------------ config restore-defaults

TAR_SAVE = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; c="$2"; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'mkdir -p -- "$r$d" || exit 1; '
    'if [ -d "$r$c" ]; then tar -czf "$r$d/config.tar.gz" -C "$(dirname -- "$r$c")" "$(basename -- "$c")" || exit 1; '
    'fi; cat > "$r$d/manifest.json.tmp" && mv -f -- "$r$d/manifest.json.tmp" "$r$d/manifest.json" && sync'
)
"""$1 = backup dir, $2 = the config directory; stdin = manifest.json. Archive: <backup>/config.tar.gz."""

TAR_RESTORE = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; c="$2"; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'rm -rf -- "$r$c" || exit 1; '
    'if [ -f "$r$d/config.tar.gz" ]; then tar -xzf "$r$d/config.tar.gz" -C "$(dirname -- "$r$c")" || exit 1; fi'
)
"""Put the config directory back as it was in the archive (or absent, when it was)."""

CLEAN_TREE = (
    'r="${PANTHER_OPS_ROOT:-}"; c="$1"; [ -d "$r$c" ] || exit 0; '
    'find "$r$c" -mindepth 1 -maxdepth 1 ! -name common -exec rm -rf -- {} +'
)
"""``--hard``: everything in the config directory but ``common/`` goes (it is in the archive)."""


def _under(path: str, root: str) -> bool:
    root = root.rstrip("/")
    return path == root or path.startswith(root + "/")


def _check_tree(tree: str, cfg: RobotConfig) -> None:
    """The config tree is replaced wholesale on a failed reset: it must be a directory of its own."""
    tree = posixpath.normpath(tree)
    protected = (cfg.compose_path, posixpath.join(cfg.home, ".panther-ops"), posixpath.join(cfg.home, ".ssh"))
    if not _under(tree, cfg.home) or tree == posixpath.normpath(cfg.home) or any(_under(p, tree) for p in protected):
        raise RemoteStateError(
            f"the config tree mounted at /config is {tree}: not a directory of its own under {cfg.home}; "
            "refusing to reset it", hint="mount ~/config at /config, as husarion_ugv_ros does")


def plan_restore_defaults(ctx: RobotContext, *, hard: bool = False) -> RobotPlan:
    """`config restore-defaults`: the 2.2 config tree reset, or (2.0/2.1) panther-ops' mounts removed."""
    cfg = read_config(ctx)
    config_dir = posixpath.join(cfg.home, "config")
    if cfg.stack.has_config_tree:
        tree = cfg.host_path_of(CONTAINER_CONFIG_DIR) or config_dir
        _check_tree(tree, cfg)
        image = cfg.compose.driver_image
        warnings: list[str] = []
        if not cfg.tree_mounted:
            warnings.append(f"{tree} is not mounted at /config in compose.yaml: the driver does not read it")
        if engine(ctx)[0] is None:
            warnings.append(f"{engine(ctx)[1]}: update_config_directory cannot run here (it would be skipped)")
        mounts = [f"{cfg.resolve(v.source)}:{v.target}:ro" for v in cfg.compose.list_volumes(cfg.service)
                  if v.source and v.target.startswith("/run/husarion/") and v.target.endswith(".env")]
        summary = (f"back up {tree} and run update_config_directory from {image}"
                   + (" after removing everything but common/ (--hard)" if hard else ""))
        plan = RobotPlan(ctx.robot.name, summary, [], (cfg.service,), cfg.compose_path, [Verify(cfg.service)],
                         None, warnings)
        plan.data.update(action="update_config_directory", image=image, config_dir=tree, env_mounts=mounts,
                         hard=hard, stack=cfg.stack.label())
        return plan
    service = cfg.service
    removed = [v for v in cfg.compose.list_volumes(service)
               if v.source and v.source.startswith(("/", "~", ".")) and _under(cfg.resolve(v.source), config_dir)]
    args = cfg.compose.args
    drop = [k for k, v in args.items() if _PATH_ARG.search(k)
            and (_under(v, CONTAINER_CONFIG_DIR) or any(_under(v, vol.target) for vol in removed))]
    warnings = []
    if args.get("wheel_type") == "custom" and {"controller_config_path", "wheel_config_path"} & set(drop):
        drop.append("wheel_type")
        warnings.append("wheel_type:=custom needs the controller/wheel files being removed: wheel_type is unset too "
                        "(the stack's default, WH01, applies; set yours with panther-ops config set wheel_type)")
    for v in sorted(removed, key=lambda v: -v.index):
        cfg.compose.remove_volume(v.target, service)
    for k in drop:
        cfg.compose.unset_arg(k, service)
    lacks = tuple(f"{k}:={args[k]}" for k in drop)
    parts = [f"unmount {v.target}" for v in removed] + [f"unset {k}" for k in drop]
    summary = "; ".join(parts) + (f" (files stay in {config_dir})" if removed else "")
    plan = compose_plan(ctx, cfg, summary, warnings, [Verify(service, (), lacks)],
                        f"nothing panther-ops added: no mounts from {config_dir}, no arguments into /config")
    plan.data["removed_mounts"] = [v.spec() for v in removed]
    plan.data["unset_args"] = drop
    return plan


def apply_restore(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """2.0/2.1: the pipeline. 2.2: archive ~/config, update_config_directory, recreate, verify, else restore."""
    if plan.data.get("action") != "update_config_directory":
        return apply_plan(ctx, plan, opts)
    name = ctx.robot.name
    result = RobotResult(name, Outcome.CHANGED, plan.summary, warnings=list(plan.warnings), data=dict(plan.data))
    if opts.dry_run:
        result.message = f"would {plan.summary} (dry run)"
        result.data["dry_run"] = True
        return result
    client, why = engine(ctx)
    if client is None:
        result.outcome = Outcome.SKIPPED
        result.message = f"{why}: update_config_directory runs in the driver image"
        return result
    tree = str(plan.data["config_dir"])
    backup_id = new_backup_id()
    bdir = f"{BACKUP_ROOT}/{backup_id}"
    archive = f"{bdir}/config.tar.gz".replace("~", ctx.transport.home(), 1)
    manifest = {
        "id": backup_id, "created": datetime.now(timezone.utc).isoformat(timespec="seconds"), "robot": name,
        "command": opts.command, "summary": plan.summary, "compose_file": plan.compose_file,
        "recreate": list(plan.recreate), "files": [], "archive": "config.tar.gz", "config_dir": tree,
    }
    res = ctx.transport.run(Command.sh(TAR_SAVE, bdir, tree), stdin=json.dumps(manifest, indent=2).encode(),
                            timeout=300)
    if not res.ok:
        raise TransportError(name, f"backup of {tree} failed, nothing changed: {res.stderr.strip()[-300:]}")
    result.data.update(backup=backup_id, archive=archive)
    problem: str | None = None
    if plan.data.get("hard"):
        res = ctx.transport.run(Command.sh(CLEAN_TREE, tree))
        if not res.ok:
            problem = f"clearing {tree} failed: {res.stderr.strip()[-300:]}"
    if problem is None:
        mounts = [a for m in plan.data.get("env_mounts", []) for a in ("-v", str(m))]
        res = ctx.transport.run(Command.of("docker", "run", "--rm", "--network", "none",
                                           "-v", f"{tree}:{CONTAINER_CONFIG_DIR}", *mounts,
                                           str(plan.data["image"]), "update_config_directory", login=True),
                                timeout=600)
        if not res.ok:
            problem = f"update_config_directory failed: {last_line(res.stderr) or last_line(res.stdout)}"
    recreated = problem is None and opts.restart
    if recreated:
        problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.message = (f"defaults restored in {tree} from {plan.data['image']}"
                          + ("" if opts.restart else " (driver not recreated: --no-restart)")
                          + f"; previous {tree} in {archive}")
        _mark(ctx, backup_id, "applied" + ("" if opts.restart else " (not recreated)"))
        return result
    try:
        res = ctx.transport.run(Command.sh(TAR_RESTORE, bdir, tree), timeout=300)
        if not res.ok:
            raise TransportError(name, res.stderr.strip()[-300:])
        again = (recreate_and_verify(ctx, plan, min(opts.settle_s, 3.0), RobotResult(name, Outcome.OK, ""))
                 if recreated else None)
    except OpsError as exc:
        result.outcome = Outcome.FAILED
        result.message = f"{problem}; RESTORE FAILED: {exc.message} (the previous {tree} is in {archive})"
        return result
    result.outcome = Outcome.ROLLED_BACK
    result.message = (f"{problem}; {tree} restored from {archive}" + (f" (after restore: {again})" if again else "")
                      + ("" if recreated else "; the driver was not touched"))
    _mark(ctx, backup_id, f"rolled-back: {problem}")
    return result


# ------------------------------------------------------------------ fleet plumbing




