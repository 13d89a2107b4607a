"""Components and battery files: their keys, types and ranges (panther-stack.md 1.4-1.7); the wheel
file is `wheel.py`."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

from panther_ops.core.kinds.common import is_number, load_mapping
from panther_ops.core.kinds.registry import FileKindError, Target
from panther_ops.core.stack import Family

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_COMPONENT_TYPE = re.compile(r"^[A-Z]{3}[0-9]{2}$")
_WORD = re.compile(r"\S+", re.ASCII)


def _positive(doc: dict[str, Any], key: str, errors: list[str], *, required: bool = False) -> None:
    if key not in doc:
        if required:
            errors.append(f"{key} is required (a number > 0)")
        return
    value = doc[key]
    if not is_number(value) or not math.isfinite(float(value)) or float(value) <= 0:
        errors.append(f"{key}={value!r} must be a finite number > 0")


def _unknown(doc: dict[str, Any], allowed: tuple[str, ...], where: str, errors: list[str]) -> None:
    for key in doc:
        if key not in allowed:
            errors.append(f"{where}{key}: unknown key (allowed: {', '.join(allowed)})")


COMPONENT_KEYS = ("type", "parent_link", "xyz", "rpy", "device_namespace", "name")
NAME_KEY_SINCE = (2, 3, 2)
"""The first release whose components.yaml documents ``name`` where 2.2 had ``device_namespace``
(husarion_ugv_ros@2.3.2:husarion_ugv_description/config/components.yaml and CONFIGURATION.md;
2.3.0 and 2.3.1 keep 2.2's example)."""


def check_components(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    what = "components file"
    doc = load_mapping(source, data, what)
    errors: list[str] = []
    _unknown(doc, ("components",), "", errors)
    items = doc.get("components", [])
    if items is None:
        items = []
    if not isinstance(items, list):
        raise FileKindError(source, what, [f"components={items!r} must be a list"])
    for i, item in enumerate(items):
        where = f"components[{i}]"
        if not isinstance(item, dict):
            errors.append(f"{where}: must be a mapping ({', '.join(COMPONENT_KEYS)})")
            continue
        _unknown(item, COMPONENT_KEYS, f"{where}.", errors)
        kind = item.get("type")
        if not (isinstance(kind, str) and _COMPONENT_TYPE.match(kind)):
            errors.append(f"{where}.type={kind!r} is not a component type such as LDR06, CAM01, ANT02")
        for key in ("parent_link", "device_namespace", "name"):
            if key in item and not (isinstance(item[key], str) and _NAME.match(item[key])):
                errors.append(f"{where}.{key}={item[key]!r} must be a name (letters, digits, _)")
        if kind != "DEV02" and "parent_link" not in item and isinstance(kind, str):
            errors.append(f"{where}.parent_link is required (e.g. cover_link)")
        for key in ("xyz", "rpy"):
            if key in item:
                errors.extend(_triple(f"{where}.{key}", item[key]))
    if errors:
        raise FileKindError(source, what, errors)
    return _renamed(items, target)


def _renamed(items: list[Any], target: Target) -> list[str]:
    """On 2.3.2+: a warning for each component still keyed ``device_namespace`` (2.2's key)."""
    if target.stack is None or target.stack.version < NAME_KEY_SINCE:
        return []
    return [f"components[{i}].device_namespace: {target.stack.label()} documents 'name' for it (its "
            f"components.yaml and CONFIGURATION.md); write name: {item['device_namespace']}"
            for i, item in enumerate(items) if isinstance(item, dict) and "device_namespace" in item
            and "name" not in item]


def triple(value: Any) -> str | None:
    """``"x y z"`` (a components entry's ``xyz`` / ``rpy``) as three finite numbers in ASCII
    digits separated by ASCII spaces, normalised to single spaces; None when it is not (the
    URDF parser reads no other)."""
    from panther_ops.core.parse.numbers import NumberError, decimal

    parts = _WORD.findall(value) if isinstance(value, str) else []
    try:
        for part in parts:
            decimal(part)
    except NumberError:
        return None
    return " ".join(parts) if len(parts) == 3 else None


def _triple(where: str, value: Any) -> list[str]:
    if triple(value) is not None:
        return []
    return [f"{where}={value!r} must be three numbers separated by spaces, e.g. \"0.0 0.0 0.0\""]


BATTERY_KEYS = ("simulate_discharging", "capacity", "initial_charge_percentage", "charging_time", "power_load")
PERCENT_UNTIL = (2, 0, 0)
"""The last version whose battery file takes percent (0-100) and no capacity:
panther_ros@2.0.0:panther_description/urdf/gazebo.urdf.xacro computes
``20.0*initial_charge_percentage/100.0``; from panther_ros@2.0.1 (and at 2.0.4, 2.1.1,
husarion_ugv_ros@2.2.2:husarion_ugv_description/urdf/common/gazebo.urdf.xacro) it is
``initial_charge_percentage*capacity``: a 0-1 fraction."""


def _battery_required(version: tuple[int, int, int]) -> tuple[str, ...]:
    """The keys the robot's gazebo.urdf.xacro reads (``battery_config['<key>']``): xacro fails
    on a missing one, and with it the robot description. 2.0.0 reads power_load only when
    simulate_discharging is true and has no capacity."""
    if version <= PERCENT_UNTIL:
        return ("simulate_discharging", "initial_charge_percentage", "charging_time")
    return BATTERY_KEYS


def check_battery(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    what = "battery file"
    doc = load_mapping(source, data, what)
    errors: list[str] = []
    _unknown(doc, BATTERY_KEYS, "", errors)
    if "simulate_discharging" in doc and not isinstance(doc["simulate_discharging"], bool):
        errors.append(f"simulate_discharging={doc['simulate_discharging']!r} is not a boolean; allowed: true, false")
    for key in ("capacity", "charging_time", "power_load"):
        _positive(doc, key, errors)
    stack = target.stack
    if stack is not None:
        required = _battery_required(stack.version)
        if stack.version <= PERCENT_UNTIL and doc.get("simulate_discharging") is True:
            required = (*required, "power_load")
        for key in required:
            if key not in doc:
                errors.append(f"{key} is required: {stack.label()}'s URDF reads it (gazebo.urdf.xacro); "
                              "without it the robot description fails")
    percent = stack is not None and stack.family is not Family.HUSARION_UGV and stack.version <= PERCENT_UNTIL
    top = 100.0 if percent or stack is None else 1.0
    if "initial_charge_percentage" in doc:
        value = doc["initial_charge_percentage"]
        if not is_number(value) or not math.isfinite(float(value)) or not 0 <= float(value) <= top:
            scale = ("0-100 (percent, panther_ros 2.0.0)" if top == 100.0
                     else "0-1 (a fraction, panther_ros 2.0.1 and later)")
            errors.append(f"initial_charge_percentage={value!r} is outside {scale}")
    if errors:
        raise FileKindError(source, what, errors)
    notes: list[str] = []
    value = doc.get("initial_charge_percentage")
    if stack is None and isinstance(value, int | float) and not isinstance(value, bool) and 0 < value <= 1:
        notes.append(f"initial_charge_percentage {float(value):g} reads as the 0-1 fraction of panther_ros 2.0.1+ "
                     f"({float(value) * 100:g} %); panther_ros 2.0.0 takes percent (0-100)")
    if stack is None and doc.get("simulate_discharging") is False and doc.get("power_load"):  # sim battery check
        notes.append("simulate_discharging is false: the plugin uses power_load 0 W (the battery does not drain)")
    return notes
