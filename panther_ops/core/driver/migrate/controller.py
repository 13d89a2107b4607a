"""The controller file (``husarion_ugv_controller/config/WH0X_controller.yaml``), 2.2 -> 2.3.

Sources: husarion_ugv_ros@2.2.2 and @2.3.2:husarion_ugv_controller/config/WH0{1,2,4,5}_controller.yaml
(2.3.1 for the versions without the mux); the semantics of the limits are ros2_controllers'
diff_drive_controller: on Humble a ``has_*_limits: false`` axis (the default when the key is
absent) is unlimited and an unset ``min_*`` is ``-max_*``; on Jazzy the ``has_*_limits``
parameters are gone ("instead set the respective limits to .NAN", ros2_controllers
doc/migration.rst, Iron to Jazzy, #1315) and its deprecated handling maps ``false`` to NaN for
``min/max_velocity``, the four acceleration keys and ``min/max_jerk``
(diff_drive_controller.cpp, on_configure). Humble bounds every velocity increase by
``max_acceleration`` and every decrease by ``min_acceleration``; Jazzy splits them by direction:
``max_acceleration`` (forward, speeding up), ``max_deceleration`` (forward, slowing down),
``max_acceleration_reverse`` (reverse, speeding up), ``max_deceleration_reverse`` (reverse,
slowing down). So with ``m`` = the 2.2 ``min_acceleration`` (or ``-A``): ``A``, ``m``, ``m``,
``A``, which for a stock file is upstream 2.3's ``A, -A, -A, A``.
"""

from __future__ import annotations

import math
from typing import Any

from panther_ops.core.driver.migrate.textedit import (
    Path,
    drop_comment_lines,
    insert_after,
    line_bounds,
    negated,
    raw,
    set_raw,
    trailing_comment,
)
from panther_ops.core.driver.migrate.translated import MUX_SINCE, MigrationRefused, Translated
from panther_ops.core.yaml.document import YamlDocument

_STALE_COMMENTS = (
    "#publish_limited_velocity: true",
    "# Whenever a min_* is unspecified, default to -max_*",
    "# min_velocity -  When unspecified `min_velocity=-max_velocity`",
    "# min_acceleration - When unspecified, `min_acceleration=-max_acceleration`",
    "# Whenever a min_* is unspecified it defaults to -max_*.",
)
"""husarion_ugv_ros@2.2.2's comments on the Humble rules (and the same rule as panther-ops' 2.2
templates word it); 2.3's files drop them."""
NAN = ".NAN"
AXES: tuple[tuple[str, str], ...] = (("linear", "x"), ("angular", "z"))
_HAS = ("has_velocity_limits", "has_acceleration_limits", "has_jerk_limits")
_ORDER = ("max_velocity", "min_velocity", "max_acceleration", "max_deceleration", "max_acceleration_reverse",
          "max_deceleration_reverse", "max_jerk", "min_jerk")
"""The order of an axis' keys in husarion_ugv_ros@2.3.2's controller files."""
_STOCK_Y = {"has_velocity_limits": True, "has_acceleration_limits": True, "has_jerk_limits": False,
            "max_velocity": 1.1, "max_acceleration": 1.5, "max_jerk": 0.0}
"""WH02's ``linear.y`` at husarion_ugv_ros@2.2.2 (2.3's mecanum controller has no such block)."""
_STOCK_ORIENTATION = [1.8e-3, 0.0, 0.0, 0.0, 1.8e-3, 0.0, 0.0, 0.0, 1.8e-3]
"""``imu_broadcaster.static_covariance_orientation`` of every 2.2.2 controller file."""
PLACEHOLDER = "<static_covariance_orientation>"
MECANUM = {"mecanum_drive_controller/MecanumDriveController":
           "husarion_mecanum_drive_controller/MecanumDriveController"}
"""WH02's drive controller type: 2.3.2 runs Husarion's own mecanum controller."""


def _number(path: str, doc: YamlDocument, at: Path) -> float:
    value = doc.get(at)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise MigrationRefused(f"{value!r} is not a number", path=path, line=doc.line_of(at),
                               key=".".join(map(str, at)), hint="write a number (m/s, rad/s, per second)")
    return float(value)


def _flag(path: str, doc: YamlDocument, at: Path) -> bool:
    value = doc.get(at, False)  # Humble's default for every has_*_limits is false
    if not isinstance(value, bool):
        raise MigrationRefused(f"{value!r} is not true or false", path=path, line=doc.line_of(at),
                               key=".".join(map(str, at)), hint="has_*_limits is a bool on Humble")
    return value


def _write(doc: YamlDocument, axis: Path, key: str, text: str, comment_from: str) -> None:
    """Write ``key`` of the axis: its value replaced in place, or a new line after the key
    before it in upstream's order (with that key's unit comment, as upstream writes them)."""
    at = (*axis, key)
    if doc.exists(at):
        set_raw(doc, at, text)
        return
    before = [k for k in _ORDER[: _ORDER.index(key)] if doc.exists((*axis, k))]
    if not before:
        doc.set(at, float("nan") if text == NAN else float(text))
        set_raw(doc, at, text)
        return
    comment = trailing_comment(doc, (*axis, comment_from)) if doc.exists((*axis, comment_from)) else ""
    insert_after(doc, (*axis, before[-1]), key, text, comment)


_JAZZY_ONLY = ("max_deceleration", "max_acceleration_reverse", "max_deceleration_reverse")
"""Keys only the Jazzy schema has: an axis holding one and no ``has_*_limits`` is already 2.3's."""


def _axis(path: str, doc: YamlDocument, axis: Path, name: str, notes: list[str]) -> None:
    keys = doc.keys(axis)
    if any(k in keys for k in _JAZZY_ONLY) and not any(h in keys for h in _HAS):
        notes.append(f"{name}: {'.'.join(map(str, axis[-2:]))} already in the Jazzy schema: kept")
        return
    has_v, has_a, has_j = (_flag(path, doc, (*axis, h)) for h in _HAS)
    where = ".".join(map(str, axis[-2:]))
    values: dict[str, str] = {}
    if has_v:
        if not doc.exists((*axis, "max_velocity")):
            raise MigrationRefused("has_velocity_limits is true but max_velocity is not set", path=path,
                                   line=doc.line_of((*axis, "has_velocity_limits")), key=f"{where}.max_velocity",
                                   hint="set max_velocity, or has_velocity_limits: false for no limit")
        _number(path, doc, (*axis, "max_velocity"))
        v = raw(doc, (*axis, "max_velocity"))
        values["max_velocity"] = v
        values["min_velocity"] = (raw(doc, (*axis, "min_velocity")) if doc.exists((*axis, "min_velocity"))
                                  else negated(v))
    else:
        values["max_velocity"] = values["min_velocity"] = NAN
        notes.append(f"{name}: {where}.has_velocity_limits false -> max_velocity/min_velocity .NAN (no limit)")
    if has_a:
        if not doc.exists((*axis, "max_acceleration")):
            raise MigrationRefused("has_acceleration_limits is true but max_acceleration is not set", path=path,
                                   line=doc.line_of((*axis, "has_acceleration_limits")),
                                   key=f"{where}.max_acceleration",
                                   hint="set max_acceleration, or has_acceleration_limits: false for no limit")
        _number(path, doc, (*axis, "max_acceleration"))
        a = raw(doc, (*axis, "max_acceleration"))
        m = (raw(doc, (*axis, "min_acceleration")) if doc.exists((*axis, "min_acceleration")) else negated(a))
        values.update(max_acceleration=a, max_deceleration=m, max_acceleration_reverse=m, max_deceleration_reverse=a)
        if doc.exists((*axis, "min_acceleration")):
            notes.append(f"{name}: {where}.min_acceleration {m} -> max_deceleration and max_acceleration_reverse {m}")
    else:
        for k in ("max_acceleration", "max_deceleration", "max_acceleration_reverse", "max_deceleration_reverse"):
            values[k] = NAN
        notes.append(f"{name}: {where}.has_acceleration_limits false -> the four acceleration limits .NAN (no limit)")
    if has_j:
        _number(path, doc, (*axis, "max_jerk"))
        j = raw(doc, (*axis, "max_jerk"))
        values["max_jerk"] = j
        values["min_jerk"] = raw(doc, (*axis, "min_jerk")) if doc.exists((*axis, "min_jerk")) else negated(j)
    else:
        values["max_jerk"] = values["min_jerk"] = NAN
    for h in (*_HAS, "min_acceleration"):
        doc.delete((*axis, h))
    comment_of = {"min_velocity": "max_velocity", "max_deceleration": "max_acceleration",
                  "max_acceleration_reverse": "max_acceleration", "max_deceleration_reverse": "max_acceleration",
                  "min_jerk": "max_jerk"}
    for key in _ORDER:
        _write(doc, axis, key, values[key], comment_of.get(key, key))


def _linear_y(path: str, doc: YamlDocument, axis: Path, name: str, notes: list[str]) -> None:
    block = doc.get(axis)
    if isinstance(block, dict) and {k: v for k, v in block.items()} == _STOCK_Y:
        doc.delete(axis)
        notes.append(f"{name}: linear.y removed (2.3's mecanum controller has no linear.y limits; the file had "
                     "2.2.2's stock values)")
        return
    raise MigrationRefused(
        "customised linear.y limits cannot be carried over: husarion_ugv 2.3's mecanum drive controller has no "
        "linear.y block", path=path, line=doc.line_of(axis), key="drive_controller.linear.y",
        hint="set linear.y back to 2.2.2's values (max_velocity 1.1, max_acceleration 1.5, has_jerk_limits false) "
             "or remove the block, then migrate; limit the robot through linear.x after the migration")


def _mux_section(holonomic: bool) -> dict[str, Any]:
    inputs = {name: {"topic": topic, "timeout": 0.2, "priority": prio}
              for name, topic, prio in (("manual", "manual/cmd_vel", 100), ("autonomous", "autonomous/cmd_vel", 10),
                                        ("unknown", "cmd_vel", 1))}
    interfaces = ({"command_interface_linear_x": "drive_controller/linear/x/velocity",
                   "command_interface_linear_y": "drive_controller/linear/y/velocity",
                   "command_interface_angular_z": "drive_controller/angular/z/velocity"} if holonomic else
                  {"command_interface_linear_x": "drive_controller/linear/velocity",
                   "command_interface_angular_z": "drive_controller/angular/velocity"})
    return {"ros__parameters": {"holonomic": holonomic, "cmd_vel_inputs": inputs, **interfaces}}


def translate_controller(text: str, path: str, target: tuple[int, int, int]) -> Translated:
    """A 2.2 controller file in the Jazzy schema of husarion_ugv ``target`` (2.3.x).

    Raises:
        MigrationRefused: a value with no 2.3 form (customised WH02 ``linear.y``, a
            ``has_*_limits`` that is not a bool, a limit that is not a number).
    """
    name = path.rsplit("/", 1)[-1]
    text, _n = drop_comment_lines(text, _STALE_COMMENTS)
    doc = YamlDocument(text, path)
    from panther_ops.core.kinds.controller_limits import locate
    from panther_ops.core.stack import stack_from_version

    top, key = locate(doc, stack_from_version("2.2.2"))
    params: Path = (top, key, "ros__parameters")
    notes: list[str] = []
    manager: Path = (top, "controller_manager", "ros__parameters")
    drive_type = doc.get((*manager, key, "type"), None)
    holonomic = isinstance(drive_type, str) and "mecanum" in drive_type
    if target >= MUX_SINCE and drive_type in MECANUM:
        set_raw(doc, (*manager, key, "type"), MECANUM[str(drive_type)])
    for part, axis_name in (*AXES, ("linear", "y")):
        axis = (*params, part, axis_name)
        if not isinstance(doc.get(axis, None), dict):
            continue
        if axis_name == "y":
            _linear_y(path, doc, axis, name, notes)
        else:
            _axis(path, doc, axis, name, notes)
    if doc.exists((*params, "use_stamped_vel")):
        doc.delete((*params, "use_stamped_vel"))
    if not doc.exists((*params, "publish_limited_velocity")) and doc.exists((*params, "cmd_vel_timeout")):
        insert_after(doc, (*params, "cmd_vel_timeout"), "publish_limited_velocity", "false")
    if target >= MUX_SINCE:
        _imu(doc, top, name, notes)
        if doc.exists(manager) and not doc.exists((*manager, "twist_mux_controller")):
            _declare_mux(doc, manager)
        if not doc.exists((top, "twist_mux_controller")):
            doc.set((top, "twist_mux_controller"), _mux_section(holonomic))
            _blank_line_before(doc, top)
    return Translated(doc.text, tuple(notes))


def _declare_mux(doc: YamlDocument, manager: Path) -> None:
    """``twist_mux_controller: type: ...`` after the last controller the manager declares."""
    last = doc.keys(manager)[-1]
    entry = doc.get((*manager, last))
    if not isinstance(entry, dict) or not entry:
        doc.set((*manager, "twist_mux_controller"), {"type": "twist_mux_controller/TwistMuxController"})
        return
    inner = (*manager, last, list(entry)[-1])
    start, end = line_bounds(doc, doc.info(inner).end)
    inner_col = len(doc.text[start:end]) - len(doc.text[start:end].lstrip(" "))
    value_line, _e = line_bounds(doc, doc.info((*manager, last)).start)
    key_start, key_end = line_bounds(doc, value_line - 1)
    key_line = doc.text[key_start:key_end]
    key_col = len(key_line) - len(key_line.lstrip(" "))
    new = f"\n{' ' * key_col}twist_mux_controller:\n{' ' * inner_col}type: twist_mux_controller/TwistMuxController"
    doc.replace_span(end, end, new, path=manager)


def _imu(doc: YamlDocument, top: str, name: str, notes: list[str]) -> None:
    at: Path = (top, "imu_broadcaster", "ros__parameters", "static_covariance_orientation")
    value = doc.get(at, None)
    if value is None:
        return
    if isinstance(value, list) and len(value) == len(_STOCK_ORIENTATION) and all(
            isinstance(x, int | float) and not isinstance(x, bool) and math.isclose(x, y)
            for x, y in zip(value, _STOCK_ORIENTATION, strict=True)):
        set_raw(doc, at, PLACEHOLDER)
        return
    if value != PLACEHOLDER:
        notes.append(f"{name}: imu_broadcaster.static_covariance_orientation kept as customised ({value}); 2.3.2 "
                     "ships a placeholder filled at launch from use_madgwick_filter, which this value overrides")


def _blank_line_before(doc: YamlDocument, top: str) -> None:
    """A blank line before the added ``twist_mux_controller`` section, as between upstream's sections."""
    info = doc.info((top, "twist_mux_controller"))
    start = doc.text.rfind("\n", 0, doc.text.rfind("\n", 0, info.start)) + 1
    if doc.text[start - 2:start] != "\n\n":
        doc.replace_span(start, start, "\n", path=(top,))
