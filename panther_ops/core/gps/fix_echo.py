"""Asking the robot's fix topic: ``ros2 topic echo --once <topic> sensor_msgs/msg/NavSatFix``
in the driver container, bounded by ``timeout``.

With the driver image's ROS 2 CLI, through the shared engine
(:mod:`panther_ops.core.containers.driver_exec`: one command per robot, one round trip, as
the E-stop's commands). Both the driver and the ``nmea-gps`` service run with
``network_mode: host`` on the robot, so the driver's CLI sees the service's node too. The
topic's name and the message's parsing are :mod:`fix_topic`'s.
"""

from __future__ import annotations

import math

from panther_ops.core.containers import driver_exec
from panther_ops.core.containers.exec_output import Answers
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.fix_topic import MSG_TYPE, NavSatFix, parse_fix
from panther_ops.errors import RemoteStateError
from panther_ops.transport.base import Command

START_S = 5
"""Added to the window: the ROS 2 CLI's start and the discovery of the publisher."""

#: In the driver container (after the image's entrypoint sourced ROS): $1 timeout, $2 the
#: namespace ('' = the driver's own), $3 the topic (relative: in that namespace), $4 its type.
CONTAINER_SCRIPT = r"""t=$1 ns=$2 topic=$3
""" + driver_exec.NAMESPACE_SH + r"""case $topic in /*) ;; *) topic="$p/$topic" ;; esac
echo "@@fix"
timeout "$t" ros2 topic echo --once "$topic" "$4" 2>&1
echo "@@exit $?"
"""


def resolve(topic: str, ns: str) -> str:
    """``topic`` as the container resolved it in namespace ``ns`` (``/`` or ``/panther``)."""
    return topic if topic.startswith("/") else f"{ns.rstrip('/')}/{topic}"


def timeout_s(window_s: float) -> int:
    return math.ceil(window_s) + START_S


def command(ns: str, topic: str, timeout: int) -> Command:
    """The one command the robot runs: the fix topic echoed once in the driver container."""
    return driver_exec.command(CONTAINER_SCRIPT, [str(timeout), ns, topic, MSG_TYPE])


def ask(ctx: RobotContext, topic: str, timeout: int) -> Answers:
    """Echo ``topic`` once in the robot's driver container (namespace: the inventory's, else
    the driver's own)."""
    return driver_exec.ask(ctx, command(ctx.robot.namespace or "", topic, timeout), timeout + 30)


def answer(got: Answers, topic: str) -> tuple[str, NavSatFix | None, str]:
    """(the topic as resolved, its fix or None, the echo's last words when it printed no fix)."""
    name = resolve(topic, got.namespace or "/")
    section = got.get("fix")
    if section is None:
        raise RemoteStateError(f"the driver did not echo {name}", hint="panther-ops driver status")
    fix = parse_fix(section.text)
    tail = ""
    if fix is None:
        said = [ln for ln in section.text.strip().splitlines() if ln.strip()]
        tail = said[-1][-200:] if said and section.status != 124 else ""
    return name, fix, tail
