"""Rules across the launch arguments of one command: custom wheels, WH05, battery in
simulation, GPS, ENU localization, mounted files (a path no volume mounts and not in the image
is an error)."""

from __future__ import annotations

import posixpath
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from panther_ops.core.kinds.arg_catalogue import _ALIAS_NOTES, _BY_KEY, _BY_NAME, IMAGE_PREFIXES, ArgType, _ugv
from panther_ops.core.robot.launch_args.catalogue import _TRUE, ArgConflictError, unavailable_text
from panther_ops.core.stack import Stack

if TYPE_CHECKING:
    from panther_ops.core.robot.compose import Volume


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
    model = args.get("robot_model")
    if args.get("wheel_type") != "WH05" or model == "lynx":
        return []
    if model is None:  # neither robot_model:= nor the robot's ROBOT_MODEL_NAME known here
        return [Finding("warning", "wh05-lynx", "wheel_type WH05 is the Lynx wheel: this robot's model is not known "
                        "here (robot_model:=, ROBOT_MODEL_NAME)", ("wheel_type", "robot_model"))]
    return [
        Finding(
            "error",
            "wh05-lynx",
            f"wheel_type WH05 is the Lynx wheel but robot_model is {model}",
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


def _inside(path: str, target: str) -> bool:
    return path == target or path.startswith(target.rstrip("/") + "/")


def _rule_mounted(stack: Stack, args: Mapping[str, str], volumes: Sequence[Volume] | None, _s: bool) -> list[Finding]:
    """An absolute path argument is a path inside the container: in a volume of the driver's
    service, or in the image (`IMAGE_PREFIXES`: a warning, since whether the image has the file
    is not known here); anywhere else the driver cannot open it (an error naming the mounts)."""
    if volumes is None:
        return []
    targets = [posixpath.normpath(v.target) for v in volumes if v.target]
    unknown = any("$" in t for t in targets)  # a mount compose interpolates: where it lands is not known here
    mounts = ", ".join(targets) or "none"
    out: list[Finding] = []
    for key, value in args.items():
        s = _BY_KEY.get(key)
        if s is None or s.type not in (ArgType.PATH, ArgType.DIR) or not value.startswith("/"):
            continue
        path = posixpath.normpath(value)
        if any(_inside(path, t) for t in targets):
            continue
        if unknown or path.startswith(IMAGE_PREFIXES):
            out.append(Finding("warning", "path-mounted",
                               f"{key}={value} is not inside any volume of the driver container; "
                               "the file must exist in the image or be mounted", (key,)))
        else:
            out.append(Finding("error", "path-mounted",
                               f"{key}={value} is neither inside a volume of the driver container (its mounts: "
                               f"{mounts}) nor in the image ({', '.join(p.rstrip('/') for p in IMAGE_PREFIXES)}): "
                               "the driver cannot open it; push the file (config push FILE --as KIND mounts it) "
                               "or mount its directory", (key,)))
    return out


RULES: tuple[ArgRule, ...] = (
    ArgRule("custom-wheels", "wheel_type custom needs wheel_config_path and controller_config_path", _rule_custom),
    ArgRule("wh05-lynx", "WH05 wheels only with robot_model lynx", _rule_wh05),
    ArgRule("battery-sim-only", "battery_config_path is simulation-only up to 2.1", _rule_battery),
    ArgRule("gps-source", "fuse_gps needs a GPS source", _rule_gps),
    ArgRule("enu-without-gps", "localization_mode enu is meant with GPS", _rule_enu),
    ArgRule("path-mounted", "an absolute config path is inside a mounted volume (or, a warning, in the image)",
            _rule_mounted),
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
    robot_model: str | None = None,
) -> list[Finding]:
    """Run every rule over a command's arguments (names as written in the command).

    Also reports names the stack does not declare: an unknown name is a warning (ros2 launch
    ignores it silently); a name of another version (``led_config_file`` on 2.2) or an alias
    (``user_animations_file``) is an error because the setting would silently not apply.
    ``robot_model``: the robot's model when the command has no ``robot_model:=`` (its
    ROBOT_MODEL_NAME, `robot_model.env_robot_model`); None: not known.
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
            findings.append(Finding("error", "unavailable-arg", unavailable_text(s, stack), (name,)))
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
    if robot_model is not None and "robot_model" not in keyed:
        keyed["robot_model"] = robot_model
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
