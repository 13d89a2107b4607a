"""Reading a robot's configuration: one read of compose.yaml (and its user's home) per command.

What was read, parsed, is `robot_config.py`'s (pure; planners import that one).
"""

from __future__ import annotations

import posixpath

from panther_ops.core.fleet.reading import compose_file
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.robot.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.errors import RemoteStateError, TransportError
from panther_ops.transport import scripts
from panther_ops.transport.base import Command


def read_compose(ctx: RobotContext) -> ComposeRead:
    """Read the robot's compose.yaml and its user's home (one round trip): the robot's write
    session made for this plan reads it first (``ctx.session``, one command on the robot for
    the read and the write), else a plain ``run``."""
    path = compose_file(ctx)
    session = ctx.session
    if session is not None and session.reads == path:
        res = session.read()
    else:
        res = ctx.transport.run(Command.sh(scripts.READ_WITH_HOME, path))
    home, _, rest = res.raw_stdout.partition(b"\n")
    if path.startswith("~/"):
        path = posixpath.join(home.decode(), path[2:])
    if res.exit_status == scripts.MISSING_EXIT:
        raise RemoteStateError(f"{path} not found on the robot", hint="set compose_file: in the inventory")
    if not res.ok:
        raise TransportError(ctx.robot.name, f"cannot read {path}: {res.stderr.strip()}")
    return ComposeRead(home.decode(), path, rest)


def read_config(ctx: RobotContext) -> RobotConfig:
    """Read and parse the robot's compose.yaml (one read)."""
    return parse_config(read_compose(ctx), ctx.robot.stack)
