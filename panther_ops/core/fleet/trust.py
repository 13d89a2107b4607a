"""`panther-ops trust ROBOT` as a change through the pipeline (`cli/mutate.py`).

Its subject is the robot's host key in the operator's known_hosts file, not the robot: the
one target is that file's directory on this machine (the local transport, as a local shutdown
hosts file's), named after the robot, so the runner opens no SSH connection to the robot,
which could not be trusted yet. The planner (`plan_trust.py`, pure) asks for the key the
robot offers: read here through the transport (`fetch_host_key`, no authentication, jump
hosts verified strictly) with the keys the known_hosts files hold for it."""

from __future__ import annotations

import os
from pathlib import Path

from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.plan_trust import HOST_KEY, OfferedKey, plan_trust
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import UsageError


def trust_target(inventory: Inventory, robot: Robot) -> tuple[Inventory, Robot]:
    """The known_hosts file's directory as a one-target inventory named after the robot."""
    if robot.transport == "local":
        raise UsageError(f"{robot.name} is a local (demo) robot: it has no host key")
    from panther_ops.transport.ssh_config import resolve

    file = Path(os.path.expanduser(resolve(inventory.endpoint(robot)).known_hosts[0])).absolute()
    target = Robot(name=robot.name, host="localhost", transport="local", root=Path("/"), home=str(file.parent),
                   source=robot.source)
    return Inventory(path=inventory.path, origin=inventory.origin, robots={robot.name: target}, groups={}, forks=1,
                     subject="host key"), target


def read_offered_key(inventory: Inventory, robot: Robot) -> OfferedKey:
    """The key ``robot`` offers and the (type, fingerprint) of those known for it."""
    from panther_ops.transport.hostkeys import fingerprint, known_hosts_name
    from panther_ops.transport.ssh import fetch_host_key, known_keys

    hop, key = fetch_host_key(inventory.endpoint(robot))
    known = tuple((k.get_name(), fingerprint(k)) for k in known_keys(hop))
    file = str(Path(os.path.expanduser(hop.known_hosts[0])).absolute())
    return OfferedKey(hostname=hop.hostname, port=hop.port, address=known_hosts_name(hop.hostname, hop.port),
                      key_type=key.get_name(), key_base64=key.get_base64(), fingerprint=fingerprint(key),
                      known=known, known_hosts_file=file)


def read_and_plan_trust(ctx: RobotContext, inventory: Inventory, robot: Robot, replace: bool) -> RobotPlan:
    """Plan recording ``robot``'s key (``ctx``: the known_hosts file's target, `trust_target`)."""
    return read_and_plan(ctx, lambda reads: plan_trust(reads, robot.name, replace),
                         {HOST_KEY: lambda _ctx, _key: read_offered_key(inventory, robot)})
