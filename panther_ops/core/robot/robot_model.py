"""The robot model (panther, lynx) a husarion_ugv driver runs as, when its command does not say.

husarion_ugv's launch files default ``robot_model`` to ``EnvironmentVariable("ROBOT_MODEL_NAME",
default_value="panther")`` (husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/
controller.launch.py, husarion_ugv_lights/launch/lights.launch.py), and the image's entrypoint
exports the robot's ``/run/husarion/robot_config.env`` (husarion_ugv_ros@2.2.2:docker/utils/
setup_environment.sh, sourced with ``set -a`` by Dockerfile.hardware). panther_ros 2.0-2.1 have
no robot_model: they drive Panthers.

The model decides defaults: husarion_ugv's ``wheel_type`` defaults to WH05 on a Lynx
(`ArgSpec.model_defaults`), and the Lynx has its own animations (``lynx_animations.yaml``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from panther_ops.core.fleet.reads import Reads
from panther_ops.core.robot.namespace import dotenv_value
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.stack import Family, Stack

ENV_KEY = "ROBOT_MODEL_NAME"


def env_robot_model(reads: Reads, stack: Stack) -> str:
    """The model the driver gets when ``robot_model:=`` is not in its command."""
    if stack.family is not Family.HUSARION_UGV:
        return "panther"
    raw = reads.file(stack.robot_env_file)
    value = dotenv_value(raw.decode(errors="replace"), ENV_KEY) if raw is not None else None
    return value or "panther"


def model_for_wheels(reads: Reads, stack: Stack, sets: Mapping[str, Any]) -> str | None:
    """The robot's ROBOT_MODEL_NAME model when a change sets the wheel type (WH05 is the Lynx
    wheel), read only then; None otherwise."""
    return env_robot_model(reads, stack) if "wheel_type" in sets else None


def robot_model_of(reads: Reads, cfg: RobotConfig) -> str:
    """The model the driver runs as: ``robot_model:=`` in its command, else ROBOT_MODEL_NAME
    (`env_robot_model`); always panther on panther_ros 2.0-2.1."""
    if cfg.stack.family is not Family.HUSARION_UGV:
        return "panther"
    return cfg.compose.args.get("robot_model") or env_robot_model(reads, cfg.stack)


def default_wheel_type(reads: Reads, cfg: RobotConfig) -> str:
    """The stack's default wheel type on this robot (WH05 on a husarion_ugv Lynx, else WH01)."""
    from panther_ops.core.robot.launch_args import spec

    return spec("wheel_type").default_for(cfg.stack, robot_model_of(reads, cfg))


def wheel_type_of(reads: Reads, cfg: RobotConfig) -> str:
    """The wheel type the driver runs with: ``wheel_type:=`` in its command, else the default
    for this robot's model (may be ``custom``)."""
    return cfg.compose.args.get("wheel_type") or default_wheel_type(reads, cfg)
