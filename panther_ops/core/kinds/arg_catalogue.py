"""The catalogue of the driver's launch arguments per stack version (panther-stack.md 1.1),
and what any argument's name and value must be to be written at all.

Below the features (`config`'s checks and edits) and the inventory (``desired.launch_args``,
checked when it loads), so both read one catalogue: which names are one argument (a name
of another version, an alias) and which text can never be a launch argument.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

from panther_ops.core.stack import Family, Stack

Version = tuple[int, int, int]


class ArgType(str, Enum):
    BOOL = "bool"
    CHOICE = "choice"
    PATH = "path"
    DIR = "dir"
    NAMESPACE = "namespace"
    STRING = "string"


Default = str | Callable[[Stack], str]


IMAGE_PREFIXES = ("/ros2_ws/", "/opt/ros/", "/husarion_utils/")
"""Where the driver image's own files are, inside the container: a path argument there needs no
volume. The catalogue's defaults are read from the image (``$(find <pkg>)/...``, resolved by
ament to ``/ros2_ws/install/<pkg>/share/<pkg>`` of the image's workspace, the path `config pull`
reads an image default from; ROS's own packages under ``/opt/ros/<distro>``); Husarion's images
keep their helper launch files in ``/husarion_utils`` (the nmea-gps image's
``nmea_navsat.launch.py``). A path under one of them is not refused when no volume mounts it:
whether the file is in that image is not known before the driver starts (a warning says so)."""

PATH_CHARACTERS = "ASCII letters, digits, '_', '.', '+', '-' and '/'"
"""The characters of a path argument (config push allows the same in the file names it writes):
nothing a shell, compose or launch reads specially, no space, no '~' (the command is not run
by a shell, so '~' is never expanded; the path is absolute anyway)."""


@dataclass(frozen=True)
class ArgSpec:
    """One launch argument.

    Attributes:
        key: catalogue key (the panther_ros 2.0/2.1 name, or the 2.2 name if 2.2-only).
        type: value type.
        description: one line for docs and ``--help``.
        since / until: first / last version (inclusive) that declares it.
        names: ``(from_version, name)`` renames, oldest first (``key`` before the first).
        choices: allowed values for CHOICE (``extra_choices`` adds per-version ones).
        default: the stack's default (callable for version-dependent defaults).
        aliases: other accepted input names, each with a note shown to the operator.
        sim_only_until: on versions up to this one the argument only matters in simulation.
        allow_none: the literal ``None`` disables the feature (components_config_path).
        tree_since: from this version on (husarion_ugv 2.2+) the default is read under
            ``common_dir_path`` -- the robot's ``~/config`` tree, mounted at ``/config`` -- when
            that argument is set; None (or an older stack): from the image (``$(find <package>)``).
            A file in the tree that the stack reads from the image is not used unless the
            argument names it.
        model_defaults: ``(from_version, robot_model, default)``: from that version on, the
            default on a robot of that model (the launch files' ``robot_model``) instead of
            ``default`` (``wheel_type``: WH05 on a Lynx).
    """

    key: str
    type: ArgType
    description: str
    since: Version = (2, 0, 0)
    until: Version | None = None
    names: tuple[tuple[Version, str], ...] = ()
    choices: tuple[str, ...] = ()
    extra_choices: tuple[tuple[Version, tuple[str, ...]], ...] = ()
    default: Default = ""
    aliases: tuple[tuple[str, str], ...] = ()
    sim_only_until: Version | None = None
    allow_none: bool = False
    tree_since: Version | None = None
    model_defaults: tuple[tuple[Version, str, str], ...] = ()

    def available(self, stack: Stack) -> bool:
        v = stack.version
        return v >= self.since and (self.until is None or v <= self.until)

    def name_for(self, stack: Stack) -> str:
        name = self.key
        for version, renamed in self.names:
            if stack.version >= version:
                name = renamed
        return name

    def all_names(self) -> tuple[str, ...]:
        return (self.key, *(n for _, n in self.names))

    def choices_for(self, stack: Stack) -> tuple[str, ...]:
        out = list(self.choices)
        for version, extra in self.extra_choices:
            if stack.version >= version:
                out.extend(extra)
        return tuple(out)

    def default_for(self, stack: Stack, robot_model: str | None = None) -> str:
        """The default on ``stack``, on a robot of ``robot_model`` (None: not known, the
        model-independent default; panther_ros 2.0-2.1 have no model)."""
        for since, model, value in self.model_defaults:
            if robot_model == model and stack.version >= since:
                return value
        return self.default(stack) if callable(self.default) else self.default

    def model_dependent(self, stack: Stack) -> bool:
        """The default on ``stack`` depends on the robot's model."""
        return any(stack.version >= since for since, _, _ in self.model_defaults)

    def default_in_tree(self, stack: Stack) -> bool:
        """The stack reads this argument's default file under ``common_dir_path`` (the ~/config tree)."""
        return self.tree_since is not None and stack.version >= self.tree_since and self.available(stack)

    def availability(self) -> str:
        since = ".".join(map(str, self.since))
        if self.until is None:
            return f"{since}+"
        return f"{since}-{'.'.join(map(str, self.until))}"


def _v(text: str) -> Version:
    a, b, c = (int(p) for p in text.split("."))
    return (a, b, c)


def _ugv(stack: Stack) -> bool:
    return stack.family is Family.HUSARION_UGV


def _tree(pkg: str, rel: str) -> str:
    """A 2.2 default read under common_dir_path: ``PythonExpression([common_dir_path,
    "/husarion_ugv_<pkg>' if common_dir_path else", FindPackageShare(...)])`` joined with ``rel``."""
    return f"<common_dir_path>/husarion_ugv_{pkg}/{rel} (common_dir_path set; else $(find husarion_ugv_{pkg})/{rel})"


def _common(pkg: str, rel: str, tree_since: Version | None = (2, 2, 0)) -> Callable[[Stack], str]:
    """2.0-2.1: ``$(find panther_<pkg>)/rel``; 2.2: under common_dir_path from ``tree_since``
    (else, and before it, the package share ``$(find husarion_ugv_<pkg>)/rel``)."""

    def default(stack: Stack) -> str:
        if not _ugv(stack):
            return f"$(find panther_{pkg})/{rel}"
        if tree_since is not None and stack.version >= tree_since:
            return _tree(pkg, rel)
        return f"$(find husarion_ugv_{pkg})/{rel}"

    return default


def _shutdown_default(stack: Stack) -> str:
    if _ugv(stack):
        return _tree("manager", "config/shutdown_hosts.yaml")
    if stack.version >= (2, 1, 1):
        return "$(find panther_manager)/config/shutdown_hosts_config.yaml"
    return "$(find panther_bringup)/config/shutdown_hosts.yaml"


def _bt_default(kind: str, tree_since: Version | None) -> Callable[[Stack], str]:
    def default(stack: Stack) -> str:
        if _ugv(stack) and tree_since is not None and stack.version >= tree_since:
            return _tree("manager", f"behavior_trees/{kind}BT.btproj")
        if _ugv(stack):
            return f"$(find husarion_ugv_manager)/behavior_trees/{kind}BT.btproj"
        return f"$(find panther_manager)/behavior_trees/Panther{kind}BT.btproj"

    return default


def _battery_default(stack: Stack) -> str:
    return "$(find husarion_ugv_battery)/config/battery.yaml" if _ugv(stack) else ""


_V2_2 = _v("2.2.0")
_V2_2_2 = _v("2.2.2")


_BOOL = ArgType.BOOL


CATALOGUE: tuple[ArgSpec, ...] = (
    ArgSpec("namespace", ArgType.NAMESPACE, "ROS namespace of every node (default: env ROBOT_NAMESPACE or '')"),
    ArgSpec("use_sim", _BOOL, "run against the simulator instead of the hardware", default="False"),
    ArgSpec(
        "wheel_type",
        ArgType.CHOICE,
        "wheel set: WH01 off-road, WH02 mecanum, WH04 small pneumatic, WH05 Lynx (2.2), custom",
        choices=("WH01", "WH02", "WH04", "custom"),
        extra_choices=((_V2_2, ("WH05",)),),
        default="WH01",
        # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/controller.launch.py and
        # husarion_ugv_description/launch/load_urdf.launch.py: default_wheel_type = {"lynx": "WH05",
        # "panther": "WH01"}, indexed by robot_model
        model_defaults=((_V2_2, "lynx", "WH05"),),
    ),
    # always the image's: panther_ros@2.0.4, @2.1.1:panther_controller/launch/controller.launch.py;
    # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/controller.launch.py (description_pkg)
    ArgSpec(
        "wheel_config_path",
        ArgType.PATH,
        "wheel description YAML (needed with wheel_type custom)",
        default=_common("description", "config/{wheel_type}.yaml", tree_since=None),
    ),
    # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/controller.launch.py
    # (husarion_ugv_controller_common_dir)
    ArgSpec(
        "controller_config_path",
        ArgType.PATH,
        "ros2_control controller YAML: velocity/acceleration limits (needed with wheel_type custom)",
        default=_common("controller", "config/{wheel_type}_controller.yaml"),
        tree_since=_V2_2,
    ),
    # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/launch/controller.launch.py (description_common_dir)
    ArgSpec(
        "components_config_path",
        ArgType.PATH,
        "components (sensors, ANT02...) added to the URDF; None disables",
        since=_v("2.0.2"),
        default=_common("description", "config/components.yaml"),
        allow_none=True,
        tree_since=_V2_2,
    ),
    ArgSpec(
        "battery_config_path",
        ArgType.PATH,
        "2.0-2.1: Gazebo LinearBatteryPlugin config (simulation only); 2.2: ADC battery driver params",
        default=_battery_default,
        sim_only_until=_v("2.1.2"),
    ),
    # panther_ros@2.0.4, @2.1.1:panther_lights/launch/lights.launch.py; husarion_ugv_ros@2.2.0 (and 2.2.1):
    # husarion_ugv_lights/launch/lights.launch.py reads it from the image (husarion_ugv_lights_pkg),
    # husarion_ugv_ros@2.2.2: from common_dir_path (husarion_ugv_lights_common_dir)
    ArgSpec(
        "led_config_file",
        ArgType.PATH,
        "LED panels, segments and default animations (2.2: animations_config_path)",
        names=((_V2_2, "animations_config_path"),),
        default=lambda s: (
            _common("lights", "config/{robot_model}_animations.yaml", tree_since=_V2_2_2)(s)
            if _ugv(s)
            else "$(find panther_lights)/config/led_config.yaml"
        ),
        tree_since=_V2_2_2,
    ),
    # panther_ros@2.0.4, @2.1.1:panther_lights/launch/lights.launch.py (""); husarion_ugv_ros@2.2.0, @2.2.2:
    # husarion_ugv_lights/launch/lights.launch.py (husarion_ugv_lights_common_dir)
    ArgSpec(
        "user_led_animations_file",
        ArgType.PATH,
        "user LED animations YAML (top key user_animations; 2.2: user_led_animations_path)",
        names=((_V2_2, "user_led_animations_path"),),
        default=lambda s: _tree("lights", "config/user_animations.yaml") if _ugv(s) else "",
        tree_since=_V2_2,
        aliases=(
            (
                "user_animations_file",
                "the manual's `user_animations_file` is not a declared launch argument "
                "(ros2 launch would ignore it); using the real one",
            ),
        ),
    ),
    ArgSpec(
        "simulation_engine",
        ArgType.STRING,
        "simulator (2.0.0-2.0.1 bringup only)",
        until=_v("2.0.1"),
        default="ignition-gazebo",
        sim_only_until=_v("2.0.1"),
    ),
    ArgSpec("publish_robot_state", _BOOL, "publish the robot description and TF", default="True"),
    # panther_ros@2.0.4, @2.1.1:panther_bringup/launch/bringup.launch.py; husarion_ugv_ros@2.2.0, @2.2.2:
    # husarion_ugv_localization/launch/localization.launch.py (included by bringup): default "True"
    ArgSpec("use_ekf", _BOOL, "fuse wheel odometry and IMU with the EKF", default="True"),
    ArgSpec(
        "ekf_config_path",
        ArgType.PATH,
        "robot_localization EKF params (2.0.0-2.0.1; later: localization_config_path)",
        until=_v("2.0.1"),
        default="$(find panther_bringup)/config/ekf.yaml",
    ),
    # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_manager/launch/manager.launch.py (husarion_ugv_manager_common_dir)
    ArgSpec(
        "shutdown_hosts_config_path",
        ArgType.PATH,
        "hosts (User Computer...) shut down with the robot",
        default=_shutdown_default,
        tree_since=_V2_2,
    ),
    ArgSpec("disable_manager", _BOOL, "do not start the lights/safety managers", since=_v("2.0.1"), default="False"),
    # panther_ros@2.0.4:panther_manager/launch/manager_bt.launch.py, @2.1.1:panther_manager/launch/manager.launch.py;
    # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_manager/launch/manager.launch.py: lights from common_dir_path
    # (husarion_ugv_manager_common_dir), safety from the image (husarion_ugv_manager_pkg)
    ArgSpec(
        "lights_bt_project_path",
        ArgType.PATH,
        "Groot2 project of the lights behavior tree",
        since=_v("2.0.2"),
        default=_bt_default("Lights", _V2_2),
        tree_since=_V2_2,
    ),
    ArgSpec(
        "safety_bt_project_path",
        ArgType.PATH,
        "Groot2 project of the safety/shutdown behavior trees (robot version >= 1.2)",
        since=_v("2.0.2"),
        default=_bt_default("Safety", None),
    ),
    ArgSpec("fuse_gps", _BOOL, "fuse GPS (gps/fix) in the localization", since=_v("2.0.2"), default="False"),
    ArgSpec(
        "localization_mode",
        ArgType.CHOICE,
        "relative (odom frame) or enu (East-North-Up, needs GPS)",
        since=_v("2.0.2"),
        choices=("relative", "enu"),
        default="relative",
    ),
    # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_localization/launch/localization.launch.py
    # (husarion_ugv_localization_common_dir)
    ArgSpec(
        "localization_config_path",
        ArgType.PATH,
        "robot_localization params",
        since=_v("2.0.2"),
        default=_common("localization", "config/{localization_mode}_localization[_with_gps].yaml"),
        tree_since=_V2_2,
    ),
    ArgSpec(
        "launch_nmea_gps",
        _BOOL,
        "run the built-in NMEA GPS driver (ANT02 via the router, 10.15.20.2:5000) -> <ns>/gps/fix",
        since=_v("2.1.1"),
        default="False",
    ),
    ArgSpec(
        "common_dir_path",
        ArgType.DIR,
        "directory holding <package>/config/... for every package (compose: /config)",
        since=_V2_2,
    ),
    ArgSpec("exit_on_wrong_hw", _BOOL, "stop when the hardware does not match", since=_V2_2, default="false"),
    ArgSpec(
        "log_level",
        ArgType.CHOICE,
        "ROS log level",
        since=_V2_2,
        choices=("DEBUG", "INFO", "WARNING", "ERROR", "FATAL"),
        default="INFO",
    ),
    # since 2.2.2: husarion_ugv_bringup CHANGELOG 2.2.2 "Add joy2twist dependency (#581)" (see robot/gamepad.py)
    ArgSpec("launch_gamepad", _BOOL, "start the gamepad (joy2twist) nodes", since=_v("2.2.2"), default="false"),
    ArgSpec(
        "robot_model",
        ArgType.CHOICE,
        "robot model (default: env ROBOT_MODEL_NAME or panther)",
        since=_V2_2,
        choices=("panther", "lynx"),
        default="panther",
    ),
    # declared by the NMEA launch file that localization includes when launch_nmea_gps is true:
    # panther_ros@2.1.1:panther_localization/launch/nmea_navsat.launch.py (params_file, device_namespace);
    # husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_localization/launch/nmea_navsat.launch.py (nmea_params_path,
    # the image's file; the device namespace is fixed to gps)
    ArgSpec(
        "params_file",
        ArgType.PATH,
        "NMEA GPS driver params (used with launch_nmea_gps; 2.2: nmea_params_path)",
        since=_v("2.1.1"),
        names=((_V2_2, "nmea_params_path"),),
        default=lambda s: (
            "$(find husarion_ugv_localization)/config/nmea_navsat.yaml"
            if _ugv(s)
            else "$(find panther_localization)/config/nmea_navsat_params.yaml"
        ),
    ),
    ArgSpec(
        "device_namespace",
        ArgType.NAMESPACE,
        "namespace of the NMEA GPS driver's topics and frame (used with launch_nmea_gps): <ns>/<it>/fix",
        since=_v("2.1.1"),
        until=_v("2.1.2"),
        default="gps",
    ),
    # the image's: husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_diagnostics/launch/system_monitor.launch.py
    # (FindPackageShare; bringup does not pass common_dir_path to it)
    ArgSpec(
        "system_monitor_config_path",
        ArgType.PATH,
        "system monitor params",
        since=_V2_2,
        default=_common("diagnostics", "config/system_monitor.yaml", tree_since=None),
    ),
)


_BY_KEY: dict[str, ArgSpec] = {spec.key: spec for spec in CATALOGUE}


_BY_NAME: dict[str, ArgSpec] = {}


_ALIAS_NOTES: dict[str, tuple[ArgSpec, str]] = {}
for _spec in CATALOGUE:
    for _name in _spec.all_names():
        _BY_NAME[_name] = _spec
    for _alias, _note in _spec.aliases:
        _ALIAS_NOTES[_alias] = (_spec, _note)


def catalogue_key(name: str) -> str | None:
    """The catalogue key of an argument's name, a per-version name or an alias (None: not in
    the catalogue): two names with one key are one argument."""
    found = _BY_NAME.get(name) or (_ALIAS_NOTES[name][0] if name in _ALIAS_NOTES else None)
    return found.key if found is not None else None


_ARG_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$", re.ASCII)


def arg_text_problem(key: str, value: str) -> tuple[str, str] | None:
    """Why ``key:=value`` can never be written into the driver's command, ``--force`` or not,
    and what is allowed (None: it can be): a name that is not a launch argument name, a value
    holding a newline or another control character (it would split or corrupt the
    ``command:`` line of compose.yaml)."""
    if not _ARG_NAME.match(key.removeprefix("launch_args.")):
        return (f"launch argument name {key!r} is not allowed",
                "letters, digits and '_', starting with a letter or '_'")
    bad = next((c for c in value if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp")), None)
    if bad is not None:
        return (f"{key}: the value {value!r} holds the control character {bad!r} (U+{ord(bad):04X})",
                "a launch argument value is one line of printable text")
    return None
