"""The drive controller's limits (``WH0X_controller.yaml``): keys, the wheel types' limits, checks.

Keys are dotted: ``controller.linear.x.max_velocity``, ``controller.angular.z.max_acceleration``,
``controller.linear.x.has_jerk_limits``... (``linear.y`` exists only for the mecanum wheels
WH02). They map into the controller file under
``/**: <controller_key>: ros__parameters: linear: x: max_velocity``, where the controller key
is ``panther_base_controller`` up to panther_ros 2.0.4 and ``drive_controller`` from 2.1.0.

The wheel types have upper limits (panther-stack.md 1.4; the shipped defaults equal them):
WH01 2.0 m/s, 2.7 m/s², 4.0 rad/s, 5.74 rad/s²; WH02 and WH04 1.1 m/s, 1.5 m/s², 2.2 rad/s,
3.2 rad/s²; WH05 (the Lynx's, husarion_ugv 2.2) 1.5 m/s, 2.1 m/s², 4.0 rad/s, 5.74 rad/s², the
values of its stock file (husarion_ugv_ros@2.2.0, @2.2.2:husarion_ugv_controller/config/
WH05_controller.yaml), where a Lynx without ``wheel_type:=`` runs WH05 (its model's default,
`ArgSpec.model_defaults`). A value above the limit is refused with `LimitExceededError` naming it, unless
``force`` (then it is written with a warning).

Two schemas, chosen by the robot's release (`schema_params`):

* ROS 2 Humble (panther_ros 2.0-2.1, husarion_ugv 2.2): per axis ``has_velocity_limits``,
  ``has_acceleration_limits``, ``has_jerk_limits`` and ``max_*``/``min_*`` of velocity,
  acceleration and jerk, finite numbers.
* ROS 2 Jazzy (husarion_ugv 2.3.0+, ros2_controllers' jazzy branch:
  diff_drive_controller/src/diff_drive_controller_parameter.yaml and
  mecanum_drive_controller/src/mecanum_drive_controller.yaml): ``max_velocity``,
  ``min_velocity``, ``max_acceleration``, ``max_deceleration``, ``max_acceleration_reverse``,
  ``max_deceleration_reverse``, ``max_jerk``, ``min_jerk``; ``.nan`` means "no limit" (the
  default of every one, and the stock files' jerk: husarion_ugv_ros@2.3.0/2.3.1/2.3.2:
  husarion_ugv_controller/config/WH0X_controller.yaml). The signs are the parameters'
  ``gt_eq_or_nan``/``lt_eq_or_nan`` validation: ``min_*``, ``max_deceleration`` and
  ``max_acceleration_reverse`` are <= 0, the others >= 0. ``has_*_limits`` (deprecated
  there, ignored by the mecanum controller) and ``min_acceleration`` (deprecated: use
  ``max_deceleration``) are refused, so a 2.3 file has one way to say a limit. The wheel
  types' limits bound the absolute value of every velocity, acceleration and deceleration.

The rules shared by the controller file's validator (`controller.py`) and its editor
(`core.robot.controller.ControllerConfig`, ``config set controller.<key>``): the same value
gets the same message whichever path writes it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from panther_ops.core.stack import Stack
from panther_ops.errors import InputError, UsageError

if TYPE_CHECKING:  # the YAML editor (ruamel) loads when a file is read, not for validating values
    from panther_ops.core.yaml.document import YamlDocument

AXES = ("linear.x", "linear.y", "angular.z")
BOOL_PARAMS = ("has_velocity_limits", "has_acceleration_limits", "has_jerk_limits")
HUMBLE_FLOAT_PARAMS = ("max_velocity", "min_velocity", "max_acceleration", "min_acceleration", "max_jerk", "min_jerk")
JAZZY_PARAMS = ("max_velocity", "min_velocity", "max_acceleration", "max_deceleration", "max_acceleration_reverse",
                "max_deceleration_reverse", "max_jerk", "min_jerk")
"""The limits of an axis in Jazzy's ros2_controllers (husarion_ugv 2.3+); all doubles, ``.nan``: no limit."""
JAZZY_SINCE = (2, 3, 0)
"""The first release whose controllers are Jazzy's (husarion_ugv_ros@2.3.0)."""
FLOAT_PARAMS = tuple(dict.fromkeys((*HUMBLE_FLOAT_PARAMS, *JAZZY_PARAMS)))
"""Every double limit parameter of either schema (a file's integer value is refused in both)."""
NON_POSITIVE = ("min_velocity", "min_acceleration", "min_jerk", "max_deceleration", "max_acceleration_reverse")
"""Limits of the reverse direction or of slowing down: <= 0 (the others >= 0)."""
CONTROLLER_KEYS = ("drive_controller", "panther_base_controller")
CONTROLLER_PARAMS = ("cmd_vel_timeout",)
"""Parameters of the controller itself (``controller.<param>``, no axis): seconds > 0."""


class ControllerError(UsageError):
    """A controller limit key or value that is not allowed."""


class LimitExceededError(ControllerError):
    """A value above the wheel type's upper limit."""


class ControllerFileError(InputError):
    """The controller file does not fit the robot's stack (e.g. wrong controller key)."""


@dataclass(frozen=True)
class WheelLimits:
    """Upper limits of a wheel type."""

    linear_velocity: float
    linear_acceleration: float
    angular_velocity: float
    angular_acceleration: float


WHEEL_LIMITS: dict[str, WheelLimits] = {
    "WH01": WheelLimits(2.0, 2.7, 4.0, 5.74),
    "WH02": WheelLimits(1.1, 1.5, 2.2, 3.2),
    "WH04": WheelLimits(1.1, 1.5, 2.2, 3.2),
    "WH05": WheelLimits(1.5, 2.1, 4.0, 5.74),
}


@dataclass(frozen=True)
class LimitKey:
    """``controller.<axis>.<param>``: axis ``linear.x`` / ``linear.y`` / ``angular.z``; or
    ``controller.<param>`` for a parameter of the controller itself (axis ``""``)."""

    axis: str
    param: str

    @property
    def dotted(self) -> str:
        return f"controller.{self.axis}.{self.param}" if self.axis else f"controller.{self.param}"

    @property
    def is_bool(self) -> bool:
        return self.param in BOOL_PARAMS

    @property
    def unit(self) -> str:
        if not self.axis:
            return "s"
        base = "rad" if self.axis.startswith("angular") else "m"
        if "velocity" in self.param:
            return f"{base}/s"
        if "celeration" in self.param:
            return f"{base}/s²"
        return f"{base}/s³" if "jerk" in self.param else ""

    def path(self, controller_key: str, top: str = "/**") -> tuple[str, ...]:
        if not self.axis:
            return (top, controller_key, "ros__parameters", self.param)
        group, axis = self.axis.split(".")
        return (top, controller_key, "ros__parameters", group, axis, self.param)


@dataclass(frozen=True)
class ValidatedLimit:
    key: LimitKey
    value: bool | float
    warnings: tuple[str, ...] = ()


def jazzy(stack: Stack) -> bool:
    """The release runs Jazzy's ros2_controllers (its limits schema, `JAZZY_PARAMS`)."""
    return stack.version >= JAZZY_SINCE


def schema_params(stack: Stack | None) -> tuple[str, ...]:
    """The limit parameters of an axis on the stack (either schema's while no robot is known)."""
    if stack is None:
        return (*BOOL_PARAMS, *FLOAT_PARAMS)
    return JAZZY_PARAMS if jazzy(stack) else (*BOOL_PARAMS, *HUMBLE_FLOAT_PARAMS)


def all_limit_keys(wheel_type: str = "WH02", stack: Stack | None = None) -> list[str]:
    """Every limit key for a wheel type (``linear.y`` only for WH02) on the stack (None: either schema)."""
    axes = AXES if wheel_type == "WH02" else tuple(a for a in AXES if a != "linear.y")
    return [*(f"controller.{a}.{p}" for a in axes for p in schema_params(stack)),
            *(f"controller.{p}" for p in CONTROLLER_PARAMS)]


def parse_limit_key(key: str) -> LimitKey:
    """``controller.linear.x.max_velocity`` (the ``controller.`` prefix is optional).

    Raises:
        ControllerError: not a limit key (the message lists the allowed ones).
    """
    text = key.strip()
    if text.startswith("controller."):
        text = text[len("controller.") :]
    parts = text.split(".")
    if len(parts) == 3 and f"{parts[0]}.{parts[1]}" in AXES and parts[2] in (*BOOL_PARAMS, *FLOAT_PARAMS):
        return LimitKey(f"{parts[0]}.{parts[1]}", parts[2])
    if len(parts) == 1 and parts[0] in CONTROLLER_PARAMS:
        return LimitKey("", parts[0])
    raise ControllerError(
        f"unknown controller limit {key!r}",
        hint="controller.{linear.x,angular.z,linear.y (WH02)}.{"
        + ",".join((*BOOL_PARAMS, *FLOAT_PARAMS))
        + "}, or controller.{" + ",".join(CONTROLLER_PARAMS) + "} (seconds)",
    )


def upper_limit(wheel_type: str, key: LimitKey) -> float | None:
    """The wheel type's limit for a key (None: no reference limit, e.g. jerk or custom wheels)."""
    limits = WHEEL_LIMITS.get(wheel_type)
    if limits is None or not key.axis or key.is_bool or "jerk" in key.param:
        return None
    linear = key.axis.startswith("linear")
    if "velocity" in key.param:
        return limits.linear_velocity if linear else limits.angular_velocity
    return limits.linear_acceleration if linear else limits.angular_acceleration


def _as_bool(key: LimitKey, value: Any) -> bool:
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("true", "1"):
        return True
    if text in ("false", "0"):
        return False
    raise ControllerError(f"{key.dotted}={value!r} is not a boolean; allowed: true, false")


def _as_float(key: LimitKey, value: Any) -> float:
    """A limit's number: a YAML number, or its text in ASCII digits (`core.parse.numbers`); NaN
    (YAML ``.nan``, or the text ``nan``/``.nan``) for an axis limit: whether the release takes
    it is `validate_limit`'s check."""
    from panther_ops.core.parse.numbers import NumberError, decimal

    if isinstance(value, bool):
        raise ControllerError(f"{key.dotted}={value!r} is not a number")
    try:
        return decimal(value.strip() if isinstance(value, str) else value)
    except NumberError:
        pass
    text = str(value).strip().lower().lstrip("+-")
    if key.axis and text in ("nan", ".nan"):
        return math.nan
    if (isinstance(value, float) and not math.isfinite(value)) or text in ("nan", "inf", "infinity"):
        raise ControllerError(f"{key.dotted}={value!r} must be a finite number ({key.unit})")
    raise ControllerError(f"{key.dotted}={value!r} is not a number ({key.unit}; ASCII digits, e.g. 1.5)")


def limit_value(key: str | LimitKey, value: Any) -> tuple[LimitKey, bool | float]:
    """The key and its value as written, whatever the robot's wheels: a boolean for
    ``has_*_limits``, a finite number or NaN otherwise, seconds > 0 for ``cmd_vel_timeout``. What
    `validate_limit` checks first, and the inventory's ``desired.controller`` when it loads.

    Raises:
        ControllerError: not a limit key, or a value of the wrong type.
    """
    lk = key if isinstance(key, LimitKey) else parse_limit_key(key)
    if lk.is_bool:
        return lk, _as_bool(lk, value)
    number = _as_float(lk, value)
    if not lk.axis and number <= 0:  # cmd_vel_timeout: the watchdog's seconds, whatever the wheels
        raise ControllerError(f"{lk.dotted}={value!r} must be a positive number of seconds",
                              hint="e.g. 0.5 (panther_ros' default; husarion_ugv 2.2: 0.2)")
    return lk, number


def validate_limit(
    stack: Stack, wheel_type: str, key: str | LimitKey, value: Any, *, force: bool = False
) -> ValidatedLimit:
    """Check a limit value for the wheel type.

    Raises:
        ControllerError: bad key or value type, ``linear.y`` on non-mecanum wheels, a
            negative maximum or positive minimum (unless ``force``).
        LimitExceededError: above the wheel type's limit (unless ``force``).
    """
    lk, checked = limit_value(key, value)
    warnings: list[str] = []

    def refuse(message: str, error: type[ControllerError] = ControllerError, hint: str | None = None) -> None:
        if not force:
            raise error(message, hint=hint or "use --force to write it anyway")
        warnings.append(message + " (forced)")

    if not lk.axis:  # cmd_vel_timeout: the watchdog's seconds, whatever the wheels
        return ValidatedLimit(lk, checked)
    _check_schema(stack, lk)
    if lk.axis == "linear.y" and wheel_type not in ("WH02", "custom"):  # custom wheels may be mecanum
        refuse(f"{lk.dotted}: linear.y limits exist only for the mecanum wheels WH02 (this robot: {wheel_type})")
    if isinstance(checked, bool):
        return ValidatedLimit(lk, checked, tuple(warnings))
    number = checked
    if math.isnan(number):
        if not jazzy(stack):
            raise ControllerError(f"{lk.dotted}={value!r} must be a finite number ({lk.unit})",
                                  hint=f".nan (no limit) is a limit value of husarion_ugv 2.3+ (ROS 2 Jazzy), "
                                       f"not of {stack.label()}")
        return ValidatedLimit(lk, number, tuple(warnings))  # no limit: Jazzy's default
    if lk.param not in NON_POSITIVE and number < 0:
        refuse(f"{lk.dotted}={number} must not be negative")
    if lk.param in NON_POSITIVE and number > 0:
        what = "it limits the reverse direction" if lk.param.startswith("min_") else "it limits slowing down"
        refuse(f"{lk.dotted}={number} must not be positive ({what})")
    limit = upper_limit(wheel_type, lk)
    if limit is not None and abs(number) > limit + 1e-9:
        refuse(
            f"{lk.dotted}={number} {lk.unit} exceeds the {wheel_type} limit of {limit} {lk.unit}",
            LimitExceededError,
            hint=f"{wheel_type} limits: {_limits_text(wheel_type)}; --force writes it anyway",
        )
    elif limit is None and "jerk" not in lk.param:
        warnings.append(f"no reference limits for wheel type {wheel_type}; {lk.dotted} not checked")
    return ValidatedLimit(lk, number, tuple(warnings))


_JAZZY_INSTEAD = {"has_velocity_limits": "set max_velocity and min_velocity to .nan for no limit",
                  "has_acceleration_limits": "set max_acceleration, max_deceleration, max_acceleration_reverse "
                                             "and max_deceleration_reverse to .nan for no limit",
                  "has_jerk_limits": "set max_jerk and min_jerk to .nan for no limit",
                  "min_acceleration": "max_deceleration (<= 0) and max_acceleration_reverse (<= 0) replace it"}


def _check_schema(stack: Stack, key: LimitKey) -> None:
    """Refuse a limit of the other schema than the stack's (Humble's or Jazzy's)."""
    if key.param in schema_params(stack):
        return
    if jazzy(stack):
        raise ControllerError(
            f"{key.dotted}: not a limit of {stack.label()} (ROS 2 Jazzy's ros2_controllers): "
            f"{_JAZZY_INSTEAD[key.param]}",
            hint="limits on husarion_ugv 2.3+: " + ", ".join(JAZZY_PARAMS))
    raise ControllerError(
        f"{key.dotted}: a limit of husarion_ugv 2.3+ (ROS 2 Jazzy), not of {stack.label()}",
        hint=f"limits on {stack.label()}: " + ", ".join((*BOOL_PARAMS, *HUMBLE_FLOAT_PARAMS)))


def _limits_text(wheel_type: str) -> str:
    lim = WHEEL_LIMITS[wheel_type]
    return (
        f"linear {lim.linear_velocity} m/s, {lim.linear_acceleration} m/s²; "
        f"angular {lim.angular_velocity} rad/s, {lim.angular_acceleration} rad/s²"
    )


def locate(doc: YamlDocument, stack: Stack, *, force: bool = False) -> tuple[str, str]:
    """Where the stack's controller section is: (top key, controller key).

    Raises:
        ControllerFileError: no controller section, or the other generation's controller
            key (unless ``force``: then a note in ``doc.notes``).
    """
    data = doc.to_plain()
    if not isinstance(data, dict):
        raise ControllerFileError("not a controller file: the top level is not a mapping", path=doc.path)
    expected = stack.controller_key
    found: list[tuple[str, str]] = []
    for top, body in data.items():
        if isinstance(body, dict):
            found.extend((str(top), k) for k in CONTROLLER_KEYS if isinstance(body.get(k), dict))
    for top, key in found:
        if key == expected:
            return top, key
    if found:
        top, key = found[0]
        message = (
            f"the file configures {key} but {stack.label()} runs {expected}: "
            "the limits in this file would not be applied"
        )
        if not force:
            raise ControllerFileError(
                message,
                path=doc.path,
                line=doc.line_of((top, key)),
                key=f"{top}.{key}",
                hint=f"rename the {key} keys to {expected} (the controller was renamed in panther_ros 2.1.0)",
            )
        doc.notes.append(message + " (forced)")
        return top, key
    raise ControllerFileError(
        f"no {expected} section in the controller file", path=doc.path, key=f"/**.{expected}"
    )


def file_limits(doc: YamlDocument, top: str, controller_key: str) -> dict[str, Any]:
    """Every limit key present in the file's controller section (dotted key -> value)."""
    out: dict[str, Any] = {}
    for dotted in all_limit_keys("WH02"):
        value = doc.get(parse_limit_key(dotted).path(controller_key, top), None)
        if value is not None:
            out[dotted] = value
    return out


def same_limit(a: Any, b: Any) -> bool:
    """Two limit values are the same: equal, or both NaN (Jazzy's "no limit", which != itself)."""
    nan = [isinstance(v, float) and math.isnan(v) for v in (a, b)]
    return all(nan) or (not any(nan) and bool(a == b))


def same_limits(a: dict[str, Any], b: dict[str, Any]) -> bool:
    """Two files' limits (`file_limits`) are the same, key for key (`same_limit`)."""
    return a.keys() == b.keys() and all(same_limit(a[k], b[k]) for k in a)


def limit_warnings(limits: dict[str, Any], wheel_type: str) -> list[str]:
    """Warnings about a file's limits as they are: above the wheel limits, enabled limits at 0."""
    warnings: list[str] = []
    for dotted, value in limits.items():
        lk = parse_limit_key(dotted)
        limit = upper_limit(wheel_type, lk)
        if limit is not None and isinstance(value, int | float) and abs(value) > limit + 1e-9:  # NaN: never
            warnings.append(f"{dotted}={value} {lk.unit} exceeds the {wheel_type} limit of {limit} {lk.unit}")
    for axis in AXES:
        for kind in ("velocity", "acceleration", "jerk"):
            enabled = limits.get(f"controller.{axis}.has_{kind}_limits")
            maximum = limits.get(f"controller.{axis}.max_{kind}")
            if enabled is True and isinstance(maximum, int | float) and maximum == 0:
                warnings.append(
                    f"controller.{axis}.has_{kind}_limits is true with max_{kind} 0.0: "
                    f"the {axis} {kind} is limited to zero"
                )
    return warnings
