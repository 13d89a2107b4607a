"""The twist mux of a controller file (husarion_ugv 2.3.2): is it there, and are its inputs usable?

Facts: husarion_ugv_ros@2.3.2:husarion_ugv_controller/launch/controller.launch.py spawns
``joint_state_broadcaster``, ``drive_controller``, ``imu_broadcaster`` and ``twist_mux_controller``
with ``--activate-as-group``: a file that does not declare ``twist_mux_controller`` (its ``type``
under ``controller_manager``) starts none of them. Every stock file of 2.3.2
(husarion_ugv_controller/config/WH0X_controller.yaml) declares
``twist_mux_controller/TwistMuxController`` with ``cmd_vel_inputs`` ``manual``, ``autonomous`` and
``unknown``, each a ``topic``, a ``timeout`` (s, a double) and a ``priority`` (an integer), and
``holonomic`` (true for the mecanum WH02). 2.3.0 and 2.3.1 spawn no mux: a declared one is not
started (a warning).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.parse.ros_names import RosNameError, topic_name
from panther_ops.core.stack import Stack

MUX = "twist_mux_controller"
MUX_SINCE = (2, 3, 2)
"""The first release whose controller.launch.py spawns the twist mux."""


@dataclass
class MuxFindings:
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def _declared(plain: dict[str, Any]) -> tuple[str, Any] | None:
    """(top key, the mux's controller_manager entry) when the file declares the mux."""
    for top, body in plain.items():
        manager = body.get("controller_manager") if isinstance(body, dict) else None
        params = manager.get("ros__parameters") if isinstance(manager, dict) else None
        if isinstance(params, dict) and MUX in params:
            return str(top), params[MUX]
    return None


def _params(plain: dict[str, Any]) -> tuple[str, Any] | None:
    for top, body in plain.items():
        if isinstance(body, dict) and isinstance(body.get(MUX), dict):
            return f"{top}.{MUX}.ros__parameters", body[MUX].get("ros__parameters")
    return None


def mux_findings(plain: dict[str, Any], stack: Stack) -> MuxFindings:
    """What the release does with the file's twist mux (see the module docstring)."""
    out = MuxFindings()
    declared = _declared(plain)
    if stack.version < MUX_SINCE:
        if declared is not None:
            out.warnings.append(f"{declared[0]}.controller_manager.ros__parameters.{MUX}: {stack.label()} spawns "
                                f"no twist mux (husarion_ugv 2.3.2+ does): it is not started")
        return out
    if declared is None or not isinstance(declared[1], dict) or not isinstance(declared[1].get("type"), str):
        out.errors.append(f"controller_manager.ros__parameters.{MUX}.type missing: {stack.label()} starts "
                          f"{MUX} together with drive_controller (spawner --activate-as-group): without it no "
                          f"controller starts; write {MUX}: {{type: twist_mux_controller/TwistMuxController}}")
        return out
    found = _params(plain)
    params = found[1] if found and isinstance(found[1], dict) else {}
    where = found[0] if found else f"/**.{MUX}.ros__parameters"
    inputs = params.get("cmd_vel_inputs")
    if not isinstance(inputs, dict) or not inputs:
        out.errors.append(f"{where}.cmd_vel_inputs: missing or empty: the mux would have no velocity input "
                          f"(stock: manual -> manual/cmd_vel, autonomous -> autonomous/cmd_vel, unknown -> cmd_vel)")
        return out
    if "holonomic" in params and not isinstance(params["holonomic"], bool):
        out.errors.append(f"{where}.holonomic={params['holonomic']!r} must be true or false")
    for name, spec in inputs.items():
        out.errors.extend(_input(f"{where}.cmd_vel_inputs.{name}", spec))
    return out


def _input(where: str, spec: Any) -> list[str]:
    if not isinstance(spec, dict):
        return [f"{where} must be a mapping (topic, timeout, priority)"]
    errors: list[str] = []
    try:
        topic_name(spec.get("topic"))
    except RosNameError as exc:
        errors.append(f"{where}.topic={spec.get('topic')!r}: {exc}")
    timeout = spec.get("timeout")
    if not isinstance(timeout, float) or not math.isfinite(timeout) or timeout <= 0:
        errors.append(f"{where}.timeout={timeout!r} must be a number of seconds > 0 written as a double (e.g. 0.2)")
    priority = spec.get("priority")
    if isinstance(priority, bool) or not isinstance(priority, int):
        errors.append(f"{where}.priority={priority!r} must be an integer (higher wins)")
    return errors
