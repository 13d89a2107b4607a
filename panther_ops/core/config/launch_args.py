"""Catalogue of the driver's launch arguments per stack version, with validation.

Facts: panther-stack.md section 1.1 (bringup.launch.py and the per-package launch files of
panther_ros 2.0.0-2.1.x and husarion_ugv_ros 2.2.x, Humble).

Each argument has a catalogue key (its panther_ros 2.0/2.1 name, or its own name when it
only exists on 2.2) and, per version, the name the stack declares:
``led_config_file`` is ``animations_config_path`` on 2.2 and ``user_led_animations_file`` is
``user_led_animations_path``. Any of those names is accepted as input; the manual's
``user_animations_file`` (never a declared argument) is accepted as an alias with a note.

`validate_arg` checks one value (type, allowed values, availability on the robot's
version) and returns the name and the normalised value to write; `check_args` runs the
cross-argument rules (`RULES`) over a whole command; `set_launch_args` does both and edits
a `ComposeFile`.
"""

from __future__ import annotations

import difflib
import re
import unicodedata
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING

from panther_ops.core.fleet.stack import Family, Stack
from panther_ops.errors import UsageError

if TYPE_CHECKING:  # validating a value needs no YAML editor (ruamel loads when a compose file is edited)
    from panther_ops.core.config.compose import ComposeFile, Volume

Version = tuple[int, int, int]


class LaunchArgError(UsageError):
    """A launch argument or value that the robot's stack does not accept."""


class UnknownArgError(LaunchArgError):
    """No such launch argument in the catalogue."""


class UnavailableArgError(LaunchArgError):
    """The argument exists, but not on the robot's stack version."""


class InvalidArgValueError(LaunchArgError):
    """The value is not allowed for the argument (the message lists what is)."""


class ArgConflictError(LaunchArgError):
    """A combination of arguments that cannot work (cross-argument rule)."""


class ArgType(str, Enum):
    BOOL = "bool"
    CHOICE = "choice"
    PATH = "path"
    DIR = "dir"
    NAMESPACE = "namespace"
    STRING = "string"


Default = str | Callable[[Stack], str]


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

    def default_for(self, stack: Stack) -> str:
        return self.default(stack) if callable(self.default) else self.default

    def availability(self) -> str:
        since = ".".join(map(str, self.since))
        if self.until is None:
            return f"{since}+"
        return f"{since}-{'.'.join(map(str, self.until))}"


@dataclass(frozen=True)
class ValidatedArg:
    """A launch argument ready to be written.

    Attributes:
        key: catalogue key.
        name: the name to write on this stack (``animations_config_path`` on 2.2).
        value: the normalised value (booleans as the stack spells them).
        warnings: things the operator should know (forced values, aliases, sim-only).
    """

    key: str
    name: str
    value: str
    warnings: tuple[str, ...] = ()
    spec: ArgSpec | None = field(default=None, compare=False, repr=False)


def _v(text: str) -> Version:
    a, b, c = (int(p) for p in text.split("."))
    return (a, b, c)


def _ugv(stack: Stack) -> bool:
    return stack.family is Family.HUSARION_UGV


def _common(pkg: str, rel: str) -> Callable[[Stack], str]:
    """2.0-2.1: ``$(find panther_<pkg>)/rel``; 2.2: under common_dir_path or the package share."""

    def default(stack: Stack) -> str:
        if _ugv(stack):
            return f"<common_dir_path or $(find husarion_ugv_{pkg})>/husarion_ugv_{pkg}/{rel}"
        return f"$(find panther_{pkg})/{rel}"

    return default


def _shutdown_default(stack: Stack) -> str:
    if _ugv(stack):
        return "<common_dir_path or $(find husarion_ugv_manager)>/husarion_ugv_manager/config/shutdown_hosts.yaml"
    if stack.version >= (2, 1, 1):
        return "$(find panther_manager)/config/shutdown_hosts_config.yaml"
    return "$(find panther_bringup)/config/shutdown_hosts.yaml"


def _bt_default(kind: str) -> Callable[[Stack], str]:
    def default(stack: Stack) -> str:
        if _ugv(stack):
            return f"$(find husarion_ugv_manager)/behavior_trees/{kind}BT.btproj"
        return f"$(find panther_manager)/behavior_trees/Panther{kind}BT.btproj"

    return default


def _battery_default(stack: Stack) -> str:
    return "$(find husarion_ugv_battery)/config/battery.yaml" if _ugv(stack) else ""


_V2_2 = _v("2.2.0")
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
    ),
    ArgSpec(
        "wheel_config_path",
        ArgType.PATH,
        "wheel description YAML (needed with wheel_type custom)",
        default=_common("description", "config/{wheel_type}.yaml"),
    ),
    ArgSpec(
        "controller_config_path",
        ArgType.PATH,
        "ros2_control controller YAML: velocity/acceleration limits (needed with wheel_type custom)",
        default=_common("controller", "config/{wheel_type}_controller.yaml"),
    ),
    ArgSpec(
        "components_config_path",
        ArgType.PATH,
        "components (sensors, ANT02...) added to the URDF; None disables",
        since=_v("2.0.2"),
        default=_common("description", "config/components.yaml"),
        allow_none=True,
    ),
    ArgSpec(
        "battery_config_path",
        ArgType.PATH,
        "2.0-2.1: Gazebo LinearBatteryPlugin config (simulation only); 2.2: ADC battery driver params",
        default=_battery_default,
        sim_only_until=_v("2.1.2"),
    ),
    ArgSpec(
        "led_config_file",
        ArgType.PATH,
        "LED panels, segments and default animations (2.2: animations_config_path)",
        names=((_V2_2, "animations_config_path"),),
        default=lambda s: (
            "<common_dir_path or $(find husarion_ugv_lights)>/husarion_ugv_lights/config/{robot_model}_animations.yaml"
            if _ugv(s)
            else "$(find panther_lights)/config/led_config.yaml"
        ),
    ),
    ArgSpec(
        "user_led_animations_file",
        ArgType.PATH,
        "user LED animations YAML (top key user_animations; 2.2: user_led_animations_path)",
        names=((_V2_2, "user_led_animations_path"),),
        default=lambda s: (
            "<common_dir_path or $(find husarion_ugv_lights)>/husarion_ugv_lights/config/user_animations.yaml"
            if _ugv(s)
            else ""
        ),
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
    ArgSpec("use_ekf", _BOOL, "fuse wheel odometry and IMU with the EKF", default="True"),
    ArgSpec(
        "ekf_config_path",
        ArgType.PATH,
        "robot_localization EKF params (2.0.0-2.0.1; later: localization_config_path)",
        until=_v("2.0.1"),
        default="$(find panther_bringup)/config/ekf.yaml",
    ),
    ArgSpec(
        "shutdown_hosts_config_path",
        ArgType.PATH,
        "hosts (User Computer...) shut down with the robot",
        default=_shutdown_default,
    ),
    ArgSpec("disable_manager", _BOOL, "do not start the lights/safety managers", since=_v("2.0.1"), default="False"),
    ArgSpec(
        "lights_bt_project_path",
        ArgType.PATH,
        "Groot2 project of the lights behavior tree",
        since=_v("2.0.2"),
        default=_bt_default("Lights"),
    ),
    ArgSpec(
        "safety_bt_project_path",
        ArgType.PATH,
        "Groot2 project of the safety/shutdown behavior trees (robot version >= 1.2)",
        since=_v("2.0.2"),
        default=_bt_default("Safety"),
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
    ArgSpec(
        "localization_config_path",
        ArgType.PATH,
        "robot_localization params",
        since=_v("2.0.2"),
        default=_common("localization", "config/{localization_mode}_localization[_with_gps].yaml"),
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
    ArgSpec("launch_gamepad", _BOOL, "start the gamepad (joy2twist) nodes", since=_V2_2, default="false"),
    ArgSpec(
        "robot_model",
        ArgType.CHOICE,
        "robot model (default: env ROBOT_MODEL_NAME or panther)",
        since=_V2_2,
        choices=("panther", "lynx"),
        default="panther",
    ),
    ArgSpec(
        "nmea_params_path",
        ArgType.PATH,
        "NMEA GPS driver params (nmea_navsat.yaml)",
        since=_V2_2,
        default="$(find husarion_ugv_localization)/config/nmea_navsat.yaml",
    ),
    ArgSpec(
        "system_monitor_config_path",
        ArgType.PATH,
        "system monitor params",
        since=_V2_2,
        default=_common("diagnostics", "config/system_monitor.yaml"),
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

_TRUE = frozenset({"true", "1"})
_FALSE = frozenset({"false", "0"})
_NS_TOKEN = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_INTERPOLATION = re.compile(r"\$\{[^}]*\}|\$[A-Za-z_][A-Za-z0-9_]*")


def spec(key: str) -> ArgSpec:
    """The catalogue entry for a key, a per-version name or an alias.

    Raises:
        UnknownArgError: not in the catalogue (the message suggests close names).
    """
    found = _BY_NAME.get(key) or (_ALIAS_NOTES[key][0] if key in _ALIAS_NOTES else None)
    if found is None:
        names = sorted({*_BY_NAME, *_ALIAS_NOTES})
        close = difflib.get_close_matches(key, names, n=3)
        hint = f"did you mean {', '.join(close)}?" if close else "see docs/configuration.md for the table"
        raise UnknownArgError(f"unknown launch argument {key!r}", hint=hint)
    return found


def args_for(stack: Stack) -> list[ArgSpec]:
    """Arguments the stack declares."""
    return [s for s in CATALOGUE if s.available(stack)]


def bool_word(stack: Stack, value: bool) -> str:
    """``True``/``False`` on panther_ros 2.0-2.1 (some args only accept these), ``true``/``false`` on 2.2."""
    word = "true" if value else "false"
    return word if _ugv(stack) else word.capitalize()


def _since_text(s: ArgSpec, stack: Stack) -> str:
    family = "husarion_ugv" if s.since >= _V2_2 else "panther_ros"
    return f"{s.key} needs {family} {s.availability()}; this robot runs {stack.label()}"


_ARG_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def check_arg_text(key: str, value: str) -> None:
    """Refuse what can never be written into the driver's command, ``--force`` or not: a
    name that is not a launch argument name, a value holding a newline or another control
    character (it would split or corrupt the ``command:`` line of compose.yaml).

    Raises:
        InvalidArgValueError: naming the argument and the offending character.
    """
    if not _ARG_NAME.match(key.removeprefix("launch_args.")):
        raise InvalidArgValueError(f"launch argument name {key!r} is not allowed",
                                   hint="letters, digits and '_', starting with a letter or '_'")
    bad = next((c for c in value if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp")), None)
    if bad is not None:
        raise InvalidArgValueError(
            f"{key}: the value {value!r} holds the control character {bad!r} (U+{ord(bad):04X})",
            hint="a launch argument value is one line of printable text",
        )


def validate_arg(
    stack: Stack,
    key: str,
    value: str,
    *,
    force: bool = False,
    context: Mapping[str, str] | None = None,
    simulation: bool = False,
) -> ValidatedArg:
    """Check one launch argument for the robot's stack and normalise its value.

    Args:
        stack: the robot's stack.
        key: catalogue key, the per-version name or an accepted alias.
        value: the value as typed (``true``, ``WH02``, ``/config/x.yaml``...).
        force: turn refusals into warnings (unknown names, values out of the choices,
            unavailable on this version). Malformed values (empty choice...) still pass.
        context: the other arguments of the command (for WH05 vs robot_model).
        simulation: the command runs in simulation (sim-only args are then fine).

    Returns:
        The name to write on this stack and the normalised value.

    Raises:
        UnknownArgError, UnavailableArgError, InvalidArgValueError: unless ``force``.
    """
    warnings: list[str] = []
    value = value.strip()
    check_arg_text(key, value)
    try:
        s = spec(key)
    except UnknownArgError:
        if not force:
            raise
        return ValidatedArg(key, key, value, (f"{key} is not in the catalogue; written as given (forced)",))
    if key in _ALIAS_NOTES:
        warnings.append(_ALIAS_NOTES[key][1] + f": {s.name_for(stack)}")
    name = s.name_for(stack)
    if key not in _ALIAS_NOTES and key != name:
        warnings.append(f"on {stack.label()} the argument is called {name}")
    if not s.available(stack):
        if not force:
            raise UnavailableArgError(_since_text(s, stack), hint=_replacement_hint(s, stack))
        warnings.append(_since_text(s, stack) + " (forced)")
    normalised = _normalise(s, stack, value, force=force, warnings=warnings)
    if s.sim_only_until is not None and stack.version <= s.sim_only_until and not simulation and normalised:
        warnings.append(
            f"{name} only matters in simulation on {stack.label()} (Gazebo battery plugin); the robot ignores it"
        )
    if s.key == "wheel_type" and normalised == "WH05":
        model = (context or {}).get("robot_model", "panther")
        if model != "lynx":
            message = (
                f"WH05 is the Lynx wheel; this robot's robot_model is {model}"
                + (" (the default)" if "robot_model" not in (context or {}) else "")
            )
            if not force:
                raise InvalidArgValueError(
                    message,
                    hint="Panther wheels: WH01 (off-road), WH02 (mecanum), WH04 (small pneumatic), custom; "
                    "on a Lynx set robot_model:=lynx",
                )
            warnings.append(message + " (forced)")
    return ValidatedArg(s.key, name, normalised, tuple(warnings), s)


def _replacement_hint(s: ArgSpec, stack: Stack) -> str | None:
    if s.key == "ekf_config_path":
        return "from 2.0.2 use localization_config_path"
    if s.key == "simulation_engine":
        return "from 2.0.2 the simulator is chosen by the simulation launch files"
    if s.key == "launch_nmea_gps":
        return (f"on {stack.label()} the GPS runs as its own compose service (nmea-gps, from the manual), "
                "not a launch argument: panther-ops gps enable")
    if s.key == "launch_gamepad":
        return (f"on {stack.label()} the gamepad runs as its own compose service (gamepad_controller, "
                "husarion/joy2twist), not a launch argument: start or stop that service in compose.yaml")
    return None


def _normalise(s: ArgSpec, stack: Stack, value: str, *, force: bool, warnings: list[str]) -> str:
    name = s.name_for(stack)
    if _INTERPOLATION.search(value) and s.type is not ArgType.PATH:
        warnings.append(f"{name}={value!r} uses compose interpolation; not checked")
        return value
    if s.type is ArgType.BOOL:
        low = value.lower()
        if low in _TRUE:
            return bool_word(stack, True)
        if low in _FALSE:
            return bool_word(stack, False)
        return _refuse(name, value, (bool_word(stack, True), bool_word(stack, False)), force, warnings)
    if s.type is ArgType.CHOICE:
        choices = s.choices_for(stack)
        for choice in choices:
            if value == choice or value.lower() == choice.lower():
                return choice
        return _refuse(name, value, choices, force, warnings)
    if s.type is ArgType.NAMESPACE:
        tokens = value.strip("/").split("/") if value.strip("/") else []
        trailing = value.endswith("/") and value != "/"
        if value and (trailing or not all(_NS_TOKEN.match(t) for t in tokens)):
            allowed = ("a ROS namespace: letters, digits, _ and /, not starting with a digit",)
            return _refuse(name, value, allowed, force, warnings, kind="a valid namespace")
        return value
    if s.type in (ArgType.PATH, ArgType.DIR):
        return _check_path(s, name, value, force, warnings)
    return value


def _check_path(s: ArgSpec, name: str, value: str, force: bool, warnings: list[str]) -> str:
    if value == "" or (s.allow_none and value == "None"):
        return value
    ok = bool(value.startswith(("/", "$(find ", "$(find-pkg-share ", "${")) or _INTERPOLATION.match(value))
    if ok and value.startswith("$(") and ")" not in value:
        ok = False
    if ok:
        return value
    allowed: tuple[str, ...] = ("an absolute path inside the container (e.g. /config/...)", "$(find <package>)/...")
    if s.type is ArgType.DIR:
        allowed = ("an absolute directory inside the container (e.g. /config)", "''")
    if s.allow_none:
        allowed = (*allowed, "None")
    return _refuse(name, value, allowed, force, warnings, kind="a path launch can open")


def _refuse(
    name: str,
    value: str,
    allowed: Iterable[str],
    force: bool,
    warnings: list[str],
    *,
    kind: str = "an allowed value",
) -> str:
    listing = ", ".join(allowed)
    message = f"{name}={value!r} is not {kind}; allowed: {listing}"
    if not force:
        raise InvalidArgValueError(message)
    warnings.append(message + " (forced)")
    return value


# ------------------------------------------------------------ cross rules


@dataclass(frozen=True)
class Finding:
    """The outcome of a cross-argument rule: ``error`` refuses (unless forced), ``warning`` informs."""

    level: str
    rule: str
    message: str
    keys: tuple[str, ...] = ()


@dataclass(frozen=True)
class ArgRule:
    """A check over the whole set of launch arguments (by catalogue key)."""

    name: str
    description: str
    check: Callable[[Stack, Mapping[str, str], Sequence[Volume] | None, bool], list[Finding]]


def _truthy(value: str | None) -> bool:
    return (value or "").lower() in _TRUE


def _rule_custom(stack: Stack, args: Mapping[str, str], _v: Sequence[Volume] | None, _s: bool) -> list[Finding]:
    if args.get("wheel_type") != "custom":
        return []
    missing = [k for k in ("wheel_config_path", "controller_config_path") if not args.get(k)]
    if not missing:
        return []
    return [
        Finding(
            "error",
            "custom-wheels",
            "wheel_type custom needs both wheel_config_path and controller_config_path "
            f"(missing: {', '.join(missing)}); base them on WH01.yaml and WH01_controller.yaml",
            ("wheel_type", *missing),
        )
    ]


def _rule_wh05(stack: Stack, args: Mapping[str, str], _v: Sequence[Volume] | None, _s: bool) -> list[Finding]:
    if args.get("wheel_type") != "WH05" or args.get("robot_model", "panther") == "lynx":
        return []
    return [
        Finding(
            "error",
            "wh05-lynx",
            f"wheel_type WH05 is the Lynx wheel but robot_model is {args.get('robot_model', 'panther')}",
            ("wheel_type", "robot_model"),
        )
    ]


def _rule_battery(stack: Stack, args: Mapping[str, str], _v: Sequence[Volume] | None, sim: bool) -> list[Finding]:
    if _ugv(stack) or sim or _truthy(args.get("use_sim")) or not args.get("battery_config_path"):
        return []
    return [
        Finding(
            "warning",
            "battery-sim-only",
            f"battery_config_path only configures the Gazebo battery plugin on {stack.label()}; "
            "the real robot ignores it",
            ("battery_config_path",),
        )
    ]


def _rule_gps(stack: Stack, args: Mapping[str, str], _v: Sequence[Volume] | None, _s: bool) -> list[Finding]:
    if not _truthy(args.get("fuse_gps")) or _truthy(args.get("launch_nmea_gps")):
        return []
    how = "launch_nmea_gps:=True or " if stack.version >= (2, 1, 1) else ""
    return [
        Finding(
            "warning",
            "gps-source",
            f"fuse_gps needs a GPS fix on <namespace>/gps/fix: {how}a GPS driver container",
            ("fuse_gps",),
        )
    ]


def _rule_enu(stack: Stack, args: Mapping[str, str], _v: Sequence[Volume] | None, _s: bool) -> list[Finding]:
    if args.get("localization_mode") != "enu" or _truthy(args.get("fuse_gps")):
        return []
    return [
        Finding(
            "warning",
            "enu-without-gps",
            "localization_mode enu without fuse_gps: the ENU frame is anchored by the IMU heading only",
            ("localization_mode", "fuse_gps"),
        )
    ]


def _rule_mounted(stack: Stack, args: Mapping[str, str], volumes: Sequence[Volume] | None, _s: bool) -> list[Finding]:
    if volumes is None:
        return []
    targets = [v.target.rstrip("/") for v in volumes]
    out: list[Finding] = []
    for key, value in args.items():
        s = _BY_KEY.get(key)
        if s is None or s.type not in (ArgType.PATH, ArgType.DIR) or not value.startswith("/"):
            continue
        if not any(value == t or value.startswith(t + "/") for t in targets if t):
            out.append(
                Finding(
                    "warning",
                    "path-mounted",
                    f"{key}={value} is not inside any volume of the driver container; "
                    "the file must exist in the image or be mounted",
                    (key,),
                )
            )
    return out


RULES: tuple[ArgRule, ...] = (
    ArgRule("custom-wheels", "wheel_type custom needs wheel_config_path and controller_config_path", _rule_custom),
    ArgRule("wh05-lynx", "WH05 wheels only with robot_model lynx", _rule_wh05),
    ArgRule("battery-sim-only", "battery_config_path is simulation-only up to 2.1", _rule_battery),
    ArgRule("gps-source", "fuse_gps needs a GPS source", _rule_gps),
    ArgRule("enu-without-gps", "localization_mode enu is meant with GPS", _rule_enu),
    ArgRule("path-mounted", "absolute config paths should be inside a mounted volume", _rule_mounted),
)


def canonical_args(stack: Stack, args: Mapping[str, str]) -> dict[str, str]:
    """Command args keyed by catalogue key (unknown names kept as they are)."""
    out: dict[str, str] = {}
    for name, value in args.items():
        s = _BY_NAME.get(name) or (_ALIAS_NOTES[name][0] if name in _ALIAS_NOTES else None)
        out[s.key if s else name] = value
    return out


def check_args(
    stack: Stack,
    args: Mapping[str, str],
    *,
    volumes: Sequence[Volume] | None = None,
    simulation: bool = False,
) -> list[Finding]:
    """Run every rule over a command's arguments (names as written in the command).

    Also reports names the stack does not declare: an unknown name is a warning (ros2 launch
    ignores it silently); a name of another version (``led_config_file`` on 2.2) or an alias
    (``user_animations_file``) is an error because the setting would silently not apply.
    """
    findings: list[Finding] = []
    for name in args:
        s = _BY_NAME.get(name)
        if name in _ALIAS_NOTES:
            real = _ALIAS_NOTES[name][0].name_for(stack)
            findings.append(Finding("error", "declared-name", f"{name} is not a launch argument: use {real}", (name,)))
        elif s is None:
            findings.append(
                Finding(
                    "warning",
                    "unknown-arg",
                    f"{name} is not an argument of {stack.label()}; ros2 launch ignores it",
                    (name,),
                )
            )
        elif not s.available(stack):
            findings.append(Finding("error", "unavailable-arg", _since_text(s, stack), (name,)))
        elif s.name_for(stack) != name:
            findings.append(
                Finding(
                    "error",
                    "declared-name",
                    f"{name} is called {s.name_for(stack)} on {stack.label()}; as written it is ignored",
                    (name,),
                )
            )
    keyed = canonical_args(stack, args)
    for rule in RULES:
        findings.extend(rule.check(stack, keyed, volumes, simulation))
    return findings


def raise_for_errors(findings: Sequence[Finding], *, force: bool = False) -> list[str]:
    """Raise `ArgConflictError` for error findings (unless ``force``); return the warning texts."""
    errors = [f for f in findings if f.level == "error"]
    if errors and not force:
        raise ArgConflictError(
            "; ".join(f.message for f in errors), hint="fix the arguments, or --force to write them anyway"
        )
    return [f.message + (" (forced)" if f.level == "error" else "") for f in findings]


# ------------------------------------------------------------ migration


@dataclass(frozen=True)
class ArgMigration:
    """What moving a command from one stack to another does to its arguments."""

    renamed: dict[str, str]
    dropped: tuple[str, ...]


def migrate_args(source: Stack, target: Stack, args: Mapping[str, str]) -> ArgMigration:
    """Names to rename and args to drop when the driver image changes version.

    ``led_config_file`` -> ``animations_config_path`` (2.1 -> 2.2), ``ekf_config_path`` dropped
    (2.0.1 -> 2.0.2), the manual alias ``user_animations_file`` -> the declared name.
    """
    renamed: dict[str, str] = {}
    dropped: list[str] = []
    for name in args:
        s = _BY_NAME.get(name) or (_ALIAS_NOTES[name][0] if name in _ALIAS_NOTES else None)
        if s is None:
            continue
        if not s.available(target):
            dropped.append(name)
        elif s.name_for(target) != name:
            renamed[name] = s.name_for(target)
    return ArgMigration(renamed, tuple(dropped))


# ------------------------------------------------------------ compose edits


@dataclass(frozen=True)
class ArgChange:
    """Result of `set_launch_args` / `unset_launch_arg`."""

    changed: bool
    args: tuple[ValidatedArg, ...]
    warnings: tuple[str, ...]


_SAID_BY_THE_ARG = {"battery-sim-only": "battery_config_path"}
"""Cross rules whose warning the argument's own check (``validate_arg``) already gives."""


def set_launch_args(
    compose: ComposeFile,
    values: Mapping[str, str],
    *,
    force: bool = False,
    service: str | None = None,
) -> ArgChange:
    """Validate and write launch arguments into the driver command of ``compose``.

    Each value is validated for the driver's stack (`validate_arg`), then the cross rules
    run over the resulting command; errors refuse the whole change (nothing written)
    unless ``force``. Names of other versions or aliases already in the command for the
    same argument are replaced by the declared name.

    Raises:
        LaunchArgError: a refused argument, value or combination.
    """
    stack = compose.stack()
    cmd = compose.command(service)
    current = dict(cmd.args)
    validated: list[ValidatedArg] = []
    warnings: list[str] = []
    prospective = dict(current)
    stale: list[str] = []
    for key, value in values.items():
        va = validate_arg(stack, key, value, force=force, context=canonical_args(stack, prospective))
        validated.append(va)
        warnings.extend(va.warnings)
        if va.spec is not None:
            for other in (*va.spec.all_names(), *(a for a, _ in va.spec.aliases)):
                if other != va.name and other in prospective:
                    stale.append(other)
                    prospective.pop(other)
                    warnings.append(f"replaced {other} (not declared on {stack.label()}) by {va.name}")
        prospective[va.name] = va.value
    volumes = compose.list_volumes(service)
    said = {v.name for v in validated if v.warnings}  # a rule that says it again in other words is left out
    findings = [
        f for f in check_args(stack, prospective, volumes=volumes) if (set(f.keys) & {v.name for v in validated}
        or f.level == "error") and not (f.rule in _SAID_BY_THE_ARG and _SAID_BY_THE_ARG[f.rule] in said)
    ]
    warnings.extend(raise_for_errors(findings, force=force))
    changed = False
    for name in stale:
        changed = compose.unset_arg(name, service) or changed
    for va in validated:
        changed = compose.set_arg(va.name, va.value, service) or changed
    return ArgChange(changed, tuple(validated), tuple(dict.fromkeys(warnings)))


def unset_launch_arg(compose: ComposeFile, key: str, *, service: str | None = None) -> ArgChange:
    """Remove an argument (every name it has had, and its aliases) from the command.

    The stack's default applies afterwards. Unknown keys are removed as written.
    """
    try:
        s: ArgSpec | None = spec(key)
    except UnknownArgError:
        s = None
    names = (key,) if s is None else (*s.all_names(), *(a for a, _ in s.aliases))
    changed = False
    for name in names:
        changed = compose.unset_arg(name, service) or changed
    return ArgChange(changed, (), ())
