"""The wheel file (``WH0X.yaml``, launch argument ``wheel_config_path``): the keys each release's
URDF reads, their types and ranges.

The robot description loads the file with ``xacro.load_yaml`` and reads these keys; a key it
reads that the file lacks stops the description from building (the driver does not start):

* panther_ros 2.0.4 / 2.1.1: ``wheel_radius`` (panther_ros@2.1.1:panther_description/urdf/panther_macro.urdf.xacro),
  ``wheel_width``, ``wheel_separation`` (the wheel's y is half of it), ``mass``, ``inertia``
  (``ixx``, ``iyy``, ``izz``), ``inertia_y_offset``, ``mesh_package``, ``folder_path``
  (panther_ros@2.0.4:panther_description/urdf/wheel.urdf.xacro, the same at 2.1.1);
* husarion_ugv 2.2.0 / 2.2.2: the same but ``mount_point_offset`` in place of
  ``wheel_separation`` (husarion_ugv_ros@2.2.0:husarion_ugv_description/urdf/common/wheel.urdf.xacro;
  ``wheel_radius`` in husarion_ugv_description/urdf/panther/panther_macro.urdf.xacro and
  lynx/lynx_macro.urdf.xacro);
* ``mecanum`` (2.1 and 2.2) is read only in simulation (inside ``<xacro:if value="${use_sim}">``
  of the same files): a file without it loads on a robot, not in the simulator.

Values that are no stock wheel's (a custom radius, width, separation) are custom wheels, the
manual's procedure (a file based on ``WH01.yaml``): accepted. A file for mecanum wheels onto a
robot whose wheel type is not (or the other way round) is written with a warning naming the fix
(`stock_wheels.mismatch`).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

from panther_ops.core.kinds.common import is_number, load_mapping
from panther_ops.core.kinds.registry import FileKindError, Target
from panther_ops.core.kinds.stock_wheels import mismatch, wheel_file_wheels
from panther_ops.core.stack import Family, Stack

WHAT = "wheel file"
_PATHISH = re.compile(r"^[A-Za-z0-9_./-]+$")
COMMON = ("wheel_radius", "wheel_width", "mass", "inertia", "inertia_y_offset", "mesh_package", "folder_path")
PANTHER_ROS_KEYS = (*COMMON, "wheel_separation")
HUSARION_UGV_KEYS = (*COMMON, "mount_point_offset")
SOURCES = {
    Family.PANTHER_ROS: "panther_ros@2.1.1:panther_description/urdf/wheel.urdf.xacro",
    Family.HUSARION_UGV: "husarion_ugv_ros@2.2.0:husarion_ugv_description/urdf/common/wheel.urdf.xacro",
}
WHEEL_KEYS = (*dict.fromkeys((*PANTHER_ROS_KEYS, *HUSARION_UGV_KEYS, "mecanum")),)
"""Every key a wheel file of a supported release holds."""


def required_keys(stack: Stack) -> tuple[str, ...]:
    """The keys the release's URDF reads on a robot."""
    return HUSARION_UGV_KEYS if stack.family is Family.HUSARION_UGV else PANTHER_ROS_KEYS


def _positive(doc: dict[str, Any], key: str, errors: list[str]) -> None:
    value = doc[key]
    if not is_number(value) or not math.isfinite(float(value)) or float(value) <= 0:
        errors.append(f"{key}={value!r} must be a finite number > 0")


def _values(doc: dict[str, Any], errors: list[str]) -> None:
    for key in ("wheel_radius", "wheel_width", "mass", "wheel_separation"):
        if key in doc:
            _positive(doc, key, errors)
    for key in ("inertia_y_offset", "mount_point_offset"):
        if key in doc and (not is_number(doc[key]) or not math.isfinite(float(doc[key]))):
            errors.append(f"{key}={doc[key]!r} must be a finite number")
    if "inertia" in doc:
        inertia = doc["inertia"]
        if not isinstance(inertia, dict):
            errors.append(f"inertia={inertia!r} must be a mapping {{ixx, iyy, izz}}")
        else:
            for key in inertia:
                if key not in ("ixx", "iyy", "izz"):
                    errors.append(f"inertia.{key}: unknown key (allowed: ixx, iyy, izz)")
            for key in ("ixx", "iyy", "izz"):
                if key not in inertia:
                    errors.append(f"inertia.{key} is required (a number > 0)")
                else:
                    _positive(inertia, key, errors)
    if "mecanum" in doc and not isinstance(doc["mecanum"], bool):
        errors.append(f"mecanum={doc['mecanum']!r} is not a boolean; allowed: true, false")
    for key in ("mesh_package", "folder_path"):
        if key in doc and not (isinstance(doc[key], str) and _PATHISH.match(doc[key]) and ".." not in doc[key]):
            errors.append(f"{key}={doc[key]!r} must be a package name or a relative path (letters, digits, _ . / -)")


def check_wheel(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    """The keys of the robot's release (of either release while no robot is known), their values."""
    doc = load_mapping(source, data, WHAT)
    errors: list[str] = []
    warnings: list[str] = []
    for key in doc:
        if key not in WHEEL_KEYS:
            errors.append(f"{key}: unknown key (allowed: {', '.join(WHEEL_KEYS)})")
    if "wheel_radius" not in doc:
        errors.append("wheel_radius is required (a number > 0)")
    stack = target.stack
    if stack is None:
        if not {"wheel_separation", "mount_point_offset"} & set(doc):
            errors.append("wheel_separation (panther_ros 2.0-2.1) or mount_point_offset (husarion_ugv 2.2) "
                          "is required")
    else:
        label, source_file = stack.label(), SOURCES[stack.family]
        needed = required_keys(stack)
        for key in needed:
            if key not in doc and key != "wheel_radius":
                errors.append(f"{key} is required on {label}: its URDF reads it ({source_file})")
        other = "wheel_separation" if stack.family is Family.HUSARION_UGV else "mount_point_offset"
        if other in doc:
            warnings.append(f"{other} is not read on {label} ({source_file} reads "
                            f"{'mount_point_offset' if other == 'wheel_separation' else 'wheel_separation'})")
        if "mecanum" not in doc and stack.version >= (2, 1, 0):
            warnings.append(f"no mecanum key: {label} reads it in simulation ({source_file})")
    _values(doc, errors)
    if errors:
        raise FileKindError(source, WHAT, errors)
    wrong = mismatch(WHAT, wheel_file_wheels(doc, stack), target.wheel_type)
    return [*warnings, wrong] if wrong else warnings
