"""The robot model (panther, lynx) a husarion_ugv driver runs as, when its command does not say.

husarion_ugv's launch files default ``robot_model`` to ``EnvironmentVariable("ROBOT_MODEL_NAME",
default_value="panther")`` (husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/
controller.launch.py, husarion_ugv_lights/launch/lights.launch.py), and the image's entrypoint
exports the robot's ``/run/husarion/robot_config.env`` (husarion_ugv_ros@2.2.2:docker/utils/
setup_environment.sh, sourced with ``set -a`` by Dockerfile.hardware). panther_ros 2.0-2.1 have
no robot_model: they drive Panthers.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from panther_ops.core.config.namespace import dotenv_value
from panther_ops.core.fleet.reads import Reads
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
