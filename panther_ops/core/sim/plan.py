"""The planner of `sim charge` (the simulation's one planner): charging a simulated Panther,
the LinearBatteryPlugin's recharge services (manual: Charging Process), called the way Husarion's
documentation calls them, through Gazebo Transport's CLI.

Sources: husarion/husarion_ugv_ros@2.1.1:panther_gazebo/CONFIGURATION.md and
@2.2.2:husarion_ugv_gazebo/CONFIGURATION.md (``ign service --service
/model/{robot_model}/battery/battery/recharge/start --reqtype ignition.msgs.Boolean --reptype
ignition.msgs.Empty --req '' --timeout 0``, and ``.../recharge/stop``); the model is spawned
with ``-name <namespace>`` (``*_gazebo/launch/spawn_robot.launch.py``; without a namespace it
takes the robot description's name, the robot model), and the plugin's ``battery_name`` is
``<namespace>/battery`` (``*_description/urdf/*gazebo.urdf.xacro``); gz-sim's
LinearBatteryPlugin serves ``/model/<model>/battery/<battery_name>/recharge/start|stop``.

Pure: the service name and the argv of the call; the call itself is the transport's.
"""

from __future__ import annotations

from dataclasses import dataclass

from panther_ops.core.parse.ros_names import RosNameError, namespace
from panther_ops.errors import UsageError

ACTIONS = ("start", "stop")
MODELS = ("panther", "lynx")
TOOLS = {"ign": ("ign", "ignition.msgs.Boolean", "ignition.msgs.Empty"),
         "gz": ("gz", "gz.msgs.Boolean", "gz.msgs.Empty")}
"""Gazebo Fortress (ROS 2 Humble: ``ign``) and Harmonic (Jazzy: ``gz``), their message names."""


@dataclass(frozen=True)
class ChargeCall:
    """One call of the recharge service."""

    action: str
    service: str
    argv: tuple[str, ...]
    listing: tuple[str, ...]
    """The command that lists the services the simulation serves."""


def recharge_service(action: str, robot_model: str = "panther", ns: str = "") -> str:
    """The service that starts or stops charging. Raises UsageError naming the bad value."""
    if action not in ACTIONS:
        raise UsageError(f"charging action {action!r}: allowed {', '.join(ACTIONS)}")
    if robot_model not in MODELS:
        raise UsageError(f"--robot-model {robot_model!r}: allowed {', '.join(MODELS)}")
    try:
        ns = namespace(ns).strip("/")
    except RosNameError as exc:
        raise UsageError(f"--namespace {ns!r}: {exc}") from None
    model = ns or robot_model
    battery = f"{ns}/battery" if ns else "battery"
    return f"/model/{model}/battery/{battery}/recharge/{action}"


def plan_charge(action: str, robot_model: str = "panther", ns: str = "", tool: str = "ign") -> ChargeCall:
    """The call of ``action`` as Husarion documents it (``--timeout 0``: the plugin answers
    nothing; the request is sent and the call returns)."""
    if tool not in TOOLS:
        raise UsageError(f"--tool {tool!r}: allowed {', '.join(TOOLS)} (ign: ROS 2 Humble's Gazebo; gz: Jazzy's)")
    service = recharge_service(action, robot_model, ns)
    exe, req, rep = TOOLS[tool]
    return ChargeCall(action, service, (exe, "service", "--service", service, "--reqtype", req, "--reptype", rep,
                                        "--req", "", "--timeout", "0"), (exe, "service", "--list"))


def missing_service(call: ChargeCall, listing: str) -> str | None:
    """Why the call would reach nothing (None: the simulation serves it), from ``ign service
    --list``: with ``--timeout 0`` the call itself cannot tell, so a wrong model or namespace
    would pass unnoticed."""
    served = {line.strip() for line in listing.splitlines() if line.strip()}
    if call.service in served:
        return None
    recharge = sorted(s for s in served if s.endswith(f"/recharge/{call.action}"))
    found = f"it serves {', '.join(recharge)}" if recharge else "no recharge service is served (is it running?)"
    return f"the simulation does not serve {call.service}: {found}"
