"""The gamepad's parameters file (``config push --as joy2twist``, planned by
`config/plan.py`'s ``plan_joy2twist``; pulled by `pull.py`), per stack version.

Where the gamepad runs decides where its parameters go (evidence below):

* its own compose service (``gamepad_controller``, image husarion/joy2twist), launched with
  ``ros2 launch joy2twist gamepad_controller.launch.py joy2twist_params_file:=<file>``: panther_ros
  2.0-2.1 (panther-docker demo/compose.minimal-setup.yaml) and husarion_ugv 2.2.0/2.2.1 (their
  docker/demo/compose.hardware.yaml mounts ``/home/husarion/config/common/joy2twist.yaml`` at
  ``/joy2twist.yaml``). The file goes to ``~/config/joy2twist/config/<name>``, is mounted at
  ``/config/joy2twist/config/<name>`` and the argument points at it; where the argument
  already names a mounted file on 2.2 (that 2.2.0 layout), that file is replaced in place. The
  gamepad service is recreated.
* the driver (husarion_ugv 2.2.2+, ``launch_gamepad:=true``): 2.2.2's
  ``husarion_ugv_bringup/launch/bringup.launch.py`` declares ``launch_gamepad`` and includes
  joy2twist's ``gamepad_controller.launch.py`` with ``joy2twist_params_file`` computed as
  ``<common_dir_path>/husarion_ugv_bringup/config/joy2twist_<ROBOT_MODEL_NAME>.yaml`` (the
  package share's when common_dir_path is empty). Bringup does not declare
  ``joy2twist_params_file`` and the include sets it, so passing it to bringup changes nothing:
  the config tree's file is the one to write (``~/config/husarion_ugv_bringup/config/
  joy2twist_<model>.yaml``, mounted at /config), and the driver is recreated.

Evidence: husarion_ugv_bringup's CHANGELOG.rst (ros2-gbp/husarion_ugv_ros-release) lists
"[Backport humble-devel] Add joy2twist dependency (#581)" under 2.2.2 (2025-07-09) and nothing
of the gamepad under 2.2.1; husarion/husarion_ugv_ros#555 (ros2-devel) and #581 (humble) add
``launch_gamepad`` and the include above to bringup.launch.py; husarion/husarion_ugv_ros
docker/demo/compose.hardware.yaml for humble-2.2.0 (and jazzy-2.3.0) still runs
``gamepad_controller`` with ``joy2twist_params_file:=/joy2twist.yaml``. docs/remote.md cites them.
"""

from __future__ import annotations

import posixpath
from dataclasses import dataclass

from panther_ops.core.fleet.reads import Reads
from panther_ops.core.robot.compose import image_repo
from panther_ops.core.robot.files import CONTAINER_CONFIG_DIR, JOY2TWIST_SINCE, ROBOT_CONFIG_DIR
from panther_ops.core.robot.namespace import dotenv_value
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.stack import Family
from panther_ops.errors import UsageError

ARG = "joy2twist_params_file"
PACKAGE = "joy2twist"


def find_gamepad_service(cfg: RobotConfig) -> str | None:
    """The compose service of the gamepad (gamepad_controller, or an image husarion/joy2twist)."""
    for name in cfg.compose.services():
        image = cfg.compose.service(name).get("image")
        if name == "gamepad_controller" or (isinstance(image, str) and image_repo(image) == "husarion/joy2twist"):
            return name
    return None


def gamepad_service(cfg: RobotConfig) -> str:
    """The compose service of the gamepad (<= 2.1), or exit 2 naming what is there."""
    found = find_gamepad_service(cfg)
    if found is not None:
        return found
    raise UsageError(f"{cfg.compose_path} has no gamepad service (gamepad_controller, image husarion/joy2twist)",
                     hint=f"on {cfg.stack.label()} the gamepad runs as its own compose service: add it as the "
                          "manual's compose.yaml has it, then push the parameters again")


LAUNCHED_BY_DRIVER = JOY2TWIST_SINCE
"""The first version whose bringup launches the gamepad (``launch_gamepad``, see the module's text)."""


def tree_path(cfg: RobotConfig, robot_model: str = "panther") -> str:
    return f"{ROBOT_CONFIG_DIR}/{cfg.stack.package_prefix}_bringup/config/joy2twist_{robot_model}.yaml"


def robot_model(reads: Reads, cfg: RobotConfig) -> str:
    """ROBOT_MODEL_NAME of the robot's env file (the bringup's name of the file), else panther."""
    raw = reads.file(cfg.stack.robot_env_file)
    if raw is None:
        return "panther"
    text = raw.decode(errors="replace")
    model = dotenv_value(text, "ROBOT_MODEL_NAME") or "panther"
    return model if model in ("panther", "lynx") else "panther"


def _mounted(cfg: RobotConfig, service: str, container_path: str) -> str | None:
    for v in cfg.compose.list_volumes(service):
        if v.source and v.target.rstrip("/") == container_path:
            return cfg.resolve(v.source)
    return None


def _mounted_file(cfg: RobotConfig, service: str, container_file: str) -> str | None:
    """The host file bind-mounted at ``container_file`` (exactly) in ``service``, if any."""
    for v in cfg.compose.list_volumes(service):
        if v.source and v.target.rstrip("/") == container_file.rstrip("/"):
            return cfg.resolve(v.source)
    return None


def driver_target(reads: Reads, cfg: RobotConfig, warnings: list[str]) -> tuple[str, str]:
    """husarion_ugv 2.2.2+ without a gamepad service: the driver's service and the tree's file."""
    if cfg.stack.version < LAUNCHED_BY_DRIVER:
        raise UsageError(f"{cfg.compose_path} has no gamepad service, and on {cfg.stack.label()} the driver does "
                         "not launch the gamepad (launch_gamepad came with husarion_ugv 2.2.2)",
                         hint="add the gamepad_controller service of husarion_ugv_ros 2.2.0's "
                              "docker/demo/compose.hardware.yaml (husarion/joy2twist, "
                              "joy2twist_params_file:=/joy2twist.yaml), or update the driver to 2.2.2")
    if not cfg.tree_mounted:
        raise UsageError(f"on {cfg.stack.label()} the driver reads the gamepad parameters from the config "
                         f"tree, which {cfg.compose_path} does not mount (~/config at /config)",
                         hint="the 2.2 layout mounts /home/husarion/config at /config with "
                              "common_dir_path:=/config")
    if cfg.compose.args.get("launch_gamepad", "false").lower() != "true":
        warnings.append("launch_gamepad is not true: the driver does not start the gamepad "
                        "(panther-ops config set launch_gamepad true)")
    if ARG in cfg.compose.args:
        warnings.append(f"{ARG}:= on the driver's command has no effect on {cfg.stack.label()}: bringup passes "
                        f"its own (the config tree's joy2twist_<model>.yaml), which is the file written")
    return cfg.service, tree_path(cfg, robot_model(reads, cfg))


def service_target(cfg: RobotConfig, service: str, name: str) -> tuple[str, tuple[str, ...]]:
    """The gamepad's own service: the file it is given (``joy2twist_params_file:=``) and the
    words its command must hold; the mount and argument are added to ``cfg.compose``."""
    current = cfg.compose.command(service).args.get(ARG)
    if current and cfg.stack.family is Family.HUSARION_UGV:  # 2.2.0/2.2.1: ~/config/common/joy2twist.yaml
        host = _mounted_file(cfg, service, current)
        if host is not None:
            return host, (f"{ARG}:={current}",)
    path = f"{ROBOT_CONFIG_DIR}/{PACKAGE}/config/{name}"
    container = f"{CONTAINER_CONFIG_DIR}/{PACKAGE}/config/{name}"
    if _mounted(cfg, service, container) != path:
        cfg.compose.add_volume(path, container, ro=True, service=service)
    cfg.compose.set_arg(ARG, container, service)
    return path, (f"{ARG}:={container}",)


IMAGE_PREFIX = "/ros2_ws/install/joy2twist"
"""``$(ros2 pkg prefix joy2twist)`` in a husarion/joy2twist image: it is built in /ros2_ws with
``colcon build --symlink-install`` (husarion/joy2twist@2f8ad45:Dockerfile, unchanged since
2023-02-28, so the same for the images humble-1.0.0-20240109 of panther-docker@2.0.4 and
humble-1.0.0-20240725-stable of @2.1.1), so the package's prefix is /ros2_ws/install/joy2twist
and its ``share/joy2twist/config/*.yaml`` are symlinks to /ros2_ws/src/joy2twist/config/
(joy2twist/CMakeLists.txt installs ``config`` to ``share/joy2twist``)."""
DEFAULT_PARAMS = "share/joy2twist/config/joy2twist.yaml"
"""gamepad_controller.launch.py's default ``joy2twist_params_file`` (husarion/joy2twist@2f8ad45:
joy2twist/launch/gamepad_controller.launch.py), under the package's prefix."""
TEMPLATE_SOURCE = "husarion/joy2twist@2f8ad45:joy2twist/config/joy2twist_panther.yaml"


@dataclass(frozen=True)
class InImage:
    """The gamepad parameters in use are the image's own file: ``path`` in ``service``'s container."""

    service: str
    path: str
    arg: str


def pull_joy2twist(reads: Reads, cfg: RobotConfig) -> tuple[bytes, str] | InImage | None:
    """The gamepad parameters in use: the file mounted into the gamepad's service, or the
    config tree's (husarion_ugv 2.2.2+, the driver launching the gamepad), or (`InImage`) the
    image's file the command names, for the caller to read from the container; None: the driver
    (2.2.2+) uses its image's default (`files.config_file` of ``JOY2TWIST`` names it)."""
    if cfg.stack.family is Family.HUSARION_UGV and find_gamepad_service(cfg) is None:
        path = tree_path(cfg, robot_model(reads, cfg))
        if cfg.tree_mounted and (data := reads.file(path)) is not None:
            return data, f"{path} (config tree)"
        if cfg.stack.version >= LAUNCHED_BY_DRIVER:
            return None
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
    path = (current or f"{IMAGE_PREFIX}/{DEFAULT_PARAMS}").replace("$(ros2 pkg prefix joy2twist)", IMAGE_PREFIX)
    if posixpath.isabs(path) and "$" not in path and cfg.stack.family is Family.PANTHER_ROS:
        return InImage(service, posixpath.normpath(path), f"{ARG}:={current}" if current else f"{ARG} (default)")
    raise UsageError(f"{service} uses {ARG}:={current or '(none)'}: the image's default, not a file on the robot",
                     hint="panther-ops has no template of the joy2twist file")
