"""Which configuration file a stack uses for what: package, file name, launch argument, template.

Facts: panther-stack.md sections 1.3-1.9 and 2.2. Templates live in
``templates/config/<family dir>/<package>/config/<file>``: ``panther-2.0`` (panther_ros
2.0.2-2.0.4, written from 2.0.4), ``panther-2.1`` (2.1.1-2.1.2, from 2.1.1),
``husarion-ugv-2.2`` (2.2.1+, from husarion_ugv_ros 2.2.2), with overlay directories for the
versions that differ (``panther-2.0.0`` for 2.0.0-2.0.1, ``panther-2.1.0``,
``husarion-ugv-2.2.0``). husarion_ugv 2.3 (ROS 2 Jazzy) keeps 2.2's files where they did not
change and overlays them (`JAZZY_DIRS`): ``husarion-ugv-2.3`` (every 2.3 tag, written from
2.3.0: the Jazzy limits schema, the EKF's ``stamped_control``), ``husarion-ugv-2.3.1``
(bringup's stamped joy2twist) and ``husarion-ugv-2.3.2`` (the twist mux, the EKF's 0.2 s
timeout, animations 16-17, the Lights tree on ``twist_mux_controller/source``, joy2twist in
husarion_ugv_teleop). Each template names the upstream file it is written from in its
header (``Source: <repo>@<tag>:<path>``, `template_source`); templates/config/README.md lists them.

Where a customised copy goes: on 2.2 the robot keeps its configuration in
``/home/husarion/config/<package>/config/<file>``, mounted at ``/config`` in the container
(``common_dir_path:=/config``). panther-ops uses the same layout on 2.0-2.1, where the
defaults live inside the image and a customised file has to be mounted and passed by its
launch argument (manual: "Modification of configuration files").
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from panther_ops.core.fleet.templates import read_template, template_path
from panther_ops.core.kinds import FileKind
from panther_ops.core.stack import Family, Generation, Stack
from panther_ops.errors import UsageError

_SOURCE = re.compile(r"(?:Source:\s*|\b)((?:panther_ros|husarion_ugv_ros)@\d+\.\d+\.\d+:[^\s)]+)")
_HEADER = 1000
"""Characters of a template that hold its header comment."""
ROBOT_CONFIG_DIR = "/home/husarion/config"
CONTAINER_CONFIG_DIR = "/config"
WHEEL_TYPES = ("WH01", "WH02", "WH04", "WH05")


_FAMILY_DIRS: dict[Generation, tuple[str, ...]] = {
    Generation.G2_0_0: ("panther-2.0.0", "panther-2.0"),
    Generation.G2_0_2: ("panther-2.0",),
    Generation.G2_1_0: ("panther-2.1.0", "panther-2.1"),
    Generation.G2_1_1: ("panther-2.1",),
    Generation.G2_2_0: ("husarion-ugv-2.2.0", "husarion-ugv-2.2"),
    Generation.G2_2_1: ("husarion-ugv-2.2",),
}
JAZZY_DIRS: dict[tuple[int, int, int], tuple[str, ...]] = {
    (2, 3, 0): ("husarion-ugv-2.3",),
    (2, 3, 1): ("husarion-ugv-2.3.1", "husarion-ugv-2.3"),
    (2, 3, 2): ("husarion-ugv-2.3.2", "husarion-ugv-2.3"),
}
"""husarion_ugv 2.3's overlays, the version's first, in front of 2.2's directories (a later
2.3 patch takes 2.3.2's until it has its own)."""


@dataclass(frozen=True)
class ConfigFile:
    """One configuration file of a stack.

    Attributes:
        kind: what it configures.
        package: ROS package that ships it (``panther_controller``...).
        filename: file name (``WH01_controller.yaml``).
        launch_arg: catalogue key of the launch argument pointing to it (None: a node
            parameter file without an argument).
        template: path under ``templates/config`` (None: panther-ops has no template).
        note: caveats (simulation only, version specifics).
    """

    kind: FileKind
    package: str
    filename: str
    launch_arg: str | None
    template: str | None
    note: str = ""

    @property
    def package_path(self) -> str:
        """``$(find <package>)/config/<file>`` -- the stack's default location."""
        return f"$(find {self.package})/config/{self.filename}"

    @property
    def robot_path(self) -> str:
        """Host path of a customised copy: ``/home/husarion/config/<package>/config/<file>``."""
        return f"{ROBOT_CONFIG_DIR}/{self.package}/config/{self.filename}"

    @property
    def container_path(self) -> str:
        """The same file inside the driver container: ``/config/<package>/config/<file>``."""
        return f"{CONTAINER_CONFIG_DIR}/{self.package}/config/{self.filename}"

    def template_text(self) -> str:
        """Default content (from ``templates/config``).

        Raises:
            UsageError: panther-ops has no template for this file.
        """
        if self.template is None:
            raise UsageError(
                f"panther-ops has no default {self.filename} for this stack",
                hint=self.note or "copy the file from the robot's image and edit it",
            )
        return read_template("config", *self.template.split("/"))


def template_source(text: str) -> str | None:
    """The upstream file a template is written from (``repo@tag:path`` in its header comment),
    or None: the template does not name one (panther-ops' own, or not traced yet)."""
    match = _SOURCE.search(text[:_HEADER])
    return match.group(1) if match else None


def _pkg(stack: Stack, name: str) -> str:
    prefix = "husarion_ugv" if stack.family is Family.HUSARION_UGV else "panther"
    return f"{prefix}_{name}"


def stock_bt_project(stack: Stack, which: str) -> tuple[str, str]:
    """(manager package, file name) of the stock ``which`` ("Lights" or "Safety") BT project on ``stack``
    (panther_ros@2.0.4 / 2.1.1:panther_manager/behavior_trees/Panther{Lights,Safety}BT.btproj;
    husarion_ugv_ros@2.2.0 / 2.2.2:husarion_ugv_manager/behavior_trees/{Lights,Safety}BT.btproj)."""
    prefix = "" if stack.family is Family.HUSARION_UGV else "Panther"
    return f"{stack.package_prefix}_manager", f"{prefix}{which}BT.btproj"


def family_dirs(stack: Stack) -> tuple[str, ...]:
    """The template directories of ``stack``, the version's overlay first."""
    base = _FAMILY_DIRS[stack.generation] if stack.version < (2, 3, 0) else _FAMILY_DIRS[Generation.G2_2_1]
    if stack.version < (2, 3, 0):
        return base
    return (*JAZZY_DIRS[min(stack.version, max(JAZZY_DIRS))], *base)


def _exists(stack: Stack, package: str, filename: str) -> str | None:
    for directory in family_dirs(stack):
        if template_path("config", directory, package, "config", filename).is_file():
            return f"{directory}/{package}/config/{filename}"
    return None


_Spec = tuple[str, str, str | None, str]  # package, filename, launch arg, note


def _wheel(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    ugv = stack.family is Family.HUSARION_UGV
    if wheel_type not in WHEEL_TYPES or (wheel_type == "WH05" and not ugv):
        raise UsageError(f"no wheel config {wheel_type!r} on {stack.label()}")
    return _pkg(stack, "description"), f"{wheel_type}.yaml", "wheel_config_path", ""


def controller_wheel_types(stack: Stack) -> tuple[str, ...]:
    """Wheel types the stack ships a controller file for (WH05, Lynx: husarion_ugv 2.2)."""
    return WHEEL_TYPES if stack.family is Family.HUSARION_UGV else WHEEL_TYPES[:3]


def _controller(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    if wheel_type not in controller_wheel_types(stack):
        raise UsageError(
            f"no default controller config for {wheel_type!r} on {stack.label()}",
            hint="custom wheels: start from WH01_controller.yaml",
        )
    return _pkg(stack, "controller"), f"{wheel_type}_controller.yaml", "controller_config_path", ""


def _components(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    if stack.version < (2, 0, 2):
        raise UsageError(f"components.yaml needs panther_ros 2.0.2+; this robot runs {stack.label()}")
    return _pkg(stack, "description"), "components.yaml", "components_config_path", ""


def _animations(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    ugv = stack.family is Family.HUSARION_UGV
    filename = f"{robot_model}_animations.yaml" if ugv else "led_config.yaml"
    return _pkg(stack, "lights"), filename, "led_config_file", ""


def _user_animations(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    ugv = stack.family is Family.HUSARION_UGV
    note = "" if ugv else "not shipped by panther_ros 2.0-2.1: the template is panther-ops' own"
    return _pkg(stack, "lights"), "user_animations.yaml", "user_led_animations_file", note


def _lights_driver(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    if stack.family is not Family.HUSARION_UGV:
        raise UsageError(f"the lights driver params file exists from husarion_ugv 2.2; this robot runs {stack.label()}")
    return _pkg(stack, "lights"), f"{robot_model}_driver.yaml", None, ""


def _shutdown_hosts(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    arg = "shutdown_hosts_config_path"
    if stack.family is Family.HUSARION_UGV:
        note = "HTTP (husarion-shutdown)" if stack.shutdown_over_http else "SSH with timeout"
        return _pkg(stack, "manager"), "shutdown_hosts.yaml", arg, note
    if stack.version >= (2, 1, 1):
        return "panther_manager", "shutdown_hosts_config.yaml", arg, "SSH"
    return "panther_bringup", "shutdown_hosts.yaml", arg, "SSH"


def _battery_plugin(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    if stack.family is Family.HUSARION_UGV:  # no driver argument: the simulation's own
        return "husarion_ugv_gazebo", "battery_plugin.yaml", None, (
            "simulation only: husarion_ugv_gazebo's simulate_robot.launch.py reads it (its battery_config_path, "
            "on the simulation's command); the driver's battery_config_path is the battery driver's parameters "
            "(husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_gazebo/launch/simulate_robot.launch.py, "
            "husarion_ugv_battery/launch/battery.launch.py)")
    note = ("simulation only; a 0-1 fraction from panther_ros 2.0.1 (panther_ros@2.0.4, @2.1.1:"
            "panther_gazebo/config/battery_plugin_config.yaml); 2.0.0 took percent: no template for it")
    return "panther_gazebo", "battery_plugin_config.yaml", "battery_config_path", note


JOY2TWIST_SINCE = (2, 2, 2)
"""The first version whose bringup launches the gamepad with its own parameters file
(``launch_gamepad``; `core.robot.gamepad`)."""


TELEOP_SINCE = (2, 3, 2)
"""The first version whose gamepad parameters are husarion_ugv_teleop's (husarion_ugv_ros@2.3.2:
husarion_ugv_teleop/launch/teleop.launch.py); 2.3.0 runs the gamepad as a compose service of its
own (husarion_ugv_ros@2.3.0:docker/demo/compose.hardware.yaml), as 2.2.0 did."""


def _joy2twist(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    if stack.family is not Family.HUSARION_UGV or stack.version < JOY2TWIST_SINCE or stack.version == (2, 3, 0):
        raise UsageError(f"the gamepad parameters are bringup's on husarion_ugv 2.2.2 and 2.3.1, teleop's from "
                         f"2.3.2; this robot runs {stack.label()} (the gamepad's own container has its own)")
    if stack.version >= TELEOP_SINCE:
        note = ("read by husarion_ugv_teleop's teleop.launch.py (which bringup always includes) as "
                "joy2twist_${ROBOT_MODEL_NAME}.yaml under common_dir_path")
        return _pkg(stack, "teleop"), f"joy2twist_{robot_model}.yaml", None, note
    note = "read by bringup (launch_gamepad:=true) as joy2twist_${ROBOT_MODEL_NAME}.yaml under common_dir_path"
    return _pkg(stack, "bringup"), f"joy2twist_{robot_model}.yaml", None, note


def _manager_bt(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
    if stack.version >= (2, 0, 2):
        raise UsageError(f"manager_bt_config.yaml is 2.0.0-2.0.1 only; this robot runs {stack.label()}")
    return "panther_manager", "manager_bt_config.yaml", None, "robot version >= 1.2"


def _manager(base: str) -> Callable[[Stack, str, str], _Spec]:
    def spec(stack: Stack, wheel_type: str, robot_model: str) -> _Spec:
        if stack.version < (2, 0, 2):
            raise UsageError(f"{base} exists from panther_ros 2.0.2; this robot runs {stack.label()}")
        filename = f"{base}.yaml" if stack.version >= (2, 1, 1) else f"{base}_config.yaml"
        return _pkg(stack, "manager"), filename, None, ""

    return spec


_SPECS: dict[FileKind, Callable[[Stack, str, str], _Spec]] = {
    FileKind.WHEEL: _wheel,
    FileKind.CONTROLLER: _controller,
    FileKind.COMPONENTS: _components,
    FileKind.LED: _animations,
    FileKind.USER_ANIMATIONS: _user_animations,
    FileKind.LIGHTS_DRIVER: _lights_driver,
    FileKind.SHUTDOWN_HOSTS: _shutdown_hosts,
    FileKind.BATTERY: _battery_plugin,
    FileKind.MANAGER_BT: _manager_bt,
    FileKind.LIGHTS_MANAGER: _manager("lights_manager"),
    FileKind.SAFETY_MANAGER: _manager("safety_manager"),
    FileKind.JOY2TWIST: _joy2twist,
}


_TEMPLATE_FROM: dict[FileKind, tuple[int, int, int]] = {FileKind.BATTERY: (2, 0, 1)}
"""Versions before these have a file no template reproduces (panther_ros 2.0.0's battery file:
percent, no capacity; the 2.0 template is 2.0.1-2.0.4's)."""


def config_file(
    stack: Stack,
    kind: FileKind,
    *,
    wheel_type: str = "WH01",
    robot_model: str = "panther",
) -> ConfigFile:
    """The file of ``kind`` on ``stack``.

    Raises:
        UsageError: the stack has no such file (e.g. lights driver params before 2.2).
    """
    package, filename, arg, note = _SPECS[kind](stack, wheel_type, robot_model)
    template = None if stack.version < _TEMPLATE_FROM.get(kind, (0, 0, 0)) else _exists(stack, package, filename)
    return ConfigFile(kind, package, filename, arg, template, note)


def config_files(stack: Stack, *, robot_model: str = "panther") -> list[ConfigFile]:
    """Every configuration file panther-ops knows for ``stack`` (one per wheel type)."""
    out: list[ConfigFile] = []
    for kind in _SPECS:
        wheel_types: tuple[str, ...] = ("",)
        if kind is FileKind.WHEEL:
            wheel_types = WHEEL_TYPES
        elif kind is FileKind.CONTROLLER:
            wheel_types = controller_wheel_types(stack)
        for wheel_type in wheel_types:
            try:
                out.append(config_file(stack, kind, wheel_type=wheel_type or "WH01", robot_model=robot_model))
            except UsageError:
                continue
    return out
