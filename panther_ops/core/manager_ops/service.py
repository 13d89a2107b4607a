"""The manager's compose service beside the driver: its mounts, its hosts file, its configuration file."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind
from panther_ops.core.manager_ops.layout import Layout
from panther_ops.core.manager_ops.projects import deployed_projects
from panther_ops.core.manager_ops.settings import (
    _SHARED_TARGETS,
    CONTAINER_DIR,
    DBUS_POWEROFF,
    DBUS_SOCKET,
    HOSTS_TARGET,
    SERVICE,
    SSH_POWEROFF,
    ManagerSettings,
)
from panther_ops.core.manager_ops.stock import CarriedParams, StockManager
from panther_ops.core.robot.compose import Volume
from panther_ops.core.robot.files import config_file
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.stack import Family
from panther_ops.core.yaml.render import Block
from panther_ops.errors import UsageError

EXISTS = "exists"
"""Fact: whether a path exists on the robot."""


# ---------------------------------------------------------------------------------------
# compose service
# ---------------------------------------------------------------------------------------
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


def service_spec(reads: Reads, cfg: RobotConfig, lay: Layout, settings: ManagerSettings) -> ServiceSpec:
    """The ``panther_ops_manager`` service for this robot's compose.yaml."""
    driver = cfg.compose.service(cfg.service)
    volumes: dict[str, str] = {CONTAINER_DIR: f"{lay.root}:{CONTAINER_DIR}:ro"}
    for vol in cfg.compose.list_volumes(cfg.service):
        if vol.source and vol.target.startswith(_SHARED_TARGETS):
            volumes[vol.target] = _ro(vol)
        elif vol.source and vol.target == DBUS_SOCKET:
            volumes[vol.target] = vol.spec()  # a socket: clients need to write to it
    known_hosts = f"{cfg.home}/.ssh/known_hosts"
    if reads.fact(EXISTS, known_hosts):
        volumes["/root/.ssh/known_hosts"] = f"{known_hosts}:/root/.ssh/known_hosts:ro"
    hosts_file, hosts_source = _hosts_file(reads, cfg, settings, volumes)
    ugv_dbus = cfg.stack.family is Family.HUSARION_UGV and DBUS_SOCKET in volumes
    command = DBUS_POWEROFF if ugv_dbus else SSH_POWEROFF
    projects = deployed_projects(cfg.stack)
    argv = [f"python3 {lay.container_archive}",
            f"--config {lay.container_config('manager.yaml')}",
            f"--lights-bt {lay.container_config('behavior_trees', projects.lights)}",
            f"--safety-bt {lay.container_config('behavior_trees', projects.safety)}",
            f"--stack {cfg.stack.version_str}"]  # message package, topics and services of this stack
    namespace = reads.namespace or cfg.compose.args.get("namespace")
    if namespace:
        argv.append(f"--namespace {namespace}")
    if settings.mode == "sim":
        argv.append(f"--sim --scenario {lay.container_config('scenario.yaml')}")
    mapping: dict[str, Any] = {"image": cfg.compose.driver_image, "container_name": SERVICE}
    merge = cfg.compose.merged_anchor(cfg.service)
    if merge is None:  # no anchor to merge: the driver's runtime settings, copied
        for key in ("network_mode", "ipc", "restart", "env_file", "environment"):
            if key in driver:
                mapping[key] = driver[key]
    if "security_opt" in driver and DBUS_SOCKET in volumes:
        mapping["security_opt"] = list(driver["security_opt"])
    mapping["volumes"] = list(volumes.values())
    mapping["command"] = Block("\n".join(argv) + "\n", ">")
    return ServiceSpec(mapping, merge, hosts_file, hosts_source, command)


def _hosts_file(reads: Reads, cfg: RobotConfig, settings: ManagerSettings,
                volumes: dict[str, str]) -> tuple[str, str]:
    """The shutdown hosts file the stock manager reads, made visible to ours: (path, where from)."""
    if settings.shutdown_hosts:  # an absolute path without '..' (the inventory checked it)
        if not reads.fact(EXISTS, settings.shutdown_hosts):
            raise UsageError(f"desired.manager.shutdown_hosts: {settings.shutdown_hosts} does not exist on "
                             f"{reads.robot}",
                             hint="push it first: panther-ops config push FILE --as shutdown-hosts")
        _check_hosts(reads, cfg, settings.shutdown_hosts)
        volumes[HOSTS_TARGET] = f"{settings.shutdown_hosts}:{HOSTS_TARGET}:ro"
        return HOSTS_TARGET, settings.shutdown_hosts
    cf = config_file(cfg.stack, FileKind.SHUTDOWN_HOSTS)
    current = cfg.compose.args.get("shutdown_hosts_config_path")
    if not current and cfg.tree_mounted:
        current = cf.container_path
    if current:
        vol = _covering(cfg, current)
        if vol is not None:
            volumes[vol.target] = _ro(vol)
            host = cfg.host_path_of(current)
            if host is not None:
                _check_hosts(reads, cfg, host)
            return current, host or current
        return current, f"{current} (inside the image)"
    return cf.package_path, f"{cf.package_path} (the image's default)"


def _check_hosts(reads: Reads, cfg: RobotConfig, path: str) -> None:
    """The hosts file the deployed manager will read, through the one hosts file validator."""
    from panther_ops.core.kinds import Target, check_file

    data = reads.file(path)
    if data is None:
        return
    check_file(FileKind.SHUTDOWN_HOSTS, path, data, target=Target(cfg.stack))


def manager_yaml(settings: ManagerSettings, spec: ServiceSpec, version: str, carried: CarriedParams,
                 stock: StockManager, intended: tuple[str, ...]) -> bytes:
    """``config/manager.yaml``: node-file shape, read by `load_manager_config`: the hosts file and
    the robot's power-off, the stock manager's values (``carried``), the inventory's
    ``desired.manager.params`` over them (later keys win); the intended differences from the
    stock manager said in its head (the plan shows the file in full)."""
    import yaml

    from panther_ops.manager.config import flatten

    params: dict[str, Any] = {"shutdown_hosts_path": spec.hosts_file,
                              "shutdown_localhost_command": spec.localhost_command}
    params.update(carried.values)
    params.update(flatten(settings.params))
    head = [f"Runtime manager parameters (docs/manager.md), written by `panther-ops manager deploy` ({version}).",
            f"What the stock manager runs with, carried over: {carried.origin};",
            "the inventory's desired.manager.params over them. Set those in the inventory and deploy again:",
            "changes made here are overwritten.",
            f"Intended differences from the stock manager of {stock.releases} (docs/manager.md):",
            *(f"- {d}" for d in intended)]
    text = "".join(f"# {line}\n" for line in head)
    return (text + yaml.safe_dump({"/**": {"ros__parameters": params}}, sort_keys=False,
                                  default_flow_style=False, width=1000, allow_unicode=True)).encode()


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
