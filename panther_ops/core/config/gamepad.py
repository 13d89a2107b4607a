"""The gamepad's parameters file (``config push --as joy2twist``), per stack version.

Up to 2.1 the gamepad is its own compose service (``gamepad_controller``, image
husarion/joy2twist) launched with ``joy2twist_params_file:=<file>``: the file goes to
``~/config/joy2twist/config/<name>``, is mounted into that service at
``/config/joy2twist/config/<name>`` and the argument points at it; the gamepad service is
recreated. On 2.2 the driver launches the gamepad (``launch_gamepad:=true``) with the config
tree's ``husarion_ugv_bringup/config/joy2twist_<model>.yaml`` (read through
``common_dir_path``): the tree's file is overwritten and the driver recreated.
"""

from __future__ import annotations

import posixpath

from panther_ops.core.config.compose import image_repo
from panther_ops.core.config.files import CONTAINER_CONFIG_DIR, ROBOT_CONFIG_DIR
from panther_ops.core.config.robot_config import RobotConfig
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.stack import Family
from panther_ops.errors import UsageError

ARG = "joy2twist_params_file"
PACKAGE = "joy2twist"


def gamepad_service(cfg: RobotConfig) -> str:
    """The compose service of the gamepad (<= 2.1), or exit 2 naming what is there."""
    for name in cfg.compose.services():
        image = cfg.compose.service(name).get("image")
        if name == "gamepad_controller" or (isinstance(image, str) and image_repo(image) == "husarion/joy2twist"):
            return name
    raise UsageError(f"{cfg.compose_path} has no gamepad service (gamepad_controller, image husarion/joy2twist)",
                     hint=f"on {cfg.stack.label()} the gamepad runs as its own compose service: add it as the "
                          "manual's compose.yaml has it, then push the parameters again")


def tree_path(cfg: RobotConfig, robot_model: str = "panther") -> str:
    return f"{ROBOT_CONFIG_DIR}/{cfg.stack.package_prefix}_bringup/config/joy2twist_{robot_model}.yaml"


def _mounted(cfg: RobotConfig, service: str, container_path: str) -> str | None:
    for v in cfg.compose.list_volumes(service):
        if v.source and v.target.rstrip("/") == container_path:
            return cfg.resolve(v.source)
    return None


def plan_joy2twist(reads: Reads, cfg: RobotConfig, name: str, data: bytes, warnings: list[str]) -> RobotPlan:
    """The plan of a checked joy2twist file ``name`` with content ``data`` for this robot."""
    edits: list[FileEdit] = []
    if cfg.stack.family is Family.HUSARION_UGV:
        if not cfg.tree_mounted:
            raise UsageError(f"on {cfg.stack.label()} the driver reads the gamepad parameters from the config "
                             f"tree, which {cfg.compose_path} does not mount (~/config at /config)",
                             hint="the 2.2 layout mounts /home/husarion/config at /config with "
                                  "common_dir_path:=/config")
        service = cfg.service
        if cfg.compose.args.get("launch_gamepad", "false").lower() != "true":
            warnings.append("launch_gamepad is not true: the driver does not start the gamepad "
                            "(panther-ops config set launch_gamepad true)")
        path = tree_path(cfg)
        contains: tuple[str, ...] = ()
    else:
        service = gamepad_service(cfg)
        path = f"{ROBOT_CONFIG_DIR}/{PACKAGE}/config/{name}"
        container = f"{CONTAINER_CONFIG_DIR}/{PACKAGE}/config/{name}"
        if _mounted(cfg, service, container) != path:
            cfg.compose.add_volume(path, container, ro=True, service=service)
        cfg.compose.set_arg(ARG, container, service)
        contains = (f"{ARG}:={container}",)
    before = reads.file(path)
    if before != data:
        edits.append(FileEdit(path, before, data))
    after = cfg.compose.text().encode()
    if after != cfg.before:
        edits.insert(0, FileEdit(cfg.compose_path, cfg.before, after, cfg.mode))
    summary = f"joy2twist: {name} -> {path}" + (f" ({contains[0]} in {service})" if contains else "")
    plan = RobotPlan(reads.robot, summary, edits, (service,), cfg.compose_path, [Verify(service, contains)],
                     None if edits else f"{path} already has this content", [*warnings, *cfg.compose.notes])
    plan.data["stack"] = cfg.stack.label()
    plan.data["robot_path"] = path
    plan.home = cfg.home
    return plan


def pull_joy2twist(reads: Reads, cfg: RobotConfig) -> tuple[bytes, str]:
    """The gamepad parameters in use: the mounted file (<= 2.1) or the tree's (2.2)."""
    if cfg.stack.family is Family.HUSARION_UGV:
        path = tree_path(cfg)
        if cfg.tree_mounted and (data := reads.file(path)) is not None:
            return data, f"{path} (config tree)"
        raise UsageError(f"{path} not found: the driver uses its image's default gamepad parameters",
                         hint="panther-ops has no template of the joy2twist file")
    service = gamepad_service(cfg)
    current = cfg.compose.command(service).args.get(ARG)
    if current:
        for v in cfg.compose.list_volumes(service):
            target = v.target.rstrip("/")
            if v.source and (current == target or current.startswith(target + "/")):
                host = posixpath.normpath(cfg.resolve(v.source) + current[len(target):])
                if (data := reads.file(host)) is not None:
                    return data, f"{host} (mounted into {service}, {ARG}:={current})"
    raise UsageError(f"{service} uses {ARG}:={current or '(none)'}: the image's default, not a file on the robot",
                     hint="panther-ops has no template of the joy2twist file")
