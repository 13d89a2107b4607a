"""`panther-ops manager deploy|remove`: the runtime manager as a compose service on the robot.

deploy, as ONE plan through the pipeline (diff, confirm, backup, atomic writes, recreate,
verify, roll back):

* upload ``~/panther-ops/manager/<version>/panther_ops_manager.pyz`` (`manager_bundle`),
  ``config/manager.yaml`` (the inventory's ``desired.manager.params`` over the defaults,
  the shutdown hosts file and the robot's own shutdown command), the BT projects of
  ``templates/behavior_trees/``, in simulation ``config/scenario.yaml``, and
  ``deployed.json`` (what is deployed, and what ``remove`` must restore);
* add the compose service ``panther_ops_manager``: the driver's image, the driver's
  ``x-common-config`` merge, the directory mounted read-only at ``/opt/panther-ops/manager``,
  command ``python3 .../panther_ops_manager.pyz --config ... --lights-bt ... --safety-bt ...``
  (``--sim --scenario ...`` in simulation);
* set ``disable_manager:=True`` on the driver (2.0.1+; 2.2 spells it ``true``) so the
  stock lights/safety managers stand down;
* recreate the services that changed and check both stay up.

remove reverts exactly: the service and ``disable_manager`` as they were before the first
deploy (compose.yaml byte-identical), the uploaded files deleted, empty directories too.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import posixpath
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.config.compose import Volume
from panther_ops.core.config.files import ConfigKind, config_file
from panther_ops.core.config.plans import compose_plan, edit_args
from panther_ops.core.config.robot import RobotConfig, read_config
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.stack import Family
from panther_ops.core.fleet.templates import template_file
from panther_ops.core.manager_ops.bundle import ARCHIVE_NAME, ManagerBundle, build_bundle
from panther_ops.core.yaml.render import Folded
from panther_ops.errors import OpsError, UsageError
from panther_ops.results import Diff, Outcome, RobotResult
from panther_ops.transport.base import Command

SERVICE = "panther_ops_manager"
ROBOT_DIR = "panther-ops/manager"
"""Under the robot user's home: ``/home/husarion/panther-ops/manager``."""
CONTAINER_DIR = "/opt/panther-ops/manager"
STATE_FILE = "deployed.json"
DISABLE_ARG = "disable_manager"
DISABLE_SINCE = (2, 0, 1)
BT_FILES = ("PantherLightsBT.btproj", "lights.xml", "PantherSafetyBT.btproj", "safety.xml", "shutdown.xml")
HOSTS_TARGET = "/etc/panther-ops/shutdown_hosts.yaml"
DBUS_SOCKET = "/run/dbus/system_bus_socket"
#: the 2.2 stack powers the Built-in Computer off over D-Bus (panther-stack.md 1.10)
DBUS_POWEROFF = ("dbus-send --system --print-reply --dest=org.freedesktop.login1 /org/freedesktop/login1 "
                 "org.freedesktop.login1.Manager.PowerOff boolean:true")
#: 2.0/2.1 shut the computer down from the container over SSH as husarion (ShutdownSingleHost localhost)
SSH_POWEROFF = ("ssh -o BatchMode=yes -o StrictHostKeyChecking=accept-new -i /root/.ssh/id_rsa "
                "husarion@127.0.0.1 sudo shutdown now")
#: driver volumes the manager gets too (read-only): robot environment, SSH key
_SHARED_TARGETS = ("/root/.ssh/id_rsa", "/run/husarion/")
SETTINGS = {
    "enabled": "deploy the manager on this robot (default true)",
    "mode": "ros2 (default, on the robot's ROS 2 graph) or sim (the simulation adapter, for labs)",
    "scenario": "sim: a shipped scenario name (charging, low_battery, ...) or a local scenario file",
    "params": "manager parameters (docs/manager.md), e.g. battery.percent.threshold.low: 0.3",
    "shutdown_hosts": "robot path of the shutdown hosts file (default: the one the driver uses)",
}
MODES = ("ros2", "sim")
_ANCHOR = re.compile(r"<<:\s*\*([^\s,\]]+)")


@dataclass(frozen=True)
class ManagerSettings:
    """What to deploy on one robot: the inventory's ``desired.manager`` plus command-line overrides."""

    enabled: bool = True
    mode: str = "ros2"
    scenario: str = "charging"
    params: Mapping[str, Any] = field(default_factory=dict)
    shutdown_hosts: str | None = None


def manager_settings(desired: Mapping[str, Any], *, sim: bool | None = None,
                     scenario: str | None = None) -> ManagerSettings:
    """Read ``desired.manager`` (unknown keys and values: UsageError); ``sim``/``scenario`` override it."""
    raw = desired.get("manager") or {}
    if not isinstance(raw, Mapping):
        raise UsageError("desired.manager must be a mapping", hint="keys: " + ", ".join(SETTINGS))
    unknown = sorted(set(raw) - set(SETTINGS))
    if unknown:
        raise UsageError(f"desired.manager: unknown setting {unknown[0]!r}", hint="allowed: " + ", ".join(SETTINGS))
    mode = str(raw.get("mode", "ros2"))
    if mode not in MODES:
        raise UsageError(f"desired.manager.mode {mode!r}: use ros2 or sim")
    if sim is not None:
        mode = "sim" if sim else "ros2"
    params = raw.get("params") or {}
    if not isinstance(params, Mapping):
        raise UsageError("desired.manager.params must be a mapping of manager parameters")
    hosts = raw.get("shutdown_hosts")
    if hosts is not None and (not isinstance(hosts, str) or not hosts.startswith("/")):
        raise UsageError("desired.manager.shutdown_hosts must be an absolute path on the robot")
    return ManagerSettings(bool(raw.get("enabled", True)), mode, str(scenario or raw.get("scenario", "charging")),
                           dict(params), hosts)


def scenario_path(name: str) -> Path:
    """A shipped scenario by name (``charging``), else a local file."""
    if "/" not in name and not name.endswith((".yaml", ".yml")):
        path = template_file("manager", "scenarios", f"{name}.yaml") if _shipped(name) else Path(name)
    else:
        path = Path(name)
    if not path.is_file():
        raise UsageError(f"scenario {name}: no such shipped scenario or file",
                         hint="shipped: " + ", ".join(sorted(p.stem for p in _scenarios())))
    return path


def _scenarios() -> list[Path]:
    from panther_ops.core.fleet.templates import template_path

    return sorted(template_path("manager", "scenarios").glob("*.yaml"))


def _shipped(name: str) -> bool:
    return any(p.stem == name for p in _scenarios())


# ---------------------------------------------------------------------------------------
# layout on the robot
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Layout:
    """Paths of one deployment, on the robot and inside the container."""

    home: str
    version: str

    @property
    def root(self) -> str:
        return f"{self.home}/{ROBOT_DIR}"

    @property
    def state(self) -> str:
        return f"{self.root}/{STATE_FILE}"

    @property
    def archive(self) -> str:
        return f"{self.root}/{self.version}/{ARCHIVE_NAME}"

    @property
    def container_archive(self) -> str:
        return f"{CONTAINER_DIR}/{self.version}/{ARCHIVE_NAME}"

    def config(self, *parts: str) -> str:
        return posixpath.join(self.root, "config", *parts)

    def container_config(self, *parts: str) -> str:
        return posixpath.join(CONTAINER_DIR, "config", *parts)


def _read(ctx: RobotContext, path: str) -> bytes | None:
    try:
        return ctx.transport.read_file(path)
    except FileNotFoundError:
        return None


def read_state(ctx: RobotContext, home: str) -> dict[str, Any] | None:
    """``deployed.json`` of the robot (None: nothing deployed, or unreadable)."""
    data = _read(ctx, f"{home}/{ROBOT_DIR}/{STATE_FILE}")
    if data is None:
        return None
    try:
        doc = json.loads(data)
    except ValueError:
        return None
    return doc if isinstance(doc, dict) else None


def _state_bytes(doc: Mapping[str, Any]) -> bytes:
    return (json.dumps(doc, indent=2, sort_keys=True) + "\n").encode()


@dataclass
class ManagerPlan(RobotPlan):
    """A plan whose uploaded copies show as one line each instead of a full diff.

    The archive is binary and the BT projects are the shipped templates: the operator reads
    compose.yaml, manager.yaml and deployed.json in full, the rest as what and how big.
    """

    briefs: dict[str, str] = field(default_factory=dict)

    @property
    def diffs(self) -> list[Diff]:
        return [Diff(e.path, self.briefs[e.path]) if e.path in self.briefs else e.diff() for e in self.edits]


def _size(n: int) -> str:
    return f"{n} B" if n < 1024 else (f"{n / 1024:.1f} KiB" if n < 1024 * 1024 else f"{n / 1048576:.1f} MiB")


def brief(edit: FileEdit, what: str) -> str:
    """A one-line stand-in for the diff of a file written as a whole (or removed)."""
    if edit.after is None:
        return f"--- a{edit.path}\n+++ /dev/null\n@@ removed: {_size(len(edit.before or b''))} @@\n"
    old = "/dev/null" if edit.before is None else f"a{edit.path}"
    sha = hashlib.sha256(edit.after).hexdigest()[:12]
    verb = "new file" if edit.before is None else "replaced"
    return f"--- {old}\n+++ b{edit.path}\n@@ {verb}: {_size(len(edit.after))}, sha256 {sha} @@\n+{what}\n"


def as_manager_plan(plan: RobotPlan, briefs: Mapping[str, str]) -> ManagerPlan:
    values = {f.name: getattr(plan, f.name) for f in dataclasses.fields(RobotPlan)}
    return ManagerPlan(**values, briefs=dict(briefs))


# ---------------------------------------------------------------------------------------
# compose service
# ---------------------------------------------------------------------------------------
def _anchor(cfg: RobotConfig) -> str | None:
    """The anchor the driver merges (``common-config``), if any."""
    raw = cfg.compose.doc.info(("services", cfg.service)).raw
    m = _ANCHOR.search(raw)
    return m.group(1) if m else None


def _ro(vol: Volume) -> str:
    if vol.read_only or not vol.source:
        return vol.spec()
    return f"{vol.source}:{vol.target}:{'ro,' + vol.options if vol.options else 'ro'}"


def _covering(cfg: RobotConfig, container_path: str) -> Volume | None:
    best: Volume | None = None
    for vol in cfg.compose.list_volumes(cfg.service):
        target = vol.target.rstrip("/")
        if vol.source and (container_path == target or container_path.startswith(target + "/")) and (
                best is None or len(target) > len(best.target.rstrip("/"))):
            best = vol
    return best


@dataclass
class ServiceSpec:
    """The manager service as it will be written, and what went into it."""

    mapping: dict[str, Any]
    merge: str | None
    hosts_file: str
    """What manager.yaml names as shutdown_hosts_path (container path or $(find ...))."""
    hosts_source: str
    localhost_command: str


def service_spec(ctx: RobotContext, cfg: RobotConfig, lay: Layout, settings: ManagerSettings) -> ServiceSpec:
    """The ``panther_ops_manager`` service for this robot's compose.yaml."""
    driver = cfg.compose.service(cfg.service)
    volumes: dict[str, str] = {CONTAINER_DIR: f"{lay.root}:{CONTAINER_DIR}:ro"}
    for vol in cfg.compose.list_volumes(cfg.service):
        if vol.source and vol.target.startswith(_SHARED_TARGETS):
            volumes[vol.target] = _ro(vol)
        elif vol.source and vol.target == DBUS_SOCKET:
            volumes[vol.target] = vol.spec()  # a socket: clients need to write to it
    known_hosts = f"{cfg.home}/.ssh/known_hosts"
    if ctx.transport.exists(known_hosts):
        volumes["/root/.ssh/known_hosts"] = f"{known_hosts}:/root/.ssh/known_hosts:ro"
    hosts_file, hosts_source = _hosts_file(ctx, cfg, settings, volumes)
    ugv_dbus = cfg.stack.family is Family.HUSARION_UGV and DBUS_SOCKET in volumes
    command = DBUS_POWEROFF if ugv_dbus else SSH_POWEROFF
    argv = [f"python3 {lay.container_archive}",
            f"--config {lay.container_config('manager.yaml')}",
            f"--lights-bt {lay.container_config('behavior_trees', 'PantherLightsBT.btproj')}",
            f"--safety-bt {lay.container_config('behavior_trees', 'PantherSafetyBT.btproj')}",
            f"--stack {cfg.stack.version_str}"]  # message package, topics and services of this stack
    namespace = ctx.robot.namespace or cfg.compose.args.get("namespace")
    if namespace:
        argv.append(f"--namespace {namespace}")
    if settings.mode == "sim":
        argv.append(f"--sim --scenario {lay.container_config('scenario.yaml')}")
    mapping: dict[str, Any] = {"image": cfg.compose.driver_image, "container_name": SERVICE}
    merge = _anchor(cfg)
    if merge is None:  # no anchor to merge: the driver's runtime settings, copied
        for key in ("network_mode", "ipc", "restart", "env_file", "environment"):
            if key in driver:
                mapping[key] = driver[key]
    if "security_opt" in driver and DBUS_SOCKET in volumes:
        mapping["security_opt"] = list(driver["security_opt"])
    mapping["volumes"] = list(volumes.values())
    mapping["command"] = Folded("\n".join(argv) + "\n")
    return ServiceSpec(mapping, merge, hosts_file, hosts_source, command)


def _hosts_file(ctx: RobotContext, cfg: RobotConfig, settings: ManagerSettings,
                volumes: dict[str, str]) -> tuple[str, str]:
    """The shutdown hosts file the stock manager reads, made visible to ours: (path, where from)."""
    if settings.shutdown_hosts:
        if ".." in settings.shutdown_hosts.split("/"):
            raise UsageError(f"desired.manager.shutdown_hosts: {settings.shutdown_hosts} holds '..': name the file "
                             "directly")
        if not ctx.transport.exists(settings.shutdown_hosts):
            raise UsageError(f"desired.manager.shutdown_hosts: {settings.shutdown_hosts} does not exist on "
                             f"{ctx.robot.name}",
                             hint="push it first: panther-ops config push FILE --as shutdown-hosts")
        _check_hosts(ctx, cfg, settings.shutdown_hosts)
        volumes[HOSTS_TARGET] = f"{settings.shutdown_hosts}:{HOSTS_TARGET}:ro"
        return HOSTS_TARGET, settings.shutdown_hosts
    cf = config_file(cfg.stack, ConfigKind.SHUTDOWN_HOSTS)
    current = cfg.compose.args.get("shutdown_hosts_config_path")
    if not current and cfg.tree_mounted:
        current = cf.container_path
    if current:
        vol = _covering(cfg, current)
        if vol is not None:
            volumes[vol.target] = _ro(vol)
            host = cfg.host_path_of(current)
            if host is not None:
                _check_hosts(ctx, cfg, host)
            return current, host or current
        return current, f"{current} (inside the image)"
    return cf.package_path, f"{cf.package_path} (the image's default)"


def _check_hosts(ctx: RobotContext, cfg: RobotConfig, path: str) -> None:
    """The hosts file the deployed manager will read, through the one hosts file validator."""
    from panther_ops.core.config.kinds import FileKind, Target, check_file

    try:
        data = ctx.transport.read_file(path)
    except FileNotFoundError:
        return
    check_file(FileKind.SHUTDOWN_HOSTS, path, data, target=Target(cfg.stack))


def manager_yaml(settings: ManagerSettings, spec: ServiceSpec, version: str) -> bytes:
    """``config/manager.yaml``: node-file shape, read by `load_manager_config`."""
    import yaml

    params: dict[str, Any] = {"shutdown_hosts_path": spec.hosts_file,
                              "shutdown_localhost_command": spec.localhost_command}
    params.update(settings.params)
    head = (f"# Runtime manager parameters (docs/manager.md), written by `panther-ops manager deploy` ({version}).\n"
            "# Defaults for everything not listed; set them in the inventory (desired.manager.params) and\n"
            "# deploy again: changes made here are overwritten.\n")
    return (head + yaml.safe_dump({"/**": {"ros__parameters": params}}, sort_keys=False,
                                  default_flow_style=False, width=1000)).encode()


def _check_params(params: Mapping[str, Any]) -> list[str]:
    from panther_ops.manager.config import config_with_params
    from panther_ops.manager.errors import ManagerError

    try:
        cfg = config_with_params(params, source="desired.manager.params")
    except ManagerError as exc:
        raise UsageError(f"desired.manager.params: {exc}") from None
    return list(cfg.notes)


def _check_scenario(path: Path) -> None:
    from panther_ops.manager.errors import ManagerError
    from panther_ops.manager.sim.scenario import load_scenario

    try:
        load_scenario(path)
    except ManagerError as exc:
        raise UsageError(f"scenario {path}: {exc}") from None


# ---------------------------------------------------------------------------------------
# deploy
# ---------------------------------------------------------------------------------------
def _arg_name(cfg: RobotConfig) -> str:
    from panther_ops.core.config.launch_args import spec

    return spec(DISABLE_ARG).name_for(cfg.stack)


def _refuse_old(cfg: RobotConfig, robot: str) -> None:
    if cfg.stack.version < DISABLE_SINCE:
        raise UsageError(
            f"{robot} runs {cfg.stack.label()}: disable_manager exists from panther_ros 2.0.1, so the stock "
            "manager could not be stood down and two managers would drive the lights and the E-stop",
            hint="update the driver first (panther-ops driver update), then deploy the manager",
        )


def plan_deploy(ctx: RobotContext, *, sim: bool | None = None, scenario: str | None = None,
                bundle: ManagerBundle | None = None) -> RobotPlan:
    """One plan: upload, service, disable_manager; nothing is written here."""
    cfg = read_config(ctx)
    _refuse_old(cfg, ctx.robot.name)
    settings = manager_settings(ctx.robot.desired, sim=sim, scenario=scenario)
    if not settings.enabled:
        plan = compose_plan(ctx, cfg, "no change", [], [], "desired.manager.enabled is false: not deployed "
                            "(panther-ops manager remove takes a deployed one away)")
        plan.recreate = ()
        return plan
    warnings = _check_params(settings.params)
    bundle = bundle or build_bundle()
    lay = Layout(cfg.home, bundle.version)
    state = read_state(ctx, cfg.home)
    spec = service_spec(ctx, cfg, lay, settings)
    ssh_via = None
    if settings.mode == "ros2":  # the stock manager stands down: ours must do what it did
        from panther_ops.core.manager_ops.checks import check_safety

        command = str(settings.params.get("shutdown_localhost_command", spec.localhost_command))
        w, ssh_via = check_safety(ctx, cfg, spec.hosts_file, spec.hosts_source, command)
        warnings += w
    arg = _arg_name(cfg)
    files, what = _deploy_files(cfg, lay, settings, spec, bundle, state, arg)
    edits = _file_edits(ctx, lay, files, state)
    _put_service(cfg, spec)
    driver_before = cfg.compose.service(cfg.service)
    w, driver_verify = edit_args(cfg, {DISABLE_ARG: True}, [], False)
    warnings += w
    driver_changed = cfg.compose.service(cfg.service) != driver_before
    recreate = [SERVICE]
    verify = [Verify(SERVICE, (lay.container_archive,))]
    if driver_changed:
        recreate.insert(0, cfg.service)
        verify.insert(0, driver_verify)
    old_version = state.get("version") if state else None
    head = (f"manager {old_version} -> {bundle.version}" if old_version and old_version != bundle.version
            else f"manager {bundle.version}")
    parts = [f"deploy {head} ({settings.mode}) as service {SERVICE} on {cfg.compose.driver_image}"]
    if driver_changed:
        parts.append(f"{arg}:={cfg.compose.args[arg]} on {cfg.service} (stock manager stands down)")
    noop = (f"manager {bundle.version} ({settings.mode}) already deployed; "
            f"{arg}:={cfg.compose.args.get(arg)} on {cfg.service}")
    briefs = {e.path: brief(e, what.get(e.path, "")) for e in edits if e.path in what or e.after is None}
    plan = as_manager_plan(compose_plan(ctx, cfg, "; ".join(parts), warnings, verify, noop, extra=edits), briefs)
    plan.recreate = tuple(recreate) if plan.edits else ()
    plan.warnings = [x for x in plan.warnings if not x.startswith(f"services.{SERVICE}.")]
    if not plan.edits:
        plan.warnings += _running_warning(ctx)
    plan.data.update({"action": "deploy", "version": bundle.version, "mode": settings.mode, "service": SERVICE,
                      "image": cfg.compose.driver_image, "shutdown_hosts": spec.hosts_source,
                      "stack": cfg.stack.version_str, "ssh_shutdowns": ssh_via})
    return plan


def _deploy_files(cfg: RobotConfig, lay: Layout, settings: ManagerSettings, spec: ServiceSpec,
                  bundle: ManagerBundle, state: Mapping[str, Any] | None,
                  arg: str) -> tuple[dict[str, bytes], dict[str, str]]:
    """Every file of the deployment (robot path -> content) and one-line descriptions of the copies."""
    files: dict[str, bytes] = {lay.archive: bundle.data,
                               lay.config("manager.yaml"): manager_yaml(settings, spec, bundle.version)}
    what = {lay.archive: f"{ARCHIVE_NAME} {bundle.version}: panther_ops.manager + "
                         + ", ".join(f"{k} {v}" for k, v in bundle.dependencies.items())}
    for bt in BT_FILES:
        files[lay.config("behavior_trees", bt)] = template_file("behavior_trees", bt).read_bytes()
        what[lay.config("behavior_trees", bt)] = f"copy of templates/behavior_trees/{bt}"
    if settings.mode == "sim":
        source = scenario_path(settings.scenario)
        _check_scenario(source)
        files[lay.config("scenario.yaml")] = source.read_bytes()
        what[lay.config("scenario.yaml")] = f"scenario {settings.scenario} ({source.name})"
    doc = {
        "format": 1, "version": bundle.version, "build": bundle.build, "mode": settings.mode,
        "service": SERVICE, "driver_service": cfg.service, "compose_file": cfg.compose_path,
        "image": cfg.compose.driver_image, "archive_sha256": bundle.sha256, "dependencies": bundle.dependencies,
        # what remove restores: kept from the first deploy on
        "disable_manager_before": state.get("disable_manager_before") if state else cfg.compose.args.get(arg),
        "files": sorted(files),
        "scenario": settings.scenario if settings.mode == "sim" else None,
    }
    files[lay.state] = _state_bytes(doc)
    return files, what


def _file_edits(ctx: RobotContext, lay: Layout, files: Mapping[str, bytes],
                state: Mapping[str, Any] | None) -> list[FileEdit]:
    """Files to write (content differs) and files of an earlier deployment to delete."""
    edits: list[FileEdit] = []
    for path, content in files.items():
        before = _read(ctx, path)
        if before != content:
            edits.append(FileEdit(path, before, content))
    earlier = {str(p) for p in (state or {}).get("files", [])}
    for old_path in sorted(earlier - set(files)):
        if not old_path.startswith(lay.root + "/"):
            continue  # never delete outside our directory, whatever deployed.json says
        old = _read(ctx, old_path)
        if old is not None:
            edits.append(FileEdit(old_path, old, None))
    return edits


def _put_service(cfg: RobotConfig, spec: ServiceSpec) -> None:
    """The service in compose.yaml as planned (unchanged when it already is)."""
    compose = cfg.compose
    if SERVICE in compose.services():
        try:
            compose.add_service(SERVICE, spec.mapping, merge=spec.merge)  # False: already as planned
            return
        except UsageError:  # there, with other settings: rewrite it
            compose.remove_service(SERVICE)
    compose.add_service(SERVICE, spec.mapping, merge=spec.merge)


def _running_warning(ctx: RobotContext) -> list[str]:
    try:
        client = ctx.transport.docker()
        if client is None:
            return []
        ctrs = service_containers(client)
    except OpsError:
        return []
    except Exception:  # docker SDK errors: the plan stays valid, the status command says more
        return []
    if not ctrs:
        return [f"service {SERVICE} has no container: `docker compose up -d {SERVICE}` on the robot starts it"]
    state = ctrs[0].attrs.get("State", {})
    if state.get("Status") != "running":
        return [f"container {SERVICE} is {state.get('Status')} (exit code {state.get('ExitCode')}): "
                "see `panther-ops manager logs`"]
    return []


# ---------------------------------------------------------------------------------------
# remove
# ---------------------------------------------------------------------------------------
def plan_remove(ctx: RobotContext) -> RobotPlan:
    """Take the service out, put disable_manager back as it was, delete the uploaded files."""
    cfg = read_config(ctx)
    state = read_state(ctx, cfg.home)
    compose = cfg.compose
    root = f"{cfg.home}/{ROBOT_DIR}"
    warnings: list[str] = []
    present = SERVICE in compose.services()
    if not present and state is None:
        plan = compose_plan(ctx, cfg, "no change", [], [], "the manager is not deployed")
        plan.recreate = ()
        return plan
    arg = _arg_name(cfg)
    if present:
        compose.remove_service(SERVICE)
    driver_before = compose.service(cfg.service)
    verify = Verify(cfg.service)
    if state is not None:
        before = state.get("disable_manager_before")
        if before is None:
            if arg in compose.args:
                verify = Verify(cfg.service, cmd_lacks=(f"{arg}:={compose.args[arg]}",))
                compose.unset_arg(arg)
        elif compose.args.get(arg) != str(before):
            compose.set_arg(arg, str(before))
            verify = Verify(cfg.service, (f"{arg}:={before}",))
    elif arg in compose.args:
        verify = Verify(cfg.service, cmd_lacks=(f"{arg}:={compose.args[arg]}",))
        compose.unset_arg(arg)
        warnings.append(f"no {root}/{STATE_FILE}: {arg} is unset (assumed it was not set before the deploy)")
    driver_changed = compose.service(cfg.service) != driver_before
    edits: list[FileEdit] = []
    paths = [str(p) for p in (state or {}).get("files", []) if str(p).startswith(root + "/")]
    for path in [*sorted(set(paths)), f"{root}/{STATE_FILE}"]:
        old = _read(ctx, path)
        if old is not None:
            edits.append(FileEdit(path, old, None))
    version = (state or {}).get("version", "?")
    parts = [f"remove manager {version} (service {SERVICE})" if present else f"remove manager {version} files"]
    if driver_changed:
        parts.append(f"{arg} restored on {cfg.service} (stock manager back)")
    plan = as_manager_plan(compose_plan(ctx, cfg, "; ".join(parts), warnings, [verify] if driver_changed else [],
                                        "the manager is not deployed", extra=edits),
                           {e.path: brief(e, "") for e in edits if e.path != cfg.compose_path})
    plan.recreate = (cfg.service,) if driver_changed else ()
    plan.data.update({"action": "remove", "version": version, "service": SERVICE, "root": root,
                      "had_service": present})
    return plan


# ---------------------------------------------------------------------------------------
# apply (the pipeline, plus the container the pipeline does not know about)
# ---------------------------------------------------------------------------------------
def service_containers(client: Any) -> list[Any]:
    return list(client.containers.list(all=True, filters={"label": f"com.docker.compose.service={SERVICE}"}))


_TIDY = ('r="${PANTHER_OPS_ROOT:-}"; d="$r$1"; [ -d "$d" ] || exit 0; '
         'find "$d" -mindepth 1 -depth -type d -empty -delete 2>/dev/null; '
         'rmdir "$d" 2>/dev/null && rmdir "$(dirname "$d")" 2>/dev/null; exit 0')


def tidy(ctx: RobotContext, root: str) -> None:
    """Delete empty directories left under the manager's directory (and it, and ~/panther-ops, if empty)."""
    try:
        ctx.transport.run(Command.sh(_TIDY, root))
    except OpsError:
        return


def _last_log(container: Any, lines: int = 3) -> str:
    try:
        text = container.logs(tail=lines).decode(errors="replace").strip()
    except Exception:  # a log is a courtesy here
        return ""
    unique = list(dict.fromkeys(t.strip() for t in text.splitlines() if t.strip()))
    return " | ".join(unique)[-400:]


def apply_manager(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """`apply_plan`, with the manager container handled where compose alone would not:

    * remove: the container is stopped before compose.yaml changes (never two managers at
      once) and deleted once the change is verified (``compose up`` leaves orphans running);
    * a rolled-back deploy of a new service: the orphan container is deleted and the driver
      recreated from the restored compose.yaml (the pipeline's own restore asked compose for
      a service the restored file no longer has).
    """
    action = plan.data.get("action")
    if not plan.edits or opts.dry_run or action not in ("deploy", "remove"):
        return apply_plan(ctx, plan, opts)
    client = ctx.transport.docker()
    stopped: list[Any] = []
    if action == "remove" and client is not None:
        for c in service_containers(client):
            if c.status == "running":
                c.stop(timeout=10)
                stopped.append(c)
    try:
        result = apply_plan(ctx, plan, opts)
    except BaseException:
        for c in stopped:
            c.start()
        raise
    root = f"{ctx.transport.home()}/{ROBOT_DIR}"
    if result.outcome is Outcome.CHANGED:
        if action == "remove" and client is not None:
            for c in service_containers(client):
                c.remove(force=True)
        tidy(ctx, root)
        return result
    if "backup" in result.data:  # written, then restored by the pipeline: make the containers match
        _repair(ctx, plan, client, result, stopped)
        tidy(ctx, root)
    else:
        for c in stopped:
            c.start()
    return result


def _repair(ctx: RobotContext, plan: RobotPlan, client: Any, result: RobotResult, stopped: list[Any]) -> None:
    from panther_ops.core.fleet.pipeline import recreate_and_verify

    if client is None:
        return
    cfg = read_config(ctx)
    services = [cfg.service]
    if SERVICE in cfg.compose.services():
        services.append(SERVICE)
    else:
        for c in service_containers(client):
            log = _last_log(c)
            if log:
                result.message += f"; manager log: {log}"
            c.remove(force=True)
    result.message = re.sub(r" \(after restore: docker compose up failed: [^)]*\)", "", result.message)
    restore = RobotPlan(plan.robot, "restore", [], tuple(services), plan.compose_file, [])
    problem = recreate_and_verify(ctx, restore, 3.0, RobotResult(plan.robot, Outcome.OK, ""))
    if problem:
        result.outcome = Outcome.FAILED
        result.message += f"; after restore: {problem}"
    for c in stopped:
        with contextlib.suppress(Exception):  # recreated by compose above: nothing to start
            c.reload()
            if c.status != "running":
                c.start()
