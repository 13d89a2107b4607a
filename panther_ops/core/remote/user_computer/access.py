"""A session on a robot's User Computer, over the robot's connection (the robot as jump host).

Where: the robot's ``user_computer:`` from the inventory, else the manual's default
(``husarion@10.15.20.3``, the address every Panther's User Computer has on the robot's LAN).
Host keys are checked against the inventory's known_hosts files (else ~/.ssh/known_hosts)
and an unknown one is refused. The sudo password is a :class:`Secret` the CLI asked for
once (or read from the environment); it stays in memory for the command only.
"""

from __future__ import annotations

import os

from panther_ops.core.fleet.inventory import UserComputer
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import RemoteStateError
from panther_ops.secret import Secret
from panther_ops.transport.user_computer import ComputerAddress, UserComputerSession

DEFAULT_KNOWN_HOSTS = "~/.ssh/known_hosts"


def address(ctx: RobotContext) -> ComputerAddress:
    """Where the robot's User Computer is and how to log in."""
    uc = ctx.robot.user_computer or UserComputer()
    known = ctx.inventory.known_hosts or (os.path.expanduser(DEFAULT_KNOWN_HOSTS),)
    return ComputerAddress(robot=ctx.robot.name, host=uc.host, port=uc.port, user=uc.user, key_file=uc.key,
                           connect_timeout=ctx.robot.connect_timeout, known_hosts=tuple(known))


def open_session(ctx: RobotContext, sudo_password: Secret | None = None) -> UserComputerSession:
    """A connected session on the robot's User Computer (raises UnreachableError)."""
    client = getattr(ctx.transport, "client", None)
    if client is None:
        raise RemoteStateError("a demo robot has no User Computer behind it")
    session = UserComputerSession(client, address(ctx), sudo_password)
    session.connect()
    return session
