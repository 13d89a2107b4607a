"""The controller file (``WH0X_controller.yaml``): structure, ROS types and the wheel limits.

The limits are checked by `controller_limits.validate_limit`, the check `config set
controller.<key>` makes, so a pushed file and a set value get the same message. A file
value must also have the type ROS declares: a double parameter written as an integer
(``max_velocity: 2``) makes the controller refuse to load. The IMU broadcaster must read
the sensor the robot's URDF declares under the robot's namespace (`controller_imu`).

The limits checked are those of the wheels the file describes (`stock_wheels`): a stock wheel's
kinematics, that wheel's limits; kinematics that are no stock wheel's are custom wheels (the
manual's procedure: a file based on ``WH01_controller.yaml``), whose limits have no reference; a
file that states no kinematics, the robot's wheel type's. A file for mecanum wheels onto a robot
whose wheel type is not (or the other way round) gets a warning naming the fix.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.kinds.common import text_of
from panther_ops.core.kinds.controller_imu import imu_findings
from panther_ops.core.kinds.controller_limits import (
    BOOL_PARAMS,
    CONTROLLER_KEYS,
    FLOAT_PARAMS,
    ControllerError,
    LimitExceededError,
    file_limits,
    jazzy,
    limit_value,
    limit_warnings,
    locate,
    validate_limit,
)
from panther_ops.core.kinds.controller_mux import mux_findings
from panther_ops.core.kinds.registry import FileKindError, Target
from panther_ops.core.kinds.stock_wheels import controller_file_wheels, limits_wheel, mismatch
from panther_ops.core.stack import Stack

WHAT = "controller file"
KINEMATICS = ("wheel_radius", "wheel_separation", "wheel_separation_x", "wheel_separation_y",
              "wheel_separation_multiplier", "wheel_separation_x_multiplier", "wheel_separation_y_multiplier",
              "left_wheel_radius_multiplier", "right_wheel_radius_multiplier", "wheel_radius_multiplier",
              "publish_rate", "cmd_vel_timeout")
AXES = (("linear", ("x", "y")), ("angular", ("z",)))


@dataclass
class _Check:
    target: Target
    force: bool
    wheel: str
    """the wheel type whose limits apply (`stock_wheels.limits_wheel`)"""
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    hint: str | None = None

    def section(self, where: str, section: dict[str, Any]) -> None:
        params = section.get("ros__parameters")
        if not isinstance(params, dict):
            self.errors.append(f"{where}.ros__parameters must be a mapping")
            return
        for name in KINEMATICS:
            if name in params:
                problem = _positive_double(params[name])
                if problem:
                    self.errors.append(f"{where}.ros__parameters.{name}={params[name]!r} {problem}")
        for group, axes in AXES:
            block = params.get(group)
            if block is None:
                continue
            if not isinstance(block, dict):
                self.errors.append(f"controller.{group} must be a mapping of axes ({', '.join(axes)})")
                continue
            for axis, values in block.items():
                if axis not in axes or not isinstance(values, dict):
                    self.errors.append(f"controller.{group}.{axis}: not an axis with limits "
                                       f"(allowed: {', '.join(f'{group}.{a}' for a in axes)})")
                    continue
                for param, value in values.items():
                    self.limit(f"controller.{group}.{axis}.{param}", param, value)

    def limit(self, dotted: str, param: str, value: Any) -> None:
        if param in BOOL_PARAMS and not isinstance(value, bool):
            self.errors.append(f"{dotted}={value!r} is not a boolean; allowed: true, false")
            return
        if param in FLOAT_PARAMS and isinstance(value, int) and not isinstance(value, bool):
            self.errors.append(f"{dotted}={value} is an integer: ROS 2 refuses an integer for a double "
                               f"parameter; write {value}.0")
            return
        stack = self.target.stack
        try:
            if stack is None:  # without a robot: types only, the limits are checked per robot
                limit_value(dotted, value)
                return
            got = validate_limit(stack, self.wheel, dotted, value, force=self.force)
        except LimitExceededError as exc:
            self.errors.append(exc.message)
            self.hint = exc.hint
            return
        except ControllerError as exc:
            self.errors.append(exc.message)
            return
        self.warnings.extend(w for w in got.warnings if "no reference limits" not in w)


def check_controller(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    from panther_ops.core.yaml.document import YamlDocument
    from panther_ops.core.yaml.paths import DocumentError
    from panther_ops.errors import UsageError

    text = text_of(source, data, WHAT)
    try:
        doc = YamlDocument(text, source)
    except DocumentError as exc:
        raise FileKindError(source, WHAT, [f"not valid YAML: {exc.message}"]) from None
    plain = doc.to_plain()
    if not isinstance(plain, dict):
        raise FileKindError(source, WHAT, ["not a controller file: the top level is not a mapping"])
    wheels = controller_file_wheels(plain, target.stack)
    check = _Check(target, force, limits_wheel(wheels, target.wheel_type))
    if target.stack is not None:
        if wheels.custom:
            check.warnings.append(f"custom wheels ({', '.join(wheels.stated)}: no stock wheel's of "
                                  f"{target.stack.label()}): the limits are checked against no stock wheel's")
        wrong = mismatch(WHAT, wheels, target.wheel_type)
        if wrong:
            check.warnings.append(wrong)
        check.warnings.extend(_gone(plain, target.stack))
        mux = mux_findings(plain, target.stack)
        if force:
            check.warnings.extend(e + " (forced)" for e in mux.errors)
        else:
            check.errors.extend(mux.errors)
        check.warnings.extend(mux.warnings)
        imu = imu_findings(plain, target.stack, target.namespace)
        if force:
            check.warnings.extend(e + " (forced)" for e in imu.errors)
        else:
            check.errors.extend(imu.errors)
            check.hint = imu.hint or check.hint
        check.warnings.extend(imu.warnings)
        try:
            top, key = locate(doc, target.stack, force=force)
            check.warnings.extend(doc.notes)
            limits = file_limits(doc, top, key)
            check.warnings.extend(w for w in limit_warnings(limits, check.wheel)
                                  if "exceeds" not in w)  # limits at zero
        except UsageError as exc:
            check.errors.append(exc.message)
            check.hint = exc.hint
    sections = [(f"{top}.{key}", body[key]) for top, body in plain.items() if isinstance(body, dict)
                for key in CONTROLLER_KEYS if isinstance(body.get(key), dict)]
    if not sections and target.stack is None:
        check.errors.append("no drive_controller (or panther_base_controller) section: not a controller file")
    for where, section in sections:
        check.section(where, section)
    if check.errors:
        raise FileKindError(source, WHAT, check.errors, hint=check.hint)
    return list(dict.fromkeys(check.warnings))


STAMPED = "use_stamped_vel"


def _gone(plain: dict[str, Any], stack: Stack) -> list[str]:
    """A warning for ``use_stamped_vel`` on a Jazzy release: its controllers take only stamped
    velocities and read no such parameter (ros2_controllers' jazzy branch,
    diff_drive_controller/src/diff_drive_controller_parameter.yaml; gone from
    husarion_ugv_ros@2.3.0:husarion_ugv_controller/config/WH0X_controller.yaml)."""
    if not jazzy(stack):
        return []
    return [f"{top}.{key}.ros__parameters.{STAMPED}: {stack.label()}'s controllers read no such parameter "
            f"(ROS 2 Jazzy takes only stamped velocities): it has no effect"
            for top, body in plain.items() if isinstance(body, dict)
            for key in CONTROLLER_KEYS if isinstance(body.get(key), dict)
            and isinstance(body[key].get("ros__parameters"), dict) and STAMPED in body[key]["ros__parameters"]]


def _positive_double(value: Any) -> str | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return "is not a number"
    if isinstance(value, int):
        return f"is an integer: ROS 2 refuses an integer for a double parameter; write {value}.0"
    if not math.isfinite(value) or value <= 0:
        return "must be a finite number > 0"
    return None
