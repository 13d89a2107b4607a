"""Start the robots' TCP connections while panther-ops still loads (``transport.ahead``).

Kept apart from ``runner`` so that starting them imports next to nothing: the command line
calls this before anything else a fleet command needs is loaded.
"""

from __future__ import annotations

from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.errors import OpsError


def connect_ahead(inventory: Inventory, robots: list[Robot]) -> None:
    """Start the robots' TCP connections now, in the background (see ``transport.ahead``):
    their sshd get ready while panther-ops still loads; ``runner.Connections`` takes them."""
    from panther_ops.transport import ahead

    endpoints = []
    for robot in robots:
        if robot.transport == "local":
            continue
        try:
            endpoints.append(inventory.endpoint(robot))
        except OpsError:  # reported when the robot is connected
            continue
    if endpoints:
        ahead.open_ahead(endpoints)
