"""The stock wheels of each release, and which wheels a wheel or controller file describes.

A wheel type (``wheel_type:=WH0X``) only picks the default ``wheel_config_path`` and
``controller_config_path``; the robot drives with what those two files say. A file whose
kinematics are a stock wheel's is that wheel's file (its limits apply); a file whose values are
no stock wheel's is a custom wheel's, which is what the manual's "custom wheels" are: files based
on ``WH01.yaml`` and ``WH01_controller.yaml`` with the custom wheels' values.

The values (the same at every tag of a family unless noted), from the stock files:

* panther_ros@2.0.4 and @2.1.1: panther_description/config/WH0{1,2,4}.yaml and
  panther_controller/config/WH0{1,2,4}_controller.yaml (WH02: ``mecanum_drive_controller``,
  the others ``diff_drive_controller``; ``mecanum`` in the wheel file from 2.1.0 only);
* husarion_ugv_ros@2.2.0 and @2.2.2: husarion_ugv_description/config/WH0{1,2,4,5}.yaml
  (``mount_point_offset`` instead of ``wheel_separation``) and
  husarion_ugv_controller/config/WH0{1,2,4,5}_controller.yaml; WH05's controller
  ``wheel_radius`` is 0.1348 up to 2.2.1 and 0.144 from 2.2.2 (the wheel file keeps 0.1348);
* husarion_ugv_ros@2.3.0, @2.3.1 and @2.3.2: the same kinematics as 2.2.2 (WH05's controller
  0.144; the wheel files unchanged), and the same upper limits in the Jazzy limits schema
  (`controller_limits`). 2.3.2's WH02 drive controller is ``husarion_mecanum_drive_controller/
  MecanumDriveController``: still mecanum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from panther_ops.core.stack import Family, Stack


@dataclass(frozen=True)
class StockWheel:
    """One stock wheel type's kinematics, as its wheel file and its controller file state them."""

    name: str
    mecanum: bool
    radius: float
    """``wheel_radius`` of the wheel file (and of the controller file unless ``controller_radius``)"""
    separation: float
    """``wheel_separation`` of panther_ros' wheel file; the controller's ``wheel_separation``
    (``wheel_separation_y`` for mecanum)"""
    mount_point_offset: float
    """``mount_point_offset`` of husarion_ugv's wheel file"""
    separation_x: float | None = None
    """the mecanum controller's ``wheel_separation_x``"""
    controller_radius: float | None = None


_PANTHER = (
    StockWheel("WH01", False, 0.1825, 0.697, 0.091),
    StockWheel("WH02", True, 0.1016, 0.6785, 0.08165, separation_x=0.44),
    StockWheel("WH04", False, 0.1016, 0.616, 0.06),
)
_WH05 = StockWheel("WH05", False, 0.1348, 0.45, 0.06)
_WH05_222 = StockWheel("WH05", False, 0.1348, 0.45, 0.06, controller_radius=0.144)


def stock_wheels(stack: Stack | None) -> tuple[StockWheel, ...]:
    """The release's stock wheels (every supported release's while no robot is known)."""
    if stack is None:
        return (*_PANTHER, _WH05, _WH05_222)
    if stack.family is not Family.HUSARION_UGV:
        return _PANTHER
    return (*_PANTHER, _WH05_222 if stack.version >= (2, 2, 2) else _WH05)


def stock_wheel(name: str | None) -> StockWheel | None:
    """A stock wheel type by name (None: ``custom`` or not known)."""
    return next((w for w in (*_PANTHER, _WH05) if w.name == name), None)


def _same(value: Any, expected: float | None) -> bool:
    return (expected is not None and isinstance(value, int | float) and not isinstance(value, bool)
            and math.isclose(float(value), expected, abs_tol=1e-9))


@dataclass(frozen=True)
class WheelsOfFile:
    """Which wheels a file describes."""

    stock: str | None
    """the stock wheel type whose values the file holds (None: none of them)"""
    mecanum: bool | None
    """mecanum wheels (None: the file does not say)"""
    stated: tuple[str, ...]
    """the kinematic values the file states (``wheel_radius=0.2`` ...): empty when it states none"""

    @property
    def custom(self) -> bool:
        """The file states its wheels' values and they are no stock wheel's."""
        return self.stock is None and bool(self.stated)

    def kind_text(self) -> str:
        return ("unknown" if self.mecanum is None else "mecanum" if self.mecanum else "non-mecanum") + " wheels"


def wheel_file_wheels(doc: dict[str, Any], stack: Stack | None) -> WheelsOfFile:
    """The wheels a wheel file (``WH0X.yaml``) describes."""
    keys = ("wheel_radius", "wheel_separation", "mount_point_offset")
    stated = tuple(f"{k}={doc[k]}" for k in keys if k in doc)
    stock = None
    for w in stock_wheels(stack):
        if _same(doc.get("wheel_radius"), w.radius) and (
                _same(doc.get("wheel_separation"), w.separation) or _same(doc.get("mount_point_offset"),
                                                                          w.mount_point_offset)):
            stock = w
            break
    mecanum = doc.get("mecanum") if isinstance(doc.get("mecanum"), bool) else (stock.mecanum if stock else None)
    return WheelsOfFile(stock.name if stock else None, mecanum, stated)


_CONTROLLER_KEYS = ("drive_controller", "panther_base_controller")
_KINEMATICS = ("wheel_radius", "wheel_separation", "wheel_separation_x", "wheel_separation_y")


def controller_file_wheels(plain: dict[str, Any], stack: Stack | None) -> WheelsOfFile:
    """The wheels a controller file describes: mecanum when its drive controller is the
    ``mecanum_drive_controller`` (or, with no type, when it has ``wheel_separation_x``); stock
    when its ``wheel_radius`` and separations are a stock wheel's of that kind."""
    params: dict[str, Any] = {}
    kind: str | None = None
    for body in plain.values():
        if not isinstance(body, dict):
            continue
        for key in _CONTROLLER_KEYS:
            section = body.get(key)
            if isinstance(section, dict) and isinstance(section.get("ros__parameters"), dict) and not params:
                params = section["ros__parameters"]
            manager = body.get("controller_manager")
            declared = manager.get("ros__parameters", {}).get(key) if isinstance(manager, dict) and isinstance(
                manager.get("ros__parameters"), dict) else None
            if isinstance(declared, dict) and isinstance(declared.get("type"), str) and kind is None:
                kind = declared["type"]
    stated = tuple(f"{k}={params[k]}" for k in _KINEMATICS if k in params)
    if kind is not None:
        mecanum: bool | None = "mecanum" in kind.lower()
    elif "wheel_separation_x" in params or "wheel_separation" in params:
        mecanum = "wheel_separation_x" in params
    else:
        mecanum = None
    stock = None
    for w in stock_wheels(stack):
        if mecanum is not None and w.mecanum != mecanum:
            continue
        same_sep = (_same(params.get("wheel_separation_x"), w.separation_x)
                    and _same(params.get("wheel_separation_y"), w.separation)) if w.mecanum else \
            _same(params.get("wheel_separation"), w.separation)
        if same_sep and _same(params.get("wheel_radius"), w.controller_radius or w.radius):
            stock = w
            break
    return WheelsOfFile(stock.name if stock else None, mecanum, stated)


def limits_wheel(wheels: WheelsOfFile, robot_wheel: str | None) -> str:
    """The wheel type whose limits a controller file is held to: the stock wheel it describes;
    ``custom`` (no reference limits) for a custom wheel's; the robot's for a file that states
    no kinematics."""
    if wheels.stock:
        return wheels.stock
    return "custom" if wheels.custom else (robot_wheel or "custom")


def mismatch(what: str, wheels: WheelsOfFile, robot_wheel: str | None) -> str | None:
    """A warning when the file's wheels are mecanum and the robot's wheel type's are not (or the
    other way round), naming the fix; None when they agree or either is not known."""
    robot = stock_wheel(robot_wheel)
    if robot is None or wheels.mecanum is None or wheels.mecanum == robot.mecanum:
        return None
    own = f"{wheels.stock}'s" if wheels.stock else "custom"
    stock_file = f"{robot.name}.yaml" if what == "wheel file" else f"{robot.name}_controller.yaml"
    return (f"this {what} describes {wheels.kind_text()} ({own}) but the robot's wheel_type {robot.name} is "
            f"{'mecanum' if robot.mecanum else 'non-mecanum'}: the driver would run one kind of wheels with the "
            f"other's kinematics; fix: base the file on {stock_file}, or if the wheels were changed: "
            f"panther-ops config set wheel_type {wheels.stock or 'custom'}")


def wheels_in(controller: bool, data: bytes, stack: Stack | None) -> WheelsOfFile:
    """The wheels a (checked) controller or wheel file's content describes."""
    from panther_ops.core.kinds.common import load_yaml

    doc = load_yaml("", data, "")
    if not isinstance(doc, dict):
        return WheelsOfFile(None, None, ())
    return controller_file_wheels(doc, stack) if controller else wheel_file_wheels(doc, stack)
