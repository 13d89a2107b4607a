"""The gamepad's parameters file (joy2twist, ``joy2twist_params_file``): its keys and types.

The keys are those the joy2twist node declares (husarion/joy2twist: ``joy2twist_panther.yaml``
and ``joy2twist_ugv.yaml``; husarion_ugv 2.2 ships a copy as
``husarion_ugv_bringup/config/joy2twist_<model>.yaml``): velocity factors per speed mode, the
E-stop topic and services, the output topic, and the gamepad's map in either of the node's
two forms: ``button_index_map`` (axis and button indexes, integers) or ``input_index_map``
(``'A3'``, ``'!A5'``, ``'B4'``: an optional negation, A for an axis or B for a button, its
number). The parameters sit under the node's name (``joy2twist_node``) or the wildcard
``/**``, below ``ros__parameters``. The E-stop topic, its services and ``cmd_vel_topic`` are
ROS names by rcl's rules (`core/parse/ros_names.py`): ``hardware/e-stop-reset`` would stop the
node when it creates its client, so it is refused here.

On husarion_ugv 2.3 (ROS 2 Jazzy) the drive controller takes only ``TwistStamped``
(husarion_ugv_ros@2.3.1:husarion_ugv_bringup/config/joy2twist_<model>.yaml and
@2.3.2:husarion_ugv_teleop/config/joy2twist_<model>.yaml say ``cmd_vel_stamped: true``), so
``cmd_vel_stamped: false`` is refused there. From 2.3.2 the velocity goes through the chainable
``twist_mux_controller``, whose inputs are ``manual/cmd_vel`` (priority 100),
``autonomous/cmd_vel`` (10) and ``cmd_vel`` (1) (husarion_ugv_ros@2.3.2:husarion_ugv_controller/
config/WH0X_controller.yaml); the stock gamepad file publishes on ``manual/cmd_vel``. A topic
that is no input of the mux is refused (nothing would read it); another input than
``manual/cmd_vel``, or no ``cmd_vel_topic`` (joy2twist's default ``cmd_vel``), is a warning.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

from panther_ops.core.kinds.common import is_number, load_mapping
from panther_ops.core.kinds.registry import FileKindError, Target
from panther_ops.core.parse.ros_names import RosNameError, service_name, topic_name
from panther_ops.core.stack import Stack

WHAT = "gamepad (joy2twist) parameters"
NODES = ("joy2twist_node", "/**")
MODES = ("fast", "regular", "slow")
AXES = ("angular_z", "linear_x", "linear_y")
BUTTONS = ("dead_man_switch", "fast_mode", "slow_mode", "e_stop_reset", "e_stop_trigger", "enable_e_stop_reset")
E_STOP = ("present", "topic", "reset_srv", "trigger_srv")
TOP = ("linear_velocity_factor", "angular_velocity_factor", "button_index_map", "input_index_map", "e_stop",
       "cmd_vel_topic", "cmd_vel_stamped")
_INPUT = re.compile(r"^!?[AB][0-9]{1,2}$")
STAMPED_SINCE = (2, 3, 0)
"""The first release whose drive controller takes only TwistStamped (ROS 2 Jazzy)."""
MUX_SINCE = (2, 3, 2)
"""The first release with the twist_mux_controller's inputs."""
MUX_INPUTS = ("manual/cmd_vel", "autonomous/cmd_vel", "cmd_vel")
_HINT = ("a joy2twist parameters file: joy2twist_node: ros__parameters: {linear_velocity_factor, "
         "angular_velocity_factor, button_index_map, e_stop}")


def _unknown(doc: dict[str, Any], allowed: tuple[str, ...], where: str, errors: list[str]) -> None:
    for key in doc:
        if key not in allowed:
            errors.append(f"{where}{key}: unknown key (allowed: {', '.join(allowed)})")


def _mapping(doc: dict[str, Any], key: str, where: str, errors: list[str]) -> dict[str, Any] | None:
    value = doc.get(key)
    if key in doc and not isinstance(value, dict):
        errors.append(f"{where}{key}={value!r} must be a mapping")
        return None
    return value


def _factors(section: dict[str, Any], where: str, errors: list[str]) -> None:
    _unknown(section, MODES, where, errors)
    for mode in MODES:
        if mode not in section:
            continue
        value = section[mode]
        if not isinstance(value, float) or isinstance(value, bool):
            errors.append(f"{where}{mode}={value!r} must be a floating-point number (e.g. 0.5; the node "
                          "declares a double)")
        elif not math.isfinite(value) or value < 0:
            errors.append(f"{where}{mode}={value!r} must be a finite number >= 0")


def _index(section: dict[str, Any], key: str, where: str, errors: list[str]) -> None:
    value = section[key]
    if not is_number(value) or not isinstance(value, int):
        errors.append(f"{where}{key}={value!r} must be an integer (the index of an axis or a button)")
    elif value < 0:
        errors.append(f"{where}{key}={value!r} must be an index >= 0")


def _input(section: dict[str, Any], key: str, where: str, errors: list[str]) -> None:
    value = section[key]
    if not isinstance(value, str) or not _INPUT.match(value):
        errors.append(f"{where}{key}={value!r} must be an input such as 'A3', '!A5' or 'B4' (optional '!', "
                      "A for an axis or B for a button, its number)")


def _map(section: dict[str, Any], where: str, errors: list[str], check: Any) -> None:
    _unknown(section, ("axis", *BUTTONS), where, errors)
    for key in BUTTONS:
        if key in section:
            check(section, key, where, errors)
    axis = _mapping(section, "axis", where, errors)
    if axis is not None:
        _unknown(axis, AXES, f"{where}axis.", errors)
        for key in AXES:
            if key in axis:
                check(axis, key, f"{where}axis.", errors)


def _buttons(section: dict[str, Any], where: str, errors: list[str]) -> None:
    _map(section, where, errors, _index)


def _inputs(section: dict[str, Any], where: str, errors: list[str]) -> None:
    _map(section, where, errors, _input)


def _e_stop(section: dict[str, Any], where: str, errors: list[str]) -> None:
    _unknown(section, E_STOP, where, errors)
    if "present" in section and not isinstance(section["present"], bool):
        errors.append(f"{where}present={section['present']!r} must be true or false")
    for key, parse in (("topic", topic_name), ("reset_srv", service_name), ("trigger_srv", service_name)):
        if key in section:
            _name(section[key], parse, f"{where}{key}", errors)


def _name(value: Any, parse: Callable[[object], str], where: str, errors: list[str]) -> None:
    """A topic or service name, by the one parser of ROS names (core/parse/ros_names.py)."""
    try:
        parse(value)
    except RosNameError as exc:
        errors.append(f"{where}={value!r}: {exc}")


def check_joy2twist(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    doc = load_mapping(source, data, WHAT)
    errors: list[str] = []
    warnings: list[str] = []
    nodes = [k for k in doc if k in NODES]
    for key in doc:
        if key not in NODES:
            errors.append(f"{key}: unknown node (allowed: {', '.join(NODES)})")
    if not nodes and not errors:
        errors.append("no joy2twist_node (or /**) section")
    for node in nodes:
        section = doc[node]
        if not isinstance(section, dict) or set(section) != {"ros__parameters"}:
            errors.append(f"{node}: must hold exactly ros__parameters:")
            continue
        params = section["ros__parameters"]
        where = f"{node}.ros__parameters."
        if not isinstance(params, dict):
            errors.append(f"{where[:-1]}={params!r} must be a mapping")
            continue
        _unknown(params, TOP, where, errors)
        for key, check in (("linear_velocity_factor", _factors), ("angular_velocity_factor", _factors),
                           ("button_index_map", _buttons), ("input_index_map", _inputs), ("e_stop", _e_stop)):
            sub = _mapping(params, key, where, errors)
            if sub is not None:
                check(sub, f"{where}{key}.", errors)
        if "button_index_map" in params and "input_index_map" in params:
            errors.append(f"{where}: button_index_map and input_index_map both given (the node reads one form)")
        if "cmd_vel_topic" in params:
            _name(params["cmd_vel_topic"], topic_name, f"{where}cmd_vel_topic", errors)
        if "cmd_vel_stamped" in params and not isinstance(params["cmd_vel_stamped"], bool):
            errors.append(f"{where}cmd_vel_stamped={params['cmd_vel_stamped']!r} must be true or false")
        elif target.stack is not None:
            _velocity_input(params, where, target.stack, errors, warnings)
    if errors:
        raise FileKindError(source, WHAT, errors, hint=_HINT)
    return warnings


def _velocity_input(params: dict[str, Any], where: str, stack: Stack, errors: list[str],
                    warnings: list[str]) -> None:
    """The release's rules for the gamepad's output (stamped from 2.3.0, the mux's inputs from 2.3.2)."""
    if stack.version < STAMPED_SINCE:
        return
    stamped = params.get("cmd_vel_stamped")
    if stamped is False:
        errors.append(f"{where}cmd_vel_stamped=false: {stack.label()}'s drive controller takes only TwistStamped "
                      f"(ROS 2 Jazzy): the gamepad's commands would not be read; write true")
    elif stamped is None:
        warnings.append(f"{where}cmd_vel_stamped: not set; {stack.label()}'s drive controller takes only "
                        f"TwistStamped: the stock file says true")
    if stack.version < MUX_SINCE:
        return
    topic = params.get("cmd_vel_topic")
    if isinstance(topic, str) and topic.strip("/") not in MUX_INPUTS:
        errors.append(f"{where}cmd_vel_topic={topic!r}: not an input of {stack.label()}'s twist_mux_controller "
                      f"({', '.join(MUX_INPUTS)}): nothing would drive the robot from it")
    elif topic is None or topic.strip("/") != MUX_INPUTS[0]:
        shown = "not set (joy2twist's default cmd_vel)" if topic is None else repr(topic)
        warnings.append(f"{where}cmd_vel_topic {shown}: the twist mux gives it a lower priority than "
                        f"{MUX_INPUTS[0]} (the stock file's, priority 100)")
